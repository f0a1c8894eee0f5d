"""The trajectory node's commands: `~/stop` (end the run, stand still) and `~/reset` (abort
the run, reset the simulator, answer once the new turtle is connected). std_srvs/srv/Trigger."""

from __future__ import annotations

from rclpy.callback_groups import CallbackGroup
from rclpy.node import Node
from std_srvs.srv import Empty, Trigger

from turtle_traj.core.control.ending import Ending
from turtle_traj.node.async_service import create_async_service
from turtle_traj.node.running import RunningNode
from turtle_traj.node.waiting import wait_until

RESET_TIMEOUT_S = 5.0


class CommandServices:
    """`~/stop` and `~/reset` of `node`, acting on `runs`."""

    def __init__(self, node: Node, runs: RunningNode, group: CallbackGroup) -> None:
        self._node, self._runs = node, runs
        node.create_service(Trigger, '~/stop', self._handle_stop, callback_group=group)
        create_async_service(node, Trigger, '~/reset', self._handle_reset, callback_group=group)
        self.stop_service = node.resolve_service_name('~/stop')
        self._sim_reset = node.create_client(Empty, 'reset', callback_group=group)

    def _handle_stop(self, request: Trigger.Request, response: Trigger.Response):
        response.success, response.message = True, self._runs.stop()
        return response

    async def _handle_reset(self, request: Trigger.Request, response: Trigger.Response):
        node, runs = self._node, self._runs
        runs.abort_run('reset requested', Ending.STOPPED)
        if not self._sim_reset.service_is_ready():
            response.message = (f'the simulator service {self._sim_reset.srv_name} is not '
                                 'available')
            return response
        future = self._sim_reset.call_async(Empty.Request())
        if not await wait_until(node, future.done, RESET_TIMEOUT_S):
            future.cancel()
            response.message = (f'{self._sim_reset.srv_name} did not answer in '
                                f'{RESET_TIMEOUT_S:g} s')
            return response
        # The simulator made a new turtle: forget the old one's pose and wait until the new
        # one's topics are connected, so that a trajectory requested next starts at once.
        runs.forget_turtle()
        if await wait_until(node, self._connected, RESET_TIMEOUT_S):
            response.success, response.message = True, 'simulator reset; ready'
        else:
            response.message = f'simulator reset, but not ready: {runs.refusal()}'
        return response

    def _connected(self) -> bool:
        """A fresh pose is in, the simulator hears the node (it acknowledged a stop) and its
        set_pen is found. Until it heard, another stop is sent for it to acknowledge (one
        sent before the new turtle subscribed reached nobody)."""
        runs = self._runs
        if runs.refusal() is not None or not runs.pen_ready:
            return False
        if runs.commands_heard():
            return True
        runs.send_stop()
        return False

"""The trajectory node's commands: `~/stop` (end the run, stand still) and `~/reset` (abort
the run, reset the simulator, answer once the new turtle is connected). std_srvs/srv/Trigger."""

from __future__ import annotations

from typing import TYPE_CHECKING

from rclpy.callback_groups import CallbackGroup
from std_srvs.srv import Empty, Trigger

from turtle_traj.node.async_service import create_async_service
from turtle_traj.node.waiting import wait_until

if TYPE_CHECKING:
    from turtle_traj.node.trajectory_node import TrajectoryNode

RESET_TIMEOUT_S = 5.0


class CommandServices:
    """`~/stop` and `~/reset` of `node`."""

    def __init__(self, node: TrajectoryNode, group: CallbackGroup) -> None:
        self._node = node
        node.create_service(Trigger, '~/stop', self._handle_stop, callback_group=group)
        create_async_service(node, Trigger, '~/reset', self._handle_reset, callback_group=group)
        self.stop_service = node.resolve_service_name('~/stop')
        self._sim_reset = node.create_client(Empty, 'reset', callback_group=group)

    def _handle_stop(self, request: Trigger.Request, response: Trigger.Response):
        response.success, response.message = True, self._node.stop()
        return response

    async def _handle_reset(self, request: Trigger.Request, response: Trigger.Response):
        node = self._node
        node.abort_run('reset requested')
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
        node.forget_turtle()
        if await wait_until(node, self._connected, RESET_TIMEOUT_S):
            response.success, response.message = True, 'simulator reset; ready'
        else:
            response.message = f'simulator reset, but not ready: {node.refusal()}'
        return response

    def _connected(self) -> bool:
        """A fresh pose is in, the simulator hears the node (it acknowledged a stop) and its
        set_pen is found."""
        node = self._node
        return node.refusal() is None and node.pen_ready and node.commands_heard()

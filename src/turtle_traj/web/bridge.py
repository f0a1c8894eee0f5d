"""The live view's ROS side: frames from the simulator's steps out to the pages, and the
pages' requests in, as a ROS user would make them (cmd_vel, rotate_absolute, the trajectory
node's draw action and parameters).

Requests arrive on the web thread; they are queued, and a timer of this node takes them every
REQUEST_PERIOD_S on the ROS thread (rclpy's EventsExecutor has no guard conditions to wake it
at once).
"""

from __future__ import annotations

import queue
import time
from typing import Any

from geometry_msgs.msg import Twist
from rcl_interfaces.msg import Parameter as ParameterMsg
from rclpy.action import ActionClient
from rclpy.node import Node
from rclpy.parameter import Parameter, parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient
from rclpy.task import Future
from turtlesim.action import RotateAbsolute

from turtle_traj.remote_parameters import typed_value
from turtle_traj.services import DRAW_ACTION, DRAW_ACTION_TYPE, interface, make_goal
from turtle_traj.sim.node import SimNode
from turtle_traj.teleop_keys import ARROWS, CANCEL_KEY, ROTATIONS, velocity
from turtle_traj.trajectories import BY_NAME
from turtle_traj.web import protocol
from turtle_traj.web.server import WebServer
from turtle_traj.wire import TURTLE_TOPIC_QOS

STATUS_PERIOD_S = 1.0
REQUEST_PERIOD_S = 0.02  # a key press waits at most this long
IDLE_FRAME_PERIOD_S = 1.0  # while nothing changes, a frame this often (the page sees it live)
KEY_WAIT_S = 2.0  # for a turtle's cmd_vel or rotate_absolute to connect, at the first press
TRAJECTORY_NODE = 'turtle_traj'  # relative: the node beside the simulator, in its namespace
_START_ONE = 'start one with `python -m turtle_traj` (or run `turtle-traj up --web`)'


class WebBridge(Node):
    """Connects `server`'s pages to `sim` and to the trajectory node next to it."""

    def __init__(self, sim: SimNode, server: WebServer, **kwargs) -> None:
        super().__init__('turtlesim_web', **kwargs)
        self._sim, self._server = sim, server
        self._requests: queue.SimpleQueue[tuple[int, dict[str, Any]]] = queue.SimpleQueue()
        self.create_timer(REQUEST_PERIOD_S, self._handle_requests)
        self._seq = 0
        self._shown: tuple | None = None  # background and poses of the last frame sent
        self._sent_wall_s = 0.0
        self._cmd_vel: dict[str, Any] = {}  # publishers by turtle
        self._rotations: dict[str, ActionClient] = {}
        self._rotation_goal = None  # the last accepted rotate_absolute goal handle
        self._keys: list[tuple[int, str, str, float]] = []  # pressed, not yet sent
        node = self.resolve_service_name(TRAJECTORY_NODE)
        self._node_name = node
        self._draw = ActionClient(self, interface(DRAW_ACTION_TYPE), f'{node}/{DRAW_ACTION}')
        self._parameters = AsyncParameterClient(self, node)
        self._goal = None  # the running draw goal's handle
        self.create_timer(STATUS_PERIOD_S, self._send_status)
        sim.step_listeners.append(self._on_step)

    def destroy_node(self) -> None:
        self._server.stop()
        if self._on_step in self._sim.step_listeners:
            self._sim.step_listeners.remove(self._on_step)
        for action in (self._draw, *self._rotations.values()):  # destroy_node leaves them
            action.destroy()
        super().destroy_node()

    # -- out: a frame per simulator step ------------------------------------------------------

    def _on_step(self) -> None:
        canvas = self._sim.canvas
        if not self._server.page_count:
            canvas.tracking = False  # nobody watches: nothing kept (a new page gets it all)
            return
        cleared, patches = canvas.take_changes()
        snapshot = None
        if self._server.snapshot_wanted:
            self._server.snapshot_wanted = False
            snapshot = canvas.trails.copy()
        shown = (self._sim.background, [(t.name, t.x, t.y, t.theta) for t in self._sim.world])
        now = time.time()
        if (not cleared and not patches and snapshot is None and shown == self._shown
                and now - self._sent_wall_s < IDLE_FRAME_PERIOD_S):
            return  # nothing changed: a standing world costs a frame a second, not 62
        self._shown, self._sent_wall_s = shown, now
        self._seq += 1
        self._server.broadcast(protocol.Frame(self._seq, self._sim.world.time_s, now, *shown,
                                              cleared, patches, snapshot))

    def _send_status(self) -> None:
        if not self._server.page_count:
            return
        ready = self._draw.server_is_ready()
        why = '' if ready else (f'no trajectory node answers on {self._node_name}/'
                                f'{DRAW_ACTION}: {_START_ONE}. Viewing and the keys still work.')
        self._server.send(None, protocol.text('status', node=ready, why=why,
                                              dropped=self._server.frames_dropped))

    # -- in: the pages' requests --------------------------------------------------------------

    def request(self, page: int, request: dict[str, Any]) -> None:
        """Queue a page's request for the ROS thread (called on the web thread)."""
        self._requests.put((page, request))

    def _handle_requests(self) -> None:
        if self._keys:
            self._send_keys()
        while True:
            try:
                page, request = self._requests.get_nowait()
            except queue.Empty:
                return
            handler = getattr(self, f'_on_{request["type"]}')
            try:
                handler(page, request)
            except Exception as error:  # noqa: BLE001 - one bad request must not stop the rest
                self.get_logger().error(f'live view request {request["type"]} failed: {error}')
                self._error(page, f'{request["type"]} failed: {error}')

    def _error(self, page: int, message: str) -> None:
        self._server.send(page, protocol.error_text(message))

    def _on_key(self, page: int, request: dict[str, Any]) -> None:
        turtle, key = request['turtle'], request['key']
        if turtle not in self._sim.world.turtles:
            self._error(page, f'no turtle {turtle!r}; there are: '
                              f'{", ".join(self._sim.world.turtles)}')
            return
        self._keys.append((page, turtle, key, time.monotonic()))
        self._send_keys()

    def _send_keys(self) -> None:
        """Act on the keys pressed, each once its turtle's topic or action is connected (the
        first press for a turtle creates them)."""
        waiting = []
        for page, turtle, key, pressed in self._keys:
            if not self._key_ready(turtle, key):
                if time.monotonic() - pressed < KEY_WAIT_S:
                    waiting.append((page, turtle, key, pressed))
                else:
                    self._error(page, f'{turtle} did not connect within {KEY_WAIT_S:g} s: is '
                                      'it still there?')
            elif key in ARROWS:
                twist = Twist()
                twist.linear.x, twist.angular.z = velocity(key)
                self._cmd_vel[turtle].publish(twist)
            elif key == CANCEL_KEY:
                if self._rotation_goal is not None:
                    self._rotation_goal.cancel_goal_async()
            else:
                self._rotations[turtle].send_goal_async(
                    RotateAbsolute.Goal(theta=ROTATIONS[key])).add_done_callback(
                        self._rotation_accepted)
        self._keys = waiting

    def _key_ready(self, turtle: str, key: str) -> bool:
        if key in ARROWS:
            if turtle not in self._cmd_vel:
                self._cmd_vel[turtle] = self.create_publisher(Twist, f'{turtle}/cmd_vel',
                                                              TURTLE_TOPIC_QOS)
            return self._cmd_vel[turtle].get_subscription_count() > 0
        if key == CANCEL_KEY:
            return True
        if turtle not in self._rotations:
            self._rotations[turtle] = ActionClient(self, RotateAbsolute,
                                                   f'{turtle}/rotate_absolute')
        return self._rotations[turtle].server_is_ready()

    def _rotation_accepted(self, future: Future) -> None:
        handle = future.result()
        if handle.accepted:
            self._rotation_goal = handle

    def _on_goto(self, page: int, request: dict[str, Any]) -> None:
        self._on_start(page, {'trajectory': 'go_to',
                              'fields': {'x': request['x'], 'y': request['y']}})

    def _on_start(self, page: int, request: dict[str, Any]) -> None:
        if not self._draw.server_is_ready():
            self._error(page, f'no trajectory node answers on {self._node_name}: {_START_ONE}')
            return
        kind = BY_NAME[request['trajectory']]
        try:
            goal = make_goal(kind, request['fields'])
        except (TypeError, ValueError, AssertionError) as error:
            self._error(page, f'{kind.name}: {error}')
            return
        run = {'trajectory': kind.name}

        def feedback(message) -> None:
            self._server.send(None, protocol.text(
                'run', state='running', progress=message.feedback.progress,
                deviation=message.feedback.deviation, elapsed=message.feedback.elapsed, **run))

        def answered(future: Future) -> None:
            handle = future.result()
            if not handle.accepted:
                self._server.send(None, protocol.text('run', state='rejected', **run))
                return
            self._goal = handle
            self._server.send(None, protocol.text('run', state='running', progress=0.0, **run))
            handle.get_result_async().add_done_callback(finished)

        def finished(future: Future) -> None:
            result = future.result().result
            figures = {name: getattr(result, name)
                       for name in result.get_fields_and_field_types()}
            self._server.send(None, protocol.text('run', state='ended', result=figures, **run))
        self._draw.send_goal_async(goal, feedback_callback=feedback).add_done_callback(answered)

    def _on_cancel(self, page: int, request: dict[str, Any]) -> None:
        if self._goal is None:
            self._error(page, 'nothing to cancel: no trajectory was started from a page')
            return
        self._goal.cancel_goal_async()

    def _parameters_ready(self, page: int) -> bool:
        if self._parameters.services_are_ready():
            return True
        self._error(page, f'no trajectory node answers parameter requests on '
                          f'{self._node_name}: {_START_ONE}')
        return False

    def _on_get_params(self, page: int, request: dict[str, Any]) -> None:
        if self._parameters_ready(page):
            self.executor.create_task(self._send_parameters(page))

    async def _send_parameters(self, page: int) -> None:
        names = sorted((await self._parameters.list_parameters()).result.names)
        values = (await self._parameters.get_parameters(names)).values
        descriptors = (await self._parameters.describe_parameters(names)).descriptors
        listed = []
        for name, value, descriptor in zip(names, values, descriptors, strict=True):
            ranges = [*descriptor.floating_point_range, *descriptor.integer_range]
            listed.append({
                'name': name, 'value': parameter_value_to_python(value),
                'description': descriptor.description, 'read_only': descriptor.read_only,
                'low': ranges[0].from_value if ranges else None,
                'high': ranges[0].to_value if ranges else None})
        self._server.send(page, protocol.text('params', params=listed))

    def _on_set_param(self, page: int, request: dict[str, Any]) -> None:
        if self._parameters_ready(page):
            self.executor.create_task(self._set_parameter(page, request['name'],
                                                          request['value']))

    async def _set_parameter(self, page: int, name: str, text: str) -> None:
        def answer(ok: bool, message: str) -> None:
            self._server.send(page, protocol.text('param_result', name=name, ok=ok,
                                                  message=message))
        known = (await self._parameters.list_parameters()).result.names
        if name not in known:
            answer(False, f'{self._node_name} has no parameter {name}')
            return
        declared = (await self._parameters.describe_parameters([name])).descriptors[0].type
        try:
            value = typed_value(declared, text)
        except ValueError as error:
            answer(False, f'{name}: {error}')
            return
        parameter = Parameter.from_parameter_msg(ParameterMsg(name=name, value=value))
        result = (await self._parameters.set_parameters([parameter])).results[0]
        answer(result.successful, result.reason or f'{name} set to {text}')

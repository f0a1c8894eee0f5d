"""The live view's trajectory panel: a client of the trajectory node, as a ROS user would be
(its draw action and its parameters), driven by the pages' forms and clicks. A node of its own,
beside the simulator's view on the same page server (`turtle_traj.apps.live_view`).

Requests arrive on the web thread; they are queued, and a timer of this node takes them every
REQUEST_PERIOD_S on the ROS thread (rclpy's EventsExecutor has no guard conditions to wake it
at once).
"""

from __future__ import annotations

from collections.abc import Coroutine
from typing import Any

from rclpy.action import ActionClient
from rclpy.node import Node
from rclpy.parameter import parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient
from rclpy.task import Future

from turtle_traj.api.ros_interface import DRAW_ACTION, DRAW_ACTION_TYPE, make_goal
from turtle_traj.client import panel_messages
from turtle_traj.client.remote_parameters import parameter_from_text
from turtle_traj.core.registry import BY_NAME
from turtle_traj.rosutils.interfaces import interface
from turtle_traj.web.messages import QueuedPart, error_text, text
from turtle_traj.web.server import WebServer

STATUS_PERIOD_S = 1.0
REQUEST_PERIOD_S = 0.02
TRAJECTORY_NODE = 'turtle_traj'  # relative: the node beside the simulator, in its namespace
_START_ONE = 'start one with `python -m turtle_traj` (or run `turtle-traj up --web`)'


class TrajectoryPanel(QueuedPart, Node):
    """Connects `server`'s panel to the trajectory node in this node's namespace."""

    checkers = panel_messages.CHECKERS
    hello_fields = staticmethod(panel_messages.hello)

    def __init__(self, server: WebServer, **kwargs) -> None:
        super().__init__('turtle_traj_web', **kwargs)
        self._server = server
        self.create_timer(REQUEST_PERIOD_S, self._handle_requests)
        node = self.resolve_service_name(TRAJECTORY_NODE)
        self._node_name = node
        self._draw = ActionClient(self, interface(DRAW_ACTION_TYPE), f'{node}/{DRAW_ACTION}')
        self._parameters = AsyncParameterClient(self, node)
        self._goal = None  # the running draw goal's handle
        self.create_timer(STATUS_PERIOD_S, self._send_status)
        server.add(self)

    def destroy_node(self) -> None:
        self._draw.destroy()  # destroy_node leaves action clients
        super().destroy_node()

    def _handle_requests(self) -> None:
        for page, request in self.inbox.take():
            handler = getattr(self, f'_on_{request["type"]}')
            try:
                handler(page, request)
            except Exception as error:  # noqa: BLE001 - one bad request must not stop the rest
                self.get_logger().error(f'live view request {request["type"]} failed: {error}')
                self._error(page, f'{request["type"]} failed: {error}')

    def _error(self, page: int, message: str) -> None:
        self._server.send(page, error_text(message))

    def _send_status(self) -> None:
        if not self._server.page_count:
            return
        ready = self._draw.server_is_ready()
        why = '' if ready else (f'no trajectory node answers on {self._node_name}/'
                                f'{DRAW_ACTION}: {_START_ONE}. Viewing and the keys still work.')
        self._server.send(None, text('status', node=ready, why=why))

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
            self._server.send(None, text(
                'run', state='running', progress=message.feedback.progress,
                deviation=message.feedback.deviation, elapsed=message.feedback.elapsed, **run))

        def answered(future: Future) -> None:
            handle = future.result()
            if not handle.accepted:
                self._server.send(None, text('run', state='rejected', **run))
                return
            self._goal = handle
            self._server.send(None, text('run', state='running', progress=0.0, **run))
            handle.get_result_async().add_done_callback(finished)

        def finished(future: Future) -> None:
            result = future.result().result
            figures = {name: getattr(result, name)
                       for name in result.get_fields_and_field_types()}
            figures['ending'] = result.ending.label  # why it ended, in words
            self._server.send(None, text('run', state='ended', result=figures, **run))
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
            self._run(page, 'get_params', self._send_parameters(page))

    def _run(self, page: int, what: str, work: Coroutine[Any, Any, None]) -> None:
        """Run `work` as a task of the executor; its failure is told to the page and logged,
        never raised out of spin (which would end the program)."""
        async def guarded() -> None:
            try:
                await work
            except Exception as error:  # noqa: BLE001 - the page says why; the view goes on
                self.get_logger().error(f'live view request {what} failed: {error}')
                self._error(page, f'{what} failed: {error}')
        self.executor.create_task(guarded())

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
        self._server.send(page, text('params', params=listed))

    def _on_set_param(self, page: int, request: dict[str, Any]) -> None:
        if self._parameters_ready(page):
            self._run(page, 'set_param',
                      self._set_parameter(page, request['name'], request['value']))

    async def _set_parameter(self, page: int, name: str, value_text: str) -> None:
        def answer(ok: bool, message: str) -> None:
            self._server.send(page, text('param_result', name=name, ok=ok, message=message))
        known = (await self._parameters.list_parameters()).result.names
        if name not in known:
            answer(False, f'{self._node_name} has no parameter {name}')
            return
        declared = (await self._parameters.describe_parameters([name])).descriptors[0].type
        try:
            parameter = parameter_from_text(name, declared, value_text)
        except ValueError as error:
            answer(False, f'{name}: {error}')
            return
        result = (await self._parameters.set_parameters([parameter])).results[0]
        answer(result.successful, result.reason or f'{name} set to {value_text}')

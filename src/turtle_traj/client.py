"""Script-side client of the trajectory node: it owns a private node and spins it itself.

Not for use inside another node's callbacks (it spins); that is what async clients are for.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable

import rclpy
from rcl_interfaces.msg import Parameter as ParameterMsg
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter, get_parameter_value, parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient
from rclpy.wait_for_message import wait_for_message
from turtlesim.msg import Pose

from turtle_traj.geometry.path import Pose2D
from turtle_traj.planning import PlanError
from turtle_traj.services import SERVICE_TYPES
from turtle_traj.settings import settings_from_values
from turtle_traj.trajectories import BY_SERVICE


class TrajClientError(RuntimeError):
    """The call could not be made or did not finish; the message says why."""


class TrajClient:
    """Calls the services of one trajectory node (default `/turtle_traj`)."""

    def __init__(self, *, node: str = '/turtle_traj', connect_timeout_s: float = 3.0) -> None:
        self.node_name = node if node.startswith('/') else f'/{node}'
        self.connect_timeout_s = connect_timeout_s
        self._context = Context()
        rclpy.init(context=self._context)
        self._node = rclpy.create_node(f'turtle_traj_cli_{os.getpid()}', context=self._context)
        self._executor = SingleThreadedExecutor(context=self._context)
        self._executor.add_node(self._node)

    def __enter__(self) -> TrajClient:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def call(self, service: str, request=None, *, timeout_s: float = 300.0,
             on_progress: Callable[[float], None] | None = None):
        """Call `<node>/<service>` and return its response.

        :param on_progress: called about twice a second with the seconds waited so far.
        :raises TrajClientError: when no node answers or the call outlives `timeout_s`.
        """
        try:
            service_type = SERVICE_TYPES[service]
        except KeyError:
            raise TrajClientError(f'unknown service {service!r}; known: '
                                  f'{", ".join(SERVICE_TYPES)}') from None
        name = f'{self.node_name}/{service}'
        client = self._node.create_client(service_type, name)
        try:
            if not client.wait_for_service(timeout_sec=self.connect_timeout_s):
                raise TrajClientError(
                    f'no trajectory node answers on {name} (waited '
                    f'{self.connect_timeout_s:g} s): start one with `python -m turtle_traj '
                    '--with-sim` (or `turtle-traj up`), and check ROS_DOMAIN_ID')
            future = client.call_async(request if request is not None
                                       else service_type.Request())
            start = last_report = time.monotonic()
            while not future.done():
                self._executor.spin_once(timeout_sec=0.1)
                now = time.monotonic()
                if now - start > timeout_s:
                    raise TrajClientError(f'{name} did not answer within {timeout_s:g} s')
                if on_progress is not None and now - last_report >= 0.5:
                    on_progress(now - start)
                    last_report = now
            return future.result()
        finally:
            self._node.destroy_client(client)

    def _wait(self, future, what: str, timeout_s: float = 5.0):
        deadline = time.monotonic() + timeout_s
        while not future.done():
            if time.monotonic() > deadline:
                raise TrajClientError(f'{what} did not answer within {timeout_s:g} s')
            self._executor.spin_once(timeout_sec=0.1)
        return future.result()

    def _parameter_client(self) -> AsyncParameterClient:
        parameters = AsyncParameterClient(self._node, self.node_name)
        if not parameters.wait_for_services(timeout_sec=self.connect_timeout_s):
            raise TrajClientError(f'no node {self.node_name} answers parameter requests')
        return parameters

    def parameters(self) -> dict[str, object]:
        """Every parameter of the node with its current value, sorted by name."""
        client = self._parameter_client()
        names = sorted(self._wait(client.list_parameters(), 'list_parameters').result.names)
        values = self._wait(client.get_parameters(names), 'get_parameters').values
        return {name: parameter_value_to_python(value)
                for name, value in zip(names, values, strict=True)}

    def set_parameter(self, name: str, value: str) -> str | None:
        """Set a parameter from its YAML text, as `ros2 param set` does; the refusal or None."""
        parameter = Parameter.from_parameter_msg(ParameterMsg(
            name=name, value=get_parameter_value(value)))
        result = self._wait(self._parameter_client().set_parameters([parameter]),
                            'set_parameters').results[0]
        return None if result.successful else result.reason

    def turtle_pose(self, values: dict[str, object] | None = None) -> Pose2D | None:
        """The driven turtle's pose (None if none arrives within a second).

        :param values: the node's parameters, if already fetched (for its turtle_name).
        """
        values = values if values is not None else self.parameters()
        namespace = self.node_name.rsplit('/', 1)[0]
        found, pose = wait_for_message(Pose, self._node,
                                       f'{namespace}/{values["turtle_name"]}/pose',
                                       time_to_wait=1.0)
        return Pose2D(pose.x, pose.y, pose.theta) if found else None

    def expected_duration(self, service: str, request) -> float | None:
        """Lower bound of a trajectory call's duration (node clock), planned as the node will.

        None when it cannot be known here (no pose, or a request the node will refuse).
        """
        try:
            values = self.parameters()
            pose = self.turtle_pose(values)
            if pose is None:
                return None
            settings = settings_from_values(values)
            plan = BY_SERVICE[service].plan(request, pose, settings)
        except (TrajClientError, PlanError, KeyError):
            return None
        return plan.lower_bound_s(settings)

    def close(self) -> None:
        self._executor.shutdown()
        self._node.destroy_node()
        rclpy.try_shutdown(context=self._context)


def report(response) -> str:
    """Human-readable result of a trajectory call."""
    lines = [('done: ' if response.success else 'failed: ') + response.message]
    if hasattr(response, 'final_x'):
        lines.append(f'  final pose  x={response.final_x:.3f} m  y={response.final_y:.3f} m  '
                     f'theta={math.degrees(response.final_theta):.1f} deg')
        lines.append(f'  elapsed {response.elapsed:.2f} s, path {response.path_length:.2f} m, '
                     f'max deviation {response.max_deviation:.4f} m, final error '
                     f'{response.final_error:.4f} m')
    return '\n'.join(lines)

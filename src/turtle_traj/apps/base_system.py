"""The physics base and the trajectory node in one process, on lock-step simulated time, and
the node's parameters for a base: what `turtle-traj up --base`, the tests and the benchmark run.
"""

from __future__ import annotations

from pathlib import Path

from rclpy.context import Context
from rclpy.node import Node
from rclpy.parameter import Parameter

from turtle_traj.apps.in_process import LockstepSim
from turtle_traj.base.drive import DriveLimits
from turtle_traj.base.node import BaseNode


def node_parameters_for(limits: DriveLimits, cmd_vel_type: str = 'TwistStamped'
                        ) -> dict[str, object]:
    """The trajectory node's parameters for a base with these limits: its odometry and
    cmd_vel, open space, no pen, top speeds and accelerations the base's own."""
    return dict(pose_source='odometry', odom_topic='odom', cmd_vel_topic='cmd_vel',
                cmd_vel_type=cmd_vel_type, arena='none', pen='none',
                linear_speed=limits.max_linear_speed, angular_speed=limits.max_angular_speed,
                max_linear_accel=limits.max_linear_accel,
                max_angular_accel=limits.max_angular_accel)


def base_node_parameters(base: BaseNode) -> dict[str, object]:
    """`node_parameters_for` a running base node."""
    return node_parameters_for(base.limiter.limits,
                               base.get_parameter('cmd_vel_type').value)


class BaseSystem(LockstepSim):
    """The physics base (`sim`), a TrajectoryNode set up for it (`node`), and, for each call,
    the odometry (`odometry`) and the ground truth (`truth`) after every step, as (time, x, y,
    yaw): what the base publishes on odom and ground_truth, taken in the process (a subscriber
    would cost lock-step a fifth of its speed).

    :param base_parameters: the base's parameter overrides.
    :param node_parameters: the trajectory node's, over `base_node_parameters`.
    """

    sim: BaseNode

    def __init__(self, *, context: Context | None = None, output_dir: Path = Path('output'),
                 base_parameters: dict[str, object] | None = None,
                 **node_parameters: object) -> None:
        super().__init__(context=context, output_dir=output_dir, sim_parameters=base_parameters)
        with self._closed_on_error():
            self._add_trajectory_node(context, {**base_node_parameters(self.sim),
                                                **node_parameters})
            self.odometry: list[tuple[float, float, float, float]] = []
            self.truth: list[tuple[float, float, float, float]] = []
            self.sim.step_listeners.append(self._record)
            self._wait_until_up(lambda: bool(self.truth))

    def _record(self) -> None:
        base = self.sim
        self.odometry.append((base.time_s, base.odometry.x, base.odometry.y, base.odometry.yaw))
        self.truth.append((base.time_s, *base.physics.pose()))

    def _create_simulator(self, context: Context | None, overrides: list[Parameter]) -> Node:
        return BaseNode(context=context, lockstep=True, parameter_overrides=overrides)

    def start(self, service_type, name: str, request=None):
        """Send a request; one to the trajectory node (a relative name) empties `odometry` and
        `truth` first, so that they then hold exactly the messages of that call."""
        if not name.startswith('/'):
            self.odometry.clear()
            self.truth.clear()
        return super().start(service_type, name, request)

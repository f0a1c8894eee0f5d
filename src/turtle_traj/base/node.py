"""BaseNode: the ROS face of the physics base, with the topics of a ROS 2 mobile base.

In: `cmd_vel` (geometry_msgs/TwistStamped, or Twist by parameter). Out: `odom`
(nav_msgs/Odometry from the wheel encoders, frame odom, child base_link: it drifts, as a real
base's does) and `ground_truth` (nav_msgs/Odometry of the true pose, frame world: for
measuring, never for control). The base starts at the world's origin, facing +x, where its
odometry starts too.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock as ClockMsg

from turtle_traj.base.drive import DriveLimits, VelocityLimiter, wheel_speeds
from turtle_traj.base.odometry import WheelOdometry
from turtle_traj.base.parameters import LIMITS, declare_parameters
from turtle_traj.base.physics import DiffDrivePhysics
from turtle_traj.rosutils.delay import CommandDelay
from turtle_traj.rosutils.lockstep import clock_message
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS

ODOM_FRAME, WORLD_FRAME, BASE_FRAME = 'odom', 'world', 'base_link'


def _odometry_message(frame: str) -> Odometry:
    msg = Odometry()
    msg.header.frame_id, msg.child_frame_id = frame, BASE_FRAME
    return msg


def _fill(msg: Odometry, x: float, y: float, yaw: float, linear: float,
          angular: float) -> Odometry:
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.orientation.z = math.sin(0.5 * yaw)
    msg.pose.pose.orientation.w = math.cos(0.5 * yaw)
    msg.twist.twist.linear.x, msg.twist.twist.angular.z = linear, angular
    return msg


class BaseNode(Node):
    """A simulated differential-drive base (node name `base` by default).

    It steps itself on a (scaled) wall-clock timer; with `lockstep` it has no timer, publishes
    /clock, and whoever runs it calls `step()` (see `LockstepExecutor`).

    :raises BaseConfigError: parameters it cannot run with (the node is destroyed).
    :raises MujocoMissing: no MuJoCo (the node is destroyed).
    """

    def __init__(self, node_name: str = 'base', *, lockstep: bool = False, **kwargs) -> None:
        super().__init__(node_name, **kwargs)
        try:
            declared = declare_parameters(self)
            self.physics = DiffDrivePhysics(declared.spec)
        except Exception:  # nothing left half-built for the garbage collector
            self.destroy_node()
            raise
        self.spec, self.period_s = declared.spec, declared.update_period_s
        self.limiter = VelocityLimiter(declared.limits)
        self.cmd_vel_timeout_s = declared.cmd_vel_timeout_s
        self.add_post_set_parameters_callback(self._apply_parameters)
        self.odometry = WheelOdometry(
            wheel_radius=self.spec.wheel_radius, wheel_separation=self.spec.wheel_separation,
            ticks_per_revolution=declared.encoder_resolution)
        self.odometry.update(*self.physics.wheel_angles(), self.period_s)
        self._command = (0.0, 0.0)
        self._command_time_s: float | None = None  # none yet: standing
        self._delay = CommandDelay(declared.command_delay_s, declared.command_jitter_s)
        self.clipped_commands = 0  # steps whose wheel speeds were scaled to the motors' limit
        self.timed_out = 0  # times the wheels were stopped for want of commands
        self.step_listeners: list[Callable[[], None]] = []
        self._own_time = lockstep or declared.publish_clock or declared.time_scale != 1.0

        message = TwistStamped if declared.cmd_vel_type == 'TwistStamped' else Twist
        self.create_subscription(message, 'cmd_vel', self._on_command, TURTLE_TOPIC_QOS)
        self._odom, self._odom_msg = (self.create_publisher(Odometry, 'odom', TURTLE_TOPIC_QOS),
                                      _odometry_message(ODOM_FRAME))
        self._truth, self._truth_msg = (
            self.create_publisher(Odometry, 'ground_truth', TURTLE_TOPIC_QOS),
            _odometry_message(WORLD_FRAME))
        self._clock_publisher = (self.create_publisher(ClockMsg, '/clock', 10)
                       if declared.publish_clock or lockstep else None)
        if not lockstep:
            self.create_timer(self.period_s / declared.time_scale, self.step,
                              clock=Clock(clock_type=ClockType.STEADY_TIME))
        self.get_logger().info(
            f'physics base: wheels r={self.spec.wheel_radius:g} m, {self.spec.wheel_separation:g}'
            f' m apart, {self.spec.mass:g} kg; {message.__name__} on '
            f'{self.resolve_topic_name("cmd_vel")}, serving odometry on {self._odom.topic_name}')

    def _apply_parameters(self, parameters: list[Parameter]) -> None:
        values = {p.name: p.value for p in parameters}
        if values.keys() & LIMITS.keys():
            self.limiter.limits = DriveLimits(**{
                name: self.get_parameter(name).value for name in LIMITS})
        if 'cmd_vel_timeout' in values:
            self.cmd_vel_timeout_s = values['cmd_vel_timeout']

    @property
    def time_s(self) -> float:
        """Simulated time [s]."""
        return self.physics.time_s

    def _on_command(self, msg: TwistStamped | Twist) -> None:
        twist = msg.twist if isinstance(msg, TwistStamped) else msg
        command = (twist.linear.x, twist.angular.z)
        if not all(map(math.isfinite, command)):
            self.get_logger().error(f'ignoring a non-finite cmd_vel {command}',
                                    throttle_duration_sec=1.0)
            return
        if self._delay.active:
            self._delay.push(self.time_s, 'base', command)
        else:
            self._command, self._command_time_s = command, self.time_s

    def _wanted(self) -> tuple[float, float]:
        """The command to head for: the latest, or a stop once it is older than the timeout."""
        if self._command_time_s is None:
            return 0.0, 0.0
        if self.time_s - self._command_time_s > self.cmd_vel_timeout_s + 1e-9:
            if self._command != (0.0, 0.0):  # a stop that times out changes nothing
                self.get_logger().warning(
                    f'no cmd_vel for {self.cmd_vel_timeout_s:g} s: stopping the wheels')
                self.timed_out += 1
            self._command, self._command_time_s = (0.0, 0.0), None
            return 0.0, 0.0
        return self._command

    def step(self) -> None:
        """One period of the base: command through the limits to the wheels, the physics,
        then the odometry and the ground truth published."""
        for _base, command in self._delay.due(self.time_s):  # a delayed command arrives
            self._command, self._command_time_s = command, self.time_s
        linear, angular = self.limiter.limit(*self._wanted(), self.period_s)
        left, right, clipped = wheel_speeds(
            linear, angular, wheel_radius=self.spec.wheel_radius,
            wheel_separation=self.spec.wheel_separation,
            max_wheel_speed=self.spec.max_wheel_speed)
        self.clipped_commands += clipped
        self.physics.drive(left, right)
        self.physics.advance(self.period_s)
        odometry = self.odometry
        odometry.update(*self.physics.wheel_angles(), self.period_s)
        stamp = (self.clock_message().clock if self._own_time
                 else self.get_clock().now().to_msg())
        if self._odom.get_subscription_count():
            msg = _fill(self._odom_msg, odometry.x, odometry.y, odometry.yaw, odometry.linear,
                        odometry.angular)
            msg.header.stamp = stamp
            self._odom.publish(msg)
        if self._truth.get_subscription_count():
            msg = _fill(self._truth_msg, *self.physics.pose(), *self.physics.twist())
            msg.header.stamp = stamp
            self._truth.publish(msg)
        if self._clock_publisher is not None and self._clock_publisher.get_subscription_count():
            self._clock_publisher.publish(self.clock_message())
        for listener in self.step_listeners:
            listener()

    def clock_message(self) -> ClockMsg:
        """The simulated time now, as /clock carries it."""
        return clock_message(self.time_s)

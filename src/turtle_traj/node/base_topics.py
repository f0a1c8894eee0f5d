"""The topics of the base the node drives: its pose in, its velocity commands out.

turtlesim's by default (`turtlesim/Pose`, `geometry_msgs/Twist`); for any ROS 2 mobile base,
`nav_msgs/Odometry` on a topic you name and `geometry_msgs/TwistStamped` (what
diff_drive_controller takes on Jazzy). Relative names follow the node's namespace.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable

from geometry_msgs.msg import Twist, TwistStamped
from rclpy.duration import Duration
from rclpy.exceptions import InvalidHandle
from rclpy.node import Node
from turtlesim.msg import Pose

from turtle_traj.core.control.commands import COMMAND_LIFESPAN_S, Command
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.turtlesim_contract import turtle_topic
from turtle_traj.rosutils.qos import POSE_READER_QOS, TURTLE_TOPIC_QOS

# What the commands are published with: turtlesim's profile, and a lifespan. A reliable writer
# keeps its last 7 commands until the simulator has them; after a cut link they would all arrive
# when it returns, and drive the turtle on commands seconds old. A command older than the
# lifespan is dropped from the writer's history (lifespan acts on the writer's side: no clocks
# across hosts are compared).
COMMAND_QOS = copy.copy(TURTLE_TOPIC_QOS)
COMMAND_QOS.lifespan = Duration(seconds=COMMAND_LIFESPAN_S)

PoseCallback = Callable[[Pose2D, float, float], None]  # pose, |linear| and angular velocity


def yaw_of(q) -> float:
    """The heading (rotation about z) of a quaternion."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class BaseTopics:
    """Subscribes to the pose the parameters name and publishes commands as they say."""

    def __init__(self, node: Node, turtle: str, on_pose: PoseCallback) -> None:
        def value(name: str) -> str:
            return node.get_parameter(name).value
        self._on_pose = on_pose
        self.odometry = value('pose_source') == 'odometry'
        if self.odometry:
            from nav_msgs.msg import Odometry
            topic, message, reader = value('odom_topic'), Odometry, self._on_odometry
        else:
            topic, message, reader = turtle_topic(turtle, 'pose'), Pose, self._on_turtlesim_pose
        self._reader = reader
        self.frame_id = ''  # of the odometry read (turtlesim's pose names none)
        self.on_arrival: Callable[[], None] = lambda: None  # as the executor delivers a pose
        self._poses = node.create_subscription(message, topic, self._delivered, POSE_READER_QOS)
        self.pose_topic = node.resolve_topic_name(topic)
        self.stamped = value('cmd_vel_type') == 'TwistStamped'
        self._clock = node.get_clock()
        command_topic = value('cmd_vel_topic') or turtle_topic(turtle, 'cmd_vel')
        if self.stamped:
            self._message = TwistStamped()
            self._message.header.frame_id = value('cmd_vel_frame_id')
            self._twist = self._message.twist
        else:
            self._message = self._twist = Twist()
        self.publisher = node.create_publisher(type(self._message), command_topic,
                                               COMMAND_QOS)

    def _delivered(self, msg) -> None:
        self.on_arrival()
        self._reader(msg)

    def _on_turtlesim_pose(self, msg: Pose) -> None:
        self._on_pose(Pose2D(msg.x, msg.y, msg.theta), msg.linear_velocity,
                      msg.angular_velocity)

    def _on_odometry(self, msg) -> None:
        position, twist = msg.pose.pose.position, msg.twist.twist
        self.frame_id = msg.header.frame_id
        self._on_pose(Pose2D(position.x, position.y, yaw_of(msg.pose.pose.orientation)),
                      abs(twist.linear.x), twist.angular.z)

    def read_waiting(self) -> None:
        """Read every pose that has arrived and not been read yet, in order, now.

        An executor takes one message from a subscription at a time, between its other
        callbacks: a starved one (rclpy 7.1.6's MultiThreadedExecutor while a handler awaits,
        ros2/rclpy#1452) dispatched fewer than turtlesim's 62.5 poses a second, and the node,
        reading its 2 s queue one pose a dispatch, steered from poses 0.3-0.7 s old. The control
        timer calls this first: each command is steered from the newest pose there is.
        """
        poses = self._poses
        while True:
            try:
                with poses.handle:
                    taken = poses.handle.take_message(poses.msg_type, poses.raw)
            except InvalidHandle:  # destroyed with the node
                return
            if taken is None:
                return
            self._reader(taken[0])

    def publish(self, command: Command) -> None:
        """Publish a command (the message is refilled: publish() serializes at once)."""
        if self.stamped:
            self._message.header.stamp = self._clock.now().to_msg()
        self._twist.linear.x, self._twist.angular.z = command.linear, command.angular
        self.publisher.publish(self._message)

"""Our simulator seen as a ROS 2 mobile base: Odometry out, TwistStamped in.

A relay beside the simulator, for testing a controller against the topics of a real base
(diff_drive_controller on Jazzy): each turtlesim pose of `<turtle_name>/pose` goes out as
`nav_msgs/Odometry` on `odom` (frame `odom`, child `base_link`, with the velocities in effect),
and each `geometry_msgs/TwistStamped` on `cmd_vel` comes in as turtlesim's Twist.
"""

from __future__ import annotations

import math

from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry
from rclpy.node import Node
from turtlesim.msg import Pose

from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS


class BaseAdapter(Node):
    """Relays one turtle's pose as Odometry and TwistStamped commands as Twist."""

    def __init__(self, node_name: str = 'turtlesim_base', **kwargs) -> None:
        super().__init__(node_name, **kwargs)
        turtle = self.declare_parameter('turtle_name', 'turtle1').value
        self._odom = Odometry()
        self._odom.header.frame_id = 'odom'
        self._odom.child_frame_id = 'base_link'
        self._odometry = self.create_publisher(Odometry, 'odom', TURTLE_TOPIC_QOS)
        self._twist = self.create_publisher(Twist, f'{turtle}/cmd_vel', TURTLE_TOPIC_QOS)
        self.create_subscription(Pose, f'{turtle}/pose', self._on_pose, TURTLE_TOPIC_QOS)
        self.create_subscription(TwistStamped, 'cmd_vel', self._on_command, TURTLE_TOPIC_QOS)

    def _on_pose(self, msg: Pose) -> None:
        odom = self._odom
        odom.header.stamp = self.get_clock().now().to_msg()
        odom.pose.pose.position.x, odom.pose.pose.position.y = msg.x, msg.y
        odom.pose.pose.orientation.z = math.sin(0.5 * msg.theta)
        odom.pose.pose.orientation.w = math.cos(0.5 * msg.theta)
        odom.twist.twist.linear.x = msg.linear_velocity
        odom.twist.twist.angular.z = msg.angular_velocity
        self._odometry.publish(odom)

    def _on_command(self, msg: TwistStamped) -> None:
        self._twist.publish(msg.twist)

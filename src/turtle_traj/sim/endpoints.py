"""Everything one simulated turtle has on the ROS graph, with turtlesim's names and QoS."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

from geometry_msgs.msg import Twist
from rclpy.action import ActionServer
from rclpy.callback_groups import CallbackGroup
from rclpy.node import Node
from rclpy.publisher import Publisher
from turtlesim.action import RotateAbsolute
from turtlesim.msg import Color, Pose
from turtlesim.srv import SetPen, TeleportAbsolute, TeleportRelative

from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.sim.rotation_goals import RotationGoals


class TurtleEndpoints:
    """A turtle's topics, services and action, created and destroyed together."""

    def __init__(self, node: Node, name: str, *, on_cmd_vel: Callable[[str, Twist], None],
                 set_pen: Callable, teleport: Callable, rotations: RotationGoals,
                 group: CallbackGroup) -> None:
        """:param set_pen, teleport: service handlers taking (name, request, response)."""
        self.pose = node.create_publisher(Pose, f'{name}/pose', TURTLE_TOPIC_QOS)
        self.color = node.create_publisher(Color, f'{name}/color_sensor', TURTLE_TOPIC_QOS)
        # One message each, refilled every step: publish() serializes at once (no allocation
        # per step).
        self.pose_msg, self.color_msg = Pose(), Color()
        self.cmd_vel = node.create_subscription(
            Twist, f'{name}/cmd_vel', lambda msg: on_cmd_vel(name, msg), TURTLE_TOPIC_QOS)
        self.services = [
            node.create_service(SetPen, f'{name}/set_pen', partial(set_pen, name)),
            node.create_service(TeleportAbsolute, f'{name}/teleport_absolute',
                                partial(teleport, name)),
            node.create_service(TeleportRelative, f'{name}/teleport_relative',
                                partial(teleport, name)),
        ]
        self.action = ActionServer(
            node, RotateAbsolute, f'{name}/rotate_absolute',
            # partial, not lambda: rclpy must see that the execute callback is a coroutine.
            execute_callback=partial(rotations.execute, name),
            cancel_callback=partial(rotations.accept_cancel, name),
            callback_group=group)

    @staticmethod
    def listened(publisher: Publisher) -> bool:
        """Whether anyone subscribes: a pose or colour nobody reads is not worth serialising
        (turtlesim publishes them regardless; with volatile topics no subscriber can tell)."""
        return publisher.get_subscription_count() > 0

    def destroy(self, node: Node) -> None:
        self.action.destroy()
        node.destroy_publisher(self.pose)
        node.destroy_publisher(self.color)
        node.destroy_subscription(self.cmd_vel)
        for service in self.services:
            node.destroy_service(service)


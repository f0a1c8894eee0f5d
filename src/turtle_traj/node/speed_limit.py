"""Nav2's speed limits (nav2_msgs/msg/SpeedLimit, from its speed filter) applied to a trajectory
node: each message sets the node's `linear_speed` to the limit, a percentage of the top speed
the server was configured with or metres per second, and 0 lifts it. The control timer reads
the new setting from its next period on, for the run under way too (the follower caps its
speed, and brakes within the base's limits)."""

from __future__ import annotations

import math

from nav2_msgs.msg import SpeedLimit
from rclpy.node import Node
from rclpy.parameter import Parameter

from turtle_traj.core.parameters.table import PARAMETER


def limited_speed(message: SpeedLimit, top_speed: float) -> float | None:
    """The top speed `message` allows (`top_speed` for no limit); None for a message that
    means nothing (not finite, negative, a percentage over 100)."""
    value = message.speed_limit
    if not math.isfinite(value) or value < 0.0 or (message.percentage and value > 100.0):
        return None
    if value == 0.0:
        return top_speed
    allowed = top_speed * value / 100.0 if message.percentage else value
    return min(top_speed, max(allowed, PARAMETER['linear_speed'].low))


class SpeedLimits:
    """Subscribes `node` to `topic`; each limit sets `follower`'s linear_speed."""

    def __init__(self, node: Node, topic: str, follower: Node) -> None:
        self._node, self._follower = node, follower
        self.top_speed = follower.get_parameter('linear_speed').value
        self._subscription = node.create_subscription(SpeedLimit, topic, self._on_limit, 10)

    def _on_limit(self, message: SpeedLimit) -> None:
        speed = limited_speed(message, self.top_speed)
        if speed is None:
            self._node.get_logger().warning(
                f'speed limit {message.speed_limit}{" %" if message.percentage else " m/s"} '
                'means nothing: ignored')
            return
        self._follower.set_parameters([Parameter('linear_speed', value=speed)])

    def destroy(self) -> None:
        """Unsubscribe, and leave the follower at its top speed."""
        self._node.destroy_subscription(self._subscription)
        self._follower.set_parameters([Parameter('linear_speed', value=self.top_speed)])

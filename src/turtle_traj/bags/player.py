"""Playing a bag back, as `ros2 bag play` does: each message published at its recorded time
(scaled by a rate), with the QoS its publishers offered when it was recorded."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosbags.rosbag2.metadata import QosDurability, QosReliability

from turtle_traj.bags.reader import Bag, Message
from turtle_traj.bags.writer import BagError
from turtle_traj.rosutils.interfaces import message_type

COMMAND_TYPES = {'geometry_msgs/msg/Twist'}  # played by default: what drives a turtle


def command_topics(bag: Bag) -> list[str]:
    return sorted(topic for topic, kind in bag.topics.items() if kind in COMMAND_TYPES)


def _qos(bag: Bag, topic: str) -> QoSProfile:
    offered = bag.offered_qos(topic)
    reliable = not offered or all(q.reliability != QosReliability.BEST_EFFORT for q in offered)
    latched = offered and all(q.durability == QosDurability.TRANSIENT_LOCAL for q in offered)
    return QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE if reliable else
                      ReliabilityPolicy.BEST_EFFORT,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else
                      DurabilityPolicy.VOLATILE)


class Player:
    """Publishes `topics` of `bag` from `node`."""

    def __init__(self, node: Node, bag: Bag, topics: Sequence[str] | None = None) -> None:
        """:raises BagError: a topic the bag does not have, or nothing to play."""
        self.bag = bag
        self.topics = list(topics) if topics else command_topics(bag)
        if not self.topics:
            raise BagError(f'{bag.path} has no command topic (geometry_msgs/msg/Twist) to play; '
                           f'name topics with --topics: it has {", ".join(sorted(bag.topics))}')
        unknown = sorted(set(self.topics) - set(bag.topics))
        if unknown:
            raise BagError(f'{bag.path} has no topic {", ".join(unknown)}; it has: '
                           f'{", ".join(sorted(bag.topics))}')
        self.latest_s = 0.0
        self.publishers = {topic: node.create_publisher(message_type(bag.topics[topic]), topic,
                                                        _qos(bag, topic))
                           for topic in self.topics}

    def connected(self) -> bool:
        """Every topic played has a subscriber."""
        return all(p.get_subscription_count() > 0 for p in self.publishers.values())

    def publish(self, message: Message) -> None:
        self.publishers[message.topic].publish(message.raw)

    def play(self, rate: float = 1.0, *, wait: Callable[[float], None] = time.sleep) -> int:
        """Publish every message at its recorded time divided by `rate`, from now; how many.
        `latest_s` is then the longest any message was sent after its time (a stalled
        publish() delays the ones after it: open loop, the command before acts that longer).

        :param wait: waits so many seconds (the caller's spin, or a sleep).
        """
        count, start, first = 0, time.monotonic(), None
        self.latest_s = 0.0
        for message in self.bag.messages(self.topics):
            first = message.time_ns if first is None else first
            due = start + (message.time_ns - first) * 1e-9 / rate
            while (remaining := due - time.monotonic()) > 0:
                wait(min(remaining, 0.05))
            self.latest_s = max(self.latest_s, time.monotonic() - due)
            self.publish(message)
            count += 1
        return count

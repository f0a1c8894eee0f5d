"""Runs held by a client that may die: the node's `~/lease`.

A client in another program that drives the node one request after another (the fleet
coordinator) holds its lease:
a publisher on `~/lease` with AUTOMATIC liveliness, asserted by its DDS participant, not by its
Python code, every fraction of `LEASE_S` (and once by a message, as it takes hold: a writer
never heard from is never seen to lapse). When a holder goes (its process died or hung for the
lease, or it let go), the node ends the run it drives: a turtle then stops within `LEASE_S`,
not when its request would have ended, and well within turtlesim's 1 s command timeout. (A
client in the node's own program holds none: it dies with the node, and DDS asserts no
liveliness to a reader of the writer's own participant, so such a hold lapses at once.)
"""

from __future__ import annotations

from collections.abc import Callable

from rclpy.duration import Duration
from rclpy.event_handler import QoSLivelinessChangedInfo, SubscriptionEventCallbacks
from rclpy.node import Node
from rclpy.qos import QoSLivelinessPolicy, QoSProfile
from std_msgs.msg import Empty

LEASE_S = 0.5
LEASE_TOPIC = 'lease'
LEASE_QOS = QoSProfile(depth=1, liveliness=QoSLivelinessPolicy.AUTOMATIC,
                       liveliness_lease_duration=Duration(seconds=LEASE_S))


class LeaseWatch:
    """Calls `on_gone` with why, whenever a holder of `node`'s lease goes."""

    def __init__(self, node: Node, on_gone: Callable[[str], None]) -> None:
        self._on_gone = on_gone
        self.subscription = node.create_subscription(
            Empty, f'~/{LEASE_TOPIC}', lambda _: None, LEASE_QOS,
            event_callbacks=SubscriptionEventCallbacks(liveliness=self._changed))

    def _changed(self, info: QoSLivelinessChangedInfo) -> None:
        if info.not_alive_count_change > 0:
            self._on_gone(f'the client holding its lease went silent for {LEASE_S:g} s '
                          '(its program died or hung)')
        elif info.alive_count_change < 0:
            self._on_gone('the client holding its lease let it go')

"""Recording topics of the ROS graph into a bag, as `ros2 bag record` does: serialized messages
as they arrive, stamped with the recording node's clock, each topic with its type, the QoS its
publishers offer and its type hash."""

from __future__ import annotations

from pathlib import Path

from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosbags.rosbag2.metadata import (
    Qos,
    QosDurability,
    QosHistory,
    QosLiveliness,
    QosReliability,
    QosTime,
)

from turtle_traj.api.ros_interface import DRAW_ACTION
from turtle_traj.bags.types import UnknownType
from turtle_traj.bags.writer import BagError, BagWriter, Topic
from turtle_traj.rosutils.clock_read import now_ns
from turtle_traj.rosutils.interfaces import message_type

HISTORY_DEPTH = 1000  # messages a subscription keeps before the recorder takes them


def default_topics(turtle: str = 'turtle1', node: str = 'turtle_traj') -> list[str]:
    """What a run is: the turtle's topics, the node's plan, the draw action's feedback and
    status, /rosout and /clock (recorded when present)."""
    return [f'{turtle}/pose', f'{turtle}/cmd_vel', f'{turtle}/color_sensor', f'{node}/plan',
            f'{node}/{DRAW_ACTION}/_action/feedback', f'{node}/{DRAW_ACTION}/_action/status',
            '/rosout', '/clock']


def fleet_topics(count: int, coordinator: str = '/fleet') -> list[str]:
    """A fleet's run: every turtle's topics and its node's (`up --turtles N`: turtle1 to
    turtleN, each node in its turtle's namespace), and the coordinator's draw action."""
    topics: list[str] = []
    for number in range(1, count + 1):
        name = f'/turtle{number}'
        topics += [topic for topic in default_topics(name, f'{name}/turtle_traj')
                   if topic not in topics]
    return [*topics, f'{coordinator}/{DRAW_ACTION}/_action/feedback',
            f'{coordinator}/{DRAW_ACTION}/_action/status']


def _bag_qos(profile: QoSProfile) -> Qos:
    def seconds(duration) -> dict:
        sec, nsec = divmod(duration.nanoseconds, 10**9)
        return {'sec': sec, 'nsec': nsec}
    return Qos(history=QosHistory(int(profile.history)), depth=profile.depth,
               reliability=QosReliability(int(profile.reliability)),
               durability=QosDurability(int(profile.durability)),
               deadline=QosTime(**seconds(profile.deadline)),
               lifespan=QosTime(**seconds(profile.lifespan)),
               liveliness=QosLiveliness(int(profile.liveliness)),
               liveliness_lease_duration=QosTime(**seconds(profile.liveliness_lease_duration)),
               avoid_ros_namespace_conventions=profile.avoid_ros_namespace_conventions)


class TopicRecorder:
    """Records `topics` of `node`'s graph while started; the node's executor delivers them."""

    def __init__(self, node: Node, topics: list[str]) -> None:
        self._node = node
        self.topics = [node.resolve_topic_name(topic) for topic in topics]
        self._subscriptions = []
        self.writer: BagWriter | None = None

    def published(self) -> dict[str, Topic]:
        """The topics asked for that have a publisher now, as the bag will keep them."""
        found = {}
        for name in self.topics:
            publishers = self._node.get_publishers_info_by_topic(name)
            if publishers:
                first = publishers[0]
                found[name] = Topic(name, first.topic_type,
                                    tuple(_bag_qos(p.qos_profile) for p in publishers),
                                    str(first.topic_type_hash))
        return found

    def start(self, path: Path, *, required: list[str] | None = None,
              custom_data: dict[str, str] | None = None) -> list[Topic]:
        """Open the bag and subscribe to every topic that has a publisher; those recorded.

        :raises BagError: a required topic has no publisher, or the bag cannot be written.
        """
        topics = self.published()
        missing = [self._node.resolve_topic_name(t) for t in required or []
                   if self._node.resolve_topic_name(t) not in topics]
        if missing:
            raise BagError(f'no publisher on {", ".join(missing)}: nothing to record there '
                           '(is the name right?)')
        try:
            self.writer = BagWriter(path, list(topics.values()), custom_data=custom_data)
        except UnknownType as error:
            raise BagError(str(error)) from None
        for topic in topics.values():
            offered = topic.offered_qos
            reliable = all(q.reliability == QosReliability.RELIABLE for q in offered)
            latched = all(q.durability == QosDurability.TRANSIENT_LOCAL for q in offered)
            qos = QoSProfile(
                depth=HISTORY_DEPTH,
                reliability=ReliabilityPolicy.RELIABLE if reliable else
                ReliabilityPolicy.BEST_EFFORT,
                durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else
                DurabilityPolicy.VOLATILE)
            self._subscriptions.append(self._node.create_subscription(
                message_type(topic.typename), topic.name,
                lambda raw, name=topic.name: self._record(name, raw), qos, raw=True))
        return list(topics.values())

    def _record(self, topic: str, raw: bytes) -> None:
        if self.writer is not None:
            self.writer.write(topic, now_ns(self._node.get_clock()), raw)

    def stop(self) -> dict[str, int]:
        """Unsubscribe and finish the bag; messages per topic (BagError if it cannot be
        finished, or if writing had stopped early: what was written before is kept)."""
        for subscription in self._subscriptions:
            self._node.destroy_subscription(subscription)
        self._subscriptions = []
        writer, self.writer = self.writer, None
        if writer is None:
            return {}
        writer.close()
        if writer.error is not None:
            raise BagError(f'{writer.error}; the {sum(writer.counts.values())} messages '
                           f'before it are kept in {writer.path}')
        return writer.counts

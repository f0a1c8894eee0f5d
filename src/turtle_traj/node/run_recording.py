"""The trajectory node's `record_dir`: each run a rosbag2 bag of the node's own topics."""

from __future__ import annotations

from datetime import datetime
from pathlib import Path

from rclpy.node import Node

from turtle_traj.api.ros_interface import DRAW_ACTION
from turtle_traj.bags.recorder import TopicRecorder
from turtle_traj.bags.types import typestore_for
from turtle_traj.bags.writer import BagError
from turtle_traj.core.control.config import ControlConfig
from turtle_traj.node.base_topics import BaseTopics


class RunRecording:
    """Records the pose and command topics the node drives by (turtlesim's, or a base's odometry
    and TwistStamped), its plan and its draw action from `start` to `stop`, into a bag named
    after the trajectory and the time in `folder`. A failure is logged: runs go on."""

    def __init__(self, node: Node, base: BaseTopics, folder: Path) -> None:
        self._node, self.folder = node, folder
        self._recorder = TopicRecorder(node, [
            base.pose_topic, base.publisher.topic_name, '~/plan',
            f'~/{DRAW_ACTION}/_action/feedback', f'~/{DRAW_ACTION}/_action/status'])
        # rosbags loads its Jazzy types here (0.1 s), not when the first run starts, where it
        # would hold the run's first commands (at five times real time, past pose_timeout)
        typestore_for(())

    def start(self, trajectory: str, control: ControlConfig) -> None:
        path = self.folder / f'{trajectory}_{datetime.now():%Y%m%d-%H%M%S-%f}'
        try:
            self._recorder.start(path, custom_data={
                'trajectory': trajectory, 'linear_speed': str(control.linear_speed),
                'angular_speed': str(control.angular_speed)})
        except BagError as error:
            self._node.get_logger().error(f'{trajectory} is not recorded: {error}')

    def stop(self) -> None:
        writer = self._recorder.writer
        if writer is None:
            return
        try:
            counts = self._recorder.stop()
        except BagError as error:
            self._node.get_logger().error(str(error))
            return
        self._node.get_logger().info(f'recorded {sum(counts.values())} messages into '
                                     f'{writer.path}')

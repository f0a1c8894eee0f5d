"""The turtle's poses as its own host sees them, for measuring a run independently of the node.

    python -m turtle_traj.testing.pose_log OUT    (until SIGTERM or SIGINT)

Run on the simulator's host (no lossy link between the turtle and this log), it writes one
line per pose, `pose <monotonic s> <x> <y> <theta>`, and one per plan the trajectory node
publishes, `plan <monotonic s> <x0> <y0> <x1> <y1> ...`. `PoseLog.read` parses the file:
the deviation of a run is then its poses' distance from its plan, between the run's start and
end (one monotonic clock for every namespace).
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from turtle_traj.testing.geometry import distance_to_polyline

PLAN_TOPIC = '/turtle_traj/plan'
SPIN_CHECK_S = 0.25  # the longest a signal's shutdown waits for the spin to see it


@dataclass
class PoseLog:
    """Poses (t, x, y, theta) and the plans published, each with the monotonic time it arrived."""

    poses: np.ndarray
    plans: list[tuple[float, np.ndarray]] = field(default_factory=list)

    @classmethod
    def read(cls, path: Path) -> PoseLog:
        poses, plans = [], []
        text = path.read_text()
        # complete lines only: read while the log is written, the last may be half written
        for line in text[:text.rfind('\n') + 1].splitlines():
            kind, *values = line.split()
            numbers = [float(value) for value in values]
            if kind == 'pose':
                poses.append(numbers)
            elif kind == 'plan' and len(numbers) >= 3:
                plans.append((numbers[0], np.array(numbers[1:]).reshape(-1, 2)))
        return cls(np.array(poses).reshape(-1, 4), plans)

    def between(self, start_s: float, end_s: float) -> np.ndarray:
        """The poses (x, y) logged from `start_s` to `end_s`."""
        inside = (self.poses[:, 0] >= start_s) & (self.poses[:, 0] <= end_s)
        return self.poses[inside, 1:3]

    def plan_after(self, start_s: float) -> np.ndarray | None:
        """The first plan published after `start_s` (None: none arrived)."""
        return next((points for time_s, points in self.plans if time_s >= start_s), None)

    def deviation_m(self, start_s: float, end_s: float) -> float:
        """A run's maximum deviation: its poses' distance from the plan published after it
        began (nan: no plan or no pose reached the log)."""
        plan, poses = self.plan_after(start_s), self.between(start_s, end_s)
        if plan is None or not len(poses):
            return math.nan
        return float(distance_to_polyline(poses, plan).max())


def main(out: str) -> None:
    import rclpy
    from nav_msgs.msg import Path as PathMsg
    from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
    from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
    from rclpy.qos import DurabilityPolicy, QoSProfile
    from turtlesim.msg import Pose

    from turtle_traj.rosutils.qos import POSE_READER_QOS

    # On SIGTERM rclpy's handler, from a thread of its own, wakes the executors that exist
    # then (it triggers their guard conditions) and the context is found shut down. So the
    # executor comes first (a signal before the spin still wakes it), the log file after it
    # (whoever waits for the file may signal at once), and the spin looks at the context every
    # SPIN_CHECK_S: on a loaded machine a wait begun after the wake had nothing to end it.
    rclpy.init()
    executor = node = None
    try:
        executor = SingleThreadedExecutor()
        node = rclpy.create_node('pose_log')
        executor.add_node(node)
        with open(out, 'w', buffering=1) as log:
            def on_pose(msg: Pose) -> None:
                log.write(f'pose {time.monotonic():.6f} {msg.x:.6f} {msg.y:.6f} '
                          f'{msg.theta:.6f}\n')

            def on_plan(msg: PathMsg) -> None:
                points = ' '.join(f'{p.pose.position.x:.6f} {p.pose.position.y:.6f}'
                                  for p in msg.poses)
                log.write(f'plan {time.monotonic():.6f} {points}\n')

            node.create_subscription(Pose, '/turtle1/pose', on_pose, POSE_READER_QOS)
            node.create_subscription(PathMsg, PLAN_TOPIC, on_plan, QoSProfile(
                depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
            while rclpy.ok():
                executor.spin_once(timeout_sec=SPIN_CHECK_S)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except _rclpy.RCLError:  # e.g. 'rcl node's context is invalid'
        if rclpy.ok():  # not a signal's shutdown while the node was being made
            raise
    finally:
        if executor is not None:
            executor.shutdown()
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    main(sys.argv[1])

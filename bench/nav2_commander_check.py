"""Nav2's own Python client drives the trajectory node: nav2_simple_commander's BasicNavigator
(navigation2, branch jazzy, unchanged) against `turtle-traj up`, at real time.

BasicNavigator imports every nav2_msgs action and service, so it needs Nav2's whole nav2_msgs,
not the FollowPath subset `make setup` builds. Set-up, once (no Nav2 wheel exists):
  1. navigation2 (jazzy) and geographic_info (ros2): their nav2_common, nav2_msgs,
     nav2_simple_commander and geographic_msgs, built with cmake against this venv
     (CMAKE_PREFIX_PATH and AMENT_PREFIX_PATH = PREFIX:.venv) and installed into PREFIX;
  2. AMENT_PREFIX_PATH=PREFIX:.venv, LD_LIBRARY_PATH=PREFIX/lib and
     PYTHONPATH=PREFIX/lib/python3.11/site-packages:<navigation2>/nav2_simple_commander for both
     `turtle-traj up` and this script (the node then serves Nav2's own type; its hash is ours).
Run: .venv/bin/python bench/nav2_commander_check.py  (with `turtle-traj up` running)
 or: .venv/bin/python bench/nav2_commander_check.py --base  (with `turtle-traj up --base`: the
     MuJoCo base, its poses from /odom in the frame odom, the path from where it stands)
With `up --base`, whose process loads MuJoCo first, the dynamic linker found the venv's
FollowPath-only libnav2_msgs__rosidl_generator_py.so for Nav2's type support here: start it
with LD_PRELOAD naming PREFIX/lib's libnav2_msgs__rosidl_generator_c.so,
libnav2_msgs__rosidl_typesupport_c.so and libnav2_msgs__rosidl_generator_py.so (and .venv/lib
at the end of LD_LIBRARY_PATH).

It sends a planner-like path (a quarter circle, a pose every 2 cm), a goal with controller_id
`dwpp`, a goal replaced 1 s in by another, a cancelled goal, three bad goals and one more, and
prints what it measured from the turtle's poses beside what BasicNavigator reports.
"""
import argparse
import math
import time

import numpy as np
import rclpy
from geometry_msgs.msg import PoseStamped
from nav2_simple_commander.robot_navigator import BasicNavigator
from nav_msgs.msg import Odometry, Path
from turtlesim.msg import Pose


def arc(x: float, y: float, radius: float = 1.0, spacing: float = 0.02) -> np.ndarray:
    """A quarter circle turning left from (x, y) heading east: a pose every `spacing` m."""
    angles = np.linspace(0.0, math.pi / 2, round(radius * math.pi / 2 / spacing) + 1)
    return np.stack([x + radius * np.sin(angles), y + radius * (1.0 - np.cos(angles))], axis=1)


def path_of(points: np.ndarray, frame_id: str = 'world') -> Path:
    path = Path()
    path.header.frame_id = frame_id
    for x, y in points:
        stamped = PoseStamped()
        stamped.header.frame_id = frame_id
        stamped.pose.position.x, stamped.pose.position.y = float(x), float(y)
        stamped.pose.orientation.w = 1.0
        path.poses.append(stamped)
    return path


def distances(points: np.ndarray, driven: np.ndarray) -> np.ndarray:
    """Each driven position's distance from the polyline through `points`."""
    starts, along = points[:-1], np.diff(points, axis=0)
    offsets = driven[:, None, :] - starts
    t = np.clip((offsets * along).sum(axis=2) / (along ** 2).sum(axis=1), 0.0, 1.0)
    return np.hypot(*(offsets - t[..., None] * along).transpose(2, 0, 1)).min(axis=1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--base', action='store_true', help='the MuJoCo base (`up --base`)')
    base = parser.parse_args().base
    rclpy.init()
    navigator = BasicNavigator()
    poses: list[tuple[float, float]] = []
    if base:  # the odometry's frame, and the base's first pose
        frame = 'odom'
        navigator.create_subscription(Odometry, '/odom', lambda message: poses.append(
            (message.pose.pose.position.x, message.pose.pose.position.y)), 100)
    else:
        frame = 'world'
        navigator.create_subscription(Pose, '/turtle1/pose',
                                      lambda message: poses.append((message.x, message.y)), 100)
    while not poses:
        rclpy.spin_once(navigator, timeout_sec=0.1)
    start = poses[-1]

    def run(points: np.ndarray, controller_id: str = '', after_1_s=None):
        poses.clear()
        feedback = []
        assert navigator.followPath(path_of(points, frame), controller_id=controller_id)
        began, acted = time.monotonic(), after_1_s is None
        while not navigator.isTaskComplete():
            message = navigator.getFeedback()
            if message is not None:
                feedback.append((message.distance_to_goal, message.speed))
            if not acted and time.monotonic() - began > 1.0:
                acted = True
                after_1_s()
        result = navigator.result_future.result().result
        return navigator.getResult(), result, feedback, np.array(poses)

    points = arc(*start, radius=0.5 if base else 1.0)
    status, result, feedback, driven = run(points)
    left = [distance for distance, _ in feedback]
    print(f'planner path: {status.name}, error_code {result.error_code}; '
          f'{1e3 * distances(points, driven).max():.2f} mm from the path at most, end '
          f'{1e3 * math.dist(driven[-1], points[-1]):.2f} mm off; feedback read {len(feedback)} '
          f'times: {left[0]:.3f} m left at first, {left[-1]:.3f} m at last, never rising: '
          f'{all(b <= a + 1e-3 for a, b in zip(left, left[1:], strict=False))}; top speed '
          f'{max(speed for _, speed in feedback):.2f} m/s')
    x, y = driven[-1]
    ahead = np.array([(x, y), (x, y + 1.0)])
    status, result, _, driven = run(ahead, controller_id='dwpp')
    print(f"controller_id 'dwpp': {status.name}, error_code {result.error_code}; end "
          f'{1e3 * math.dist(driven[-1], ahead[-1]):.1f} mm off')
    x, y = driven[-1]
    replacement = []

    def replace() -> None:
        here = poses[-1]
        replacement.append(np.array([here, (here[0], here[1] - 0.5)]))
        navigator.followPath(path_of(replacement[0], frame))
    status, result, _, driven = run(np.array([(x, y), (x, y - 2.0)]), after_1_s=replace)
    print(f'a goal replaced 1 s in: the replacement {status.name}, error_code '
          f'{result.error_code}; end {1e3 * math.dist(driven[-1], replacement[0][-1]):.1f} mm '
          "off the replacement's end")
    x, y = driven[-1]
    status, _, _, _ = run(np.array([(x, y), (x, y + 2.0)]), after_1_s=navigator.cancelTask)
    print(f'cancelled 1 s in: {status.name}')
    for name, bad, fields in (('an empty path', np.empty((0, 2)), {}),
                              ('a pose not a number', np.array([(1.0, math.nan), (2.0, 2.0)]), {}),
                              ('an unknown controller', np.array([(x, y), (x + 0.3, y)]),
                               {'controller_id': 'nope'})):
        status, result, _, _ = run(bad, **fields)
        print(f'{name}: {status.name}, error_code {result.error_code}: {result.error_msg}')
    here = poses[-1] if poses else (x, y)
    status, _, _, _ = run(np.array([here, (here[0] + 0.3, here[1])]))
    print(f'and the next goal: {status.name}')
    navigator.destroy_node()
    rclpy.shutdown()


if __name__ == '__main__':
    main()

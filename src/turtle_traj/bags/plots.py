"""Plots of a recorded run, with matplotlib: the path over the plan, the deviation over time,
v and omega against their limits, and the draw action's progress.

`Run` is what the plots need, read from a bag; the drawing functions take a matplotlib Axes
each, so the same panels make the separate PNGs of `turtle-traj plot` and the demo's one
picture per trajectory.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import matplotlib

matplotlib.use('Agg')  # files only: no display needed
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from turtle_traj.bags.reader import Bag  # noqa: E402
from turtle_traj.core.geometry.projection import NearestOnPolyline  # noqa: E402
from turtle_traj.core.parameters.table import DEFAULTS  # noqa: E402
from turtle_traj.core.turtlesim_contract import WORLD_SIZE_M  # noqa: E402

PANELS = ('path', 'deviation', 'speeds', 'progress')


@dataclass
class Run:
    """A recorded run, as arrays: times in seconds from its first pose."""

    name: str
    poses: np.ndarray  # (N, 6): t, x, y, theta, v, omega
    plan: np.ndarray = field(default_factory=lambda: np.empty((0, 2)))  # (K, 2)
    progress: np.ndarray = field(default_factory=lambda: np.empty((0, 2)))  # t, progress
    linear_limit: float = DEFAULTS['linear_speed']
    angular_limit: float = DEFAULTS['angular_speed']

    @property
    def deviation(self) -> np.ndarray:
        """(N, 2): t, distance of each pose from the plan (empty without a plan)."""
        if not len(self.plan) or not len(self.poses):
            return np.empty((0, 2))
        distances = NearestOnPolyline(self.plan).distances(self.poses[:, 1:3])
        return np.column_stack((self.poses[:, 0], distances))


def _odometry(value) -> tuple[float, float, float, float, float]:
    """x, y, heading, speed and turn rate of a nav_msgs/Odometry."""
    q, twist = value.pose.pose.orientation, value.twist.twist
    heading = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
    return (value.pose.pose.position.x, value.pose.pose.position.y, heading, twist.linear.x,
            twist.angular.z)


# The poses a run drives by (the node's pose_source): turtlesim's, or a base's odometry.
_POSE_TYPES = {
    'turtlesim/msg/Pose': lambda value: (value.x, value.y, value.theta, value.linear_velocity,
                                         value.angular_velocity),
    'nav_msgs/msg/Odometry': _odometry,
}


def read_run(path: Path) -> Run:
    """The run recorded in the bag at `path`.

    :raises BagError: not a readable bag, or one without poses (turtlesim's or odometry).
    """
    from turtle_traj.bags.writer import BagError
    with Bag(path) as bag:
        pose_topics = [t for t, kind in bag.topics.items() if kind in _POSE_TYPES]
        if not pose_topics:
            raise BagError(f'{path} has no turtlesim/msg/Pose or nav_msgs/msg/Odometry topic: '
                           'nothing to plot')
        wanted = [pose_topics[0]] + [t for t, kind in bag.topics.items() if kind in (
            'nav_msgs/msg/Path', 'turtle_traj_interfaces/action/Draw_FeedbackMessage')]
        poses, plan, progress = [], np.empty((0, 2)), []
        for message in bag.messages(wanted, deserialize=True):
            value = message.value
            if message.topic == pose_topics[0]:
                poses.append((message.time_ns * 1e-9, *_POSE_TYPES[message.typename](value)))
            elif message.typename == 'nav_msgs/msg/Path':
                plan = np.array([(p.pose.position.x, p.pose.position.y) for p in value.poses])
            else:
                progress.append((message.time_ns * 1e-9, value.feedback.progress))
        data = bag.custom_data
    poses_array = np.array(poses).reshape(-1, 6)
    start = poses_array[0, 0] if len(poses_array) else 0.0
    poses_array[:, 0] -= start
    progress_array = np.array(progress).reshape(-1, 2)
    progress_array[:, 0] -= start
    return Run(data.get('trajectory', path.name), poses_array, plan.reshape(-1, 2),
               progress_array, float(data.get('linear_speed', DEFAULTS['linear_speed'])),
               float(data.get('angular_speed', DEFAULTS['angular_speed'])))


def draw_path(axes, run: Run) -> None:
    if len(run.plan):
        axes.plot(run.plan[:, 0], run.plan[:, 1], '--', color='0.6', lw=1, label='plan')
    axes.plot(run.poses[:, 1], run.poses[:, 2], color='tab:blue', lw=1.2, label='driven')
    axes.set(xlim=(0, WORLD_SIZE_M), ylim=(0, WORLD_SIZE_M), aspect='equal', xlabel='x [m]',
             ylabel='y [m]', title=f'{run.name}: path over the plan')
    axes.legend(loc='upper right', fontsize='small')


def draw_deviation(axes, run: Run) -> None:
    deviation = run.deviation
    axes.plot(deviation[:, 0], 1e3 * deviation[:, 1], color='tab:red', lw=1)
    axes.set(xlabel='t [s]', ylabel='deviation [mm]', title='distance from the plan')


def draw_speeds(axes, run: Run) -> None:
    t = run.poses[:, 0]
    axes.plot(t, run.poses[:, 4], color='tab:blue', lw=1, label='v [m/s]')
    axes.plot(t, run.poses[:, 5], color='tab:orange', lw=1, label='ω [rad/s]')
    for limit, color in ((run.linear_limit, 'tab:blue'), (run.angular_limit, 'tab:orange')):
        axes.axhline(limit, color=color, ls=':', lw=1)
        axes.axhline(-limit, color=color, ls=':', lw=1)
    axes.set(xlabel='t [s]', ylabel='speed', title='v and ω against their limits (dotted)')
    axes.legend(loc='upper right', fontsize='small')


def draw_progress(axes, run: Run) -> None:
    axes.plot(run.progress[:, 0], 100 * run.progress[:, 1], color='tab:green', lw=1.2)
    axes.set(xlabel='t [s]', ylabel='progress [%]', ylim=(0, 105),
             title='draw action progress')


DRAWERS = {'path': draw_path, 'deviation': draw_deviation, 'speeds': draw_speeds,
           'progress': draw_progress}


def panels_of(run: Run) -> tuple[str, ...]:
    """The panels `run` has data for: progress only for a run of the draw action."""
    return PANELS if len(run.progress) else PANELS[:-1]


def panel(run: Run, name: str) -> Figure:
    figure = Figure(figsize=(5, 4.5) if name == 'path' else (6, 3.2), dpi=100,
                    layout='constrained')
    DRAWERS[name](figure.add_subplot(), run)
    return figure


def overview(run: Run) -> Figure:
    """The run's panels in one picture: four, or without progress the path down the left."""
    figure = Figure(figsize=(10, 8), dpi=80, layout='constrained')
    names = panels_of(run)
    places = [1, 2, 3, 4] if len(names) == 4 else [(1, 3), 2, 4]
    for name, place in zip(names, places, strict=True):
        DRAWERS[name](figure.add_subplot(2, 2, place), run)
    return figure


def write_overview(run: Run, target: Path) -> Path:
    """The panels of `run` in one PNG (the demo's plot per trajectory)."""
    overview(run).savefig(target)
    return target


def write_plots(bag: Path, folder: Path) -> list[Path]:
    """One PNG per panel for the run in `bag`, into `folder`; the files."""
    run = read_run(bag)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for name in panels_of(run):
        target = folder / f'{name}.png'
        panel(run, name).savefig(target)
        written.append(target)
    return written

"""Nav2's goal checkers, judged on the pose a run ends at. Pure Python.

In Nav2 a goal checker says when the robot has reached a FollowPath goal: within
`xy_goal_tolerance` of the path's last pose and, where that pose has an orientation, within
`yaw_goal_tolerance` of it (`SimpleGoalChecker`); `StoppedGoalChecker` also wants the robot
below `trans_stopped_velocity` and `rot_stopped_velocity`. Here the node drives every run to
the path's end and its last orientation and ends it once the robot is at rest, so a run that
succeeded is then checked: a goal the checker says is not reached fails, saying by how much.
`stateful` (Nav2's: once within xy, only the yaw is checked after) needs no state here: the
check is made once, at the end.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Pose2D

SIMPLE = 'nav2_controller::SimpleGoalChecker'
STOPPED = 'nav2_controller::StoppedGoalChecker'
_DEFAULTS = {'xy_goal_tolerance': 0.25, 'yaw_goal_tolerance': 0.25,
             'trans_stopped_velocity': 0.25, 'rot_stopped_velocity': 0.25}


@dataclass(frozen=True)
class GoalChecker:
    """One of Nav2's goal checkers, with its tolerances."""

    name: str  # its id in the parameter file
    xy_tolerance: float = 0.25  # [m]
    yaw_tolerance: float = 0.25  # [rad]
    # StoppedGoalChecker's: the robot must move slower than these [m/s, rad/s]; None: any
    stopped: tuple[float, float] | None = None

    @classmethod
    def from_values(cls, name: str, plugin: str, values: Mapping[str, object]) -> GoalChecker:
        """The checker of a parameter file's `<name>.plugin` and its keys.

        :raises ValueError: a tolerance that is not a number at least 0.
        """
        numbers = {}
        for key, default in _DEFAULTS.items():
            value = values.get(key, default)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not (
                    math.isfinite(value) and value >= 0.0):
                raise ValueError(f'{name}.{key} must be a number of at least 0, not {value!r}')
            numbers[key] = float(value)
        stopped = ((numbers['trans_stopped_velocity'], numbers['rot_stopped_velocity'])
                   if plugin == STOPPED else None)
        return cls(name, numbers['xy_goal_tolerance'], numbers['yaw_goal_tolerance'], stopped)

    def miss(self, pose: Pose2D, velocity: tuple[float, float], goal: tuple[float, float],
             goal_yaw: float | None) -> str | None:
        """Why the robot at `pose`, moving at `velocity` (m/s, rad/s), has not reached the
        goal; None once it has."""
        distance = math.dist((pose.x, pose.y), goal)
        if distance > self.xy_tolerance:
            return (f'goal checker {self.name}: {distance:.3f} m from the goal, beyond '
                    f'xy_goal_tolerance {self.xy_tolerance:g} m')
        if goal_yaw is not None:
            off = abs(wrap_angle(pose.theta - goal_yaw))
            if off > self.yaw_tolerance:
                return (f'goal checker {self.name}: {off:.3f} rad from the goal\'s heading, '
                        f'beyond yaw_goal_tolerance {self.yaw_tolerance:g} rad')
        if self.stopped is not None and (abs(velocity[0]) > self.stopped[0]
                                         or abs(velocity[1]) > self.stopped[1]):
            return (f'goal checker {self.name}: still moving at {velocity[0]:.3f} m/s, '
                    f'{velocity[1]:.3f} rad/s')
        return None


def checker_for(checkers: Mapping[str, GoalChecker], name: str) -> GoalChecker:
    """The checker a goal's `goal_checker_id` names, as Nav2 picks it: an empty one is the
    only one loaded.

    :raises KeyError: with the reason, for an id not loaded (or empty among several).
    """
    if name in checkers:
        return checkers[name]
    if not name and len(checkers) == 1:
        return next(iter(checkers.values()))
    raise KeyError(f"goal_checker_id {name!r} is not one of this server's: "
                   f"{', '.join(checkers)}")

"""Pure pursuit with four of the regulations of Nav2's Regulated Pure Pursuit (RPP).

Pure pursuit steers on the arc through a look-ahead point on the path: curvature
k = 2 y / d^2, where y is the point's offset to the left of the robot and d its distance.
The regulations, as RPP names them (Macenski et al., "Regulated Pure Pursuit for Robot Path
Tracking", 2023), written from that description:

- adaptive look-ahead (`use_velocity_scaled_lookahead_dist`): the look-ahead distance is the
  speed times `lookahead_time`, clamped to `min_lookahead_dist` and `max_lookahead_dist`;
- regulated linear velocity on curvature (`use_regulated_linear_velocity_scaling`): below the
  radius `regulated_linear_scaling_min_radius` the speed scales with the radius, down to
  `regulated_linear_scaling_min_speed`;
- approach velocity scaling: within `approach_velocity_scaling_dist` of the goal the speed
  scales with the distance left, down to `min_approach_linear_velocity`, and never above the
  speed from which the base can still stop (its acceleration limit);
- rotate to heading (`use_rotate_to_heading`): facing more than `rotate_to_heading_min_angle`
  away from the look-ahead point, it turns in place first.

Those numbers are its tuning (`tuning.Tunable`), with RPP's names and defaults: the node serves
them as the parameters `pure_pursuit.<name>`. The node clamps each command to the base's limits
(`walker.PlanWalker`).
"""

from __future__ import annotations

import math

import numpy as np

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.controller import Limits, State, Stroke
from turtle_traj.core.control.tuning import Tunable
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.projection import nearest_point

_SPACING_M = 0.01  # the path is followed point by point this far apart
_SEARCH_POINTS = 100  # the nearest point is searched up to 1 m ahead of the last one
_NEAR_END_M = 0.05  # the goal counts only this close to the end along the path (a closed
# path ends where it starts)


class PurePursuit:
    """Regulated pure pursuit along one stroke (see the module's docstring)."""

    rotate_to_heading = True
    approach_scaling = True
    # RPP's defaults
    lookahead_time = Tunable(1.5, 'The look-ahead distance is the speed times this', 's',
                             0.01, 20.0)
    min_lookahead_dist = Tunable(0.3, 'Shortest look-ahead distance', 'm', 0.01, 10.0)
    max_lookahead_dist = Tunable(0.9, 'Longest look-ahead distance', 'm', 0.01, 10.0)
    regulated_linear_scaling_min_radius = Tunable(
        0.9, 'Below this radius of curvature the speed scales with the radius', 'm', 0.0, 100.0)
    regulated_linear_scaling_min_speed = Tunable(
        0.25, 'The least speed the curvature scaling leaves (at most the top speed)', 'm/s',
        0.0, 10.0)
    approach_velocity_scaling_dist = Tunable(
        0.6, 'Within this distance of the goal the speed scales with the distance left', 'm',
        0.0, 10.0)
    min_approach_linear_velocity = Tunable(
        0.05, 'The least speed the approach scaling leaves', 'm/s', 0.001, 10.0)
    rotate_to_heading_min_angle = Tunable(
        math.radians(45.0), 'Facing further than this from the look-ahead point, it turns in '
        'place first', 'rad', 0.0, math.pi)
    goal_tolerance = Tunable(0.01, 'Arrived this close to the end of a stroke', 'm', 0.001, 1.0)

    def start(self, stroke: Stroke, limits: Limits) -> None:
        self.points = _densified(np.asarray(stroke.points, dtype=float))
        self.arc = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(self.points, axis=0).T))))
        self.limits = limits
        self.nearest = 0

    def command(self, state: State) -> Command | None:
        pose, velocity = state.pose, state.velocity
        remaining = self.arc[-1] - self.arc[self._nearest(pose)]
        if self._arrived(pose, remaining):
            return None if _stopped(velocity) else self.stopping(velocity)
        curvature, bearing = self._steering(pose, abs(velocity.linear))
        speed = self._regulated_speed(curvature, remaining)
        return self.choose(speed, curvature, bearing, velocity)

    def choose(self, speed: float, curvature: float, bearing: float,
               velocity: Command) -> Command:
        """The command for a regulated speed on the arc of `curvature`."""
        if self.rotate_to_heading and abs(bearing) > self.rotate_to_heading_min_angle:
            return Command(0.0, math.copysign(self.limits.angular_speed, bearing))
        return Command(speed, curvature * speed)

    def stopping(self, velocity: Command) -> Command:
        """The command that stops the robot at the goal (the node brakes it within the
        limits)."""
        return Command()

    def _nearest(self, pose: Pose2D) -> int:
        """The path's point nearest the robot, from the last one up to `_SEARCH_POINTS` ahead
        (the search is short, so that a later part of the path passing close by is not
        jumped to)."""
        self.nearest = nearest_point(self.points, self.nearest, _SEARCH_POINTS, pose.x, pose.y)
        return self.nearest

    def _arrived(self, pose: Pose2D, remaining: float) -> bool:
        end, before = self.points[-1], self.points[-2]
        beyond = ((pose.x - end[0]) * (end[0] - before[0])
                  + (pose.y - end[1]) * (end[1] - before[1])) > 0.0
        return remaining < _NEAR_END_M and (
            math.dist((pose.x, pose.y), end) <= self.goal_tolerance or beyond)

    def _steering(self, pose: Pose2D, speed: float) -> tuple[float, float]:
        """The arc's curvature to the look-ahead point, and the point's bearing."""
        distance = min(max(speed * self.lookahead_time, self.min_lookahead_dist),
                       self.max_lookahead_dist)
        target = self.points[-1]
        for first in range(self.nearest, len(self.points), _SEARCH_POINTS):  # the first beyond
            ahead = self.points[first:first + _SEARCH_POINTS]
            beyond = np.nonzero(np.hypot(ahead[:, 0] - pose.x, ahead[:, 1] - pose.y)
                                >= distance)[0]
            if len(beyond):
                target = ahead[beyond[0]]
                break
        dx, dy = target[0] - pose.x, target[1] - pose.y
        left = -math.sin(pose.theta) * dx + math.cos(pose.theta) * dy
        squared = max(dx * dx + dy * dy, 1e-12)
        return 2.0 * left / squared, wrap_angle(math.atan2(dy, dx) - pose.theta)

    def _regulated_speed(self, curvature: float, remaining: float) -> float:
        limits = self.limits
        speed = limits.linear_speed
        floor = min(self.regulated_linear_scaling_min_speed, limits.linear_speed)
        radius = 1.0 / max(abs(curvature), 1e-9)
        min_radius = self.regulated_linear_scaling_min_radius
        if radius < min_radius:
            speed = max(speed * radius / min_radius, floor)
        approach = self.approach_velocity_scaling_dist
        if self.approach_scaling and remaining < approach:
            speed = min(speed, max(speed * remaining / approach,
                                   self.min_approach_linear_velocity))
        if limits.linear_braking:
            speed = min(speed, math.sqrt(2.0 * limits.linear_braking * max(remaining, 0.0)))
        return speed


def _densified(points: np.ndarray) -> np.ndarray:
    parts = []
    for a, b in zip(points[:-1], points[1:], strict=True):
        count = max(1, math.ceil(math.dist(a, b) / _SPACING_M))
        parts.append(a + np.outer(np.arange(count) / count, b - a))
    parts.append(points[-1:])
    return np.concatenate(parts)


def _stopped(velocity: Command) -> bool:
    """The velocity in effect is a stop."""
    return abs(velocity.linear) < 1e-9 and abs(velocity.angular) < 1e-9

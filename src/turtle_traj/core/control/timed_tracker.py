"""Following a motion planned in time: a polyline with its speed at each point
(`Polyline.speeds`, the minimum-time trajectory's) on a base with acceleration limits. Pure
Python.

Each command finds the instant of the plan the robot is at: the one whose position is nearest
the pose predicted for when the command takes effect, searched from a little before the last
one found to a few periods after it (where the plan curls at a near-pivot, a robot pushed off
it lies nearer to where the plan goes on after the curl). The plan at that instant gives the
heading to keep and the line to pull back onto; the plan one period on gives the speed and the
turn rate (feed-forward). The heading set-point steers back onto the plan's line as
`trackers.PolylineTracker` steers onto a path. Where the turn rate it asks for is beyond the
base's top rate, the speed is cut in proportion, so the robot stays on the curve it asks for
and loses time rather than the path (the plan keeps none of the turn rate in reserve).
Arrival and the end are the polyline tracker's; past the end, it backs up to it.

The polyline tracker, reading a planned speed by arc length and turning at that speed times
the path's curvature, falls behind such a motion where it nearly pivots, the heading turning
fast while the robot barely moves (the DWPP paper's 135-degree steps within 106 mm: 21.9 s
and 123 mm from the path, where this tracker takes 20.6 s and 94 mm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.config import Limits
from turtle_traj.core.control.prediction import Prediction
from turtle_traj.core.control.profile import SpeedProfile
from turtle_traj.core.control.trackers import (
    PolylineTracker,
    TrackerGains,
    braking_speed,
    steering_rate,
)
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Polyline, Pose2D

# Where a match is searched for, around the last one: a robot pushed off the plan where it
# curls (a near-pivot) lies nearer to where the plan goes on after the curl than to where it is
# in the plan; it cannot get further ahead of the plan than a few periods a command.
_BEHIND_S = 0.5
_AHEAD_PERIODS = 3


@dataclass(frozen=True)
class Reference:
    """Where the plan has the robot at an instant, and how it moves there."""

    x: float
    y: float
    heading: float
    speed: float
    turn_rate: float


class Timing:
    """A polyline's motion in time: each segment at a constant acceleration between the
    speeds at its ends (`SpeedProfile.timed`)."""

    def __init__(self, polyline: Polyline, profile: SpeedProfile) -> None:
        assert profile.times is not None
        self.polyline = polyline
        self.times = profile.times
        self.speeds = profile.speed
        self.duration_s = float(profile.times[-1])
        self._instant = 0.0  # of the plan, where the last match found the robot

    def match(self, pose: Pose2D, period_s: float) -> float:
        """The instant of the plan nearest `pose`, from a little before the last one found to
        a few periods after it (`_BEHIND_S`, `_AHEAD_PERIODS`): on the nearer of the two
        segments at the nearest point, where its constant acceleration has the plan there."""
        polyline, count = self.polyline, len(self.times)
        first = max(int(np.searchsorted(self.times, self._instant - _BEHIND_S)) - 1, 0)
        last = min(int(np.searchsorted(self.times, self._instant
                                       + _AHEAD_PERIODS * period_s)) + 1, count - 1)
        window = polyline.points[first:last + 1]
        nearest = first + int(np.argmin((window[:, 0] - pose.x) ** 2
                                        + (window[:, 1] - pose.y) ** 2))
        best = (math.inf, 0, 0.0)
        for index in (nearest - 1, nearest):
            if not 0 <= index < count - 1:
                continue
            (ax, ay), (bx, by) = polyline.points[index], polyline.points[index + 1]
            dx, dy = bx - ax, by - ay
            share = min(max(((pose.x - ax) * dx + (pose.y - ay) * dy)
                            / max(dx * dx + dy * dy, 1e-24), 0.0), 1.0)
            gap = (ax + share * dx - pose.x) ** 2 + (ay + share * dy - pose.y) ** 2
            best = min(best, (gap, index, share))
        _, index, share = best
        along = share * float(polyline.segment_lengths[index])
        start_speed, end_speed = float(self.speeds[index]), float(self.speeds[index + 1])
        length = max(float(polyline.segment_lengths[index]), 1e-12)
        # v^2 is linear along a segment of constant acceleration
        there = math.sqrt(max(start_speed ** 2 + (end_speed ** 2 - start_speed ** 2)
                              * along / length, 0.0))
        found = float(self.times[index]) + 2.0 * along / max(start_speed + there, 1e-9)
        self._instant = min(max(found, self._instant - _BEHIND_S),
                            self._instant + _AHEAD_PERIODS * period_s)
        return self._instant

    def at(self, instant: float) -> Reference:
        """The reference at `instant` (at rest on the end once the plan is over)."""
        polyline = self.polyline
        last = len(polyline.points) - 2
        if instant >= self.duration_s:
            end = polyline.points[-1]
            return Reference(float(end[0]), float(end[1]), float(polyline.headings[last]),
                             0.0, 0.0)
        index = min(int(np.searchsorted(self.times, max(instant, 0.0), side='right')) - 1, last)
        length = float(polyline.segment_lengths[index])
        start_speed, end_speed = float(self.speeds[index]), float(self.speeds[index + 1])
        accel = (end_speed ** 2 - start_speed ** 2) / (2.0 * max(length, 1e-12))
        elapsed = max(instant - float(self.times[index]), 0.0)
        speed = max(start_speed + accel * elapsed, 0.0)
        share = min((start_speed * elapsed + 0.5 * accel * elapsed ** 2) / max(length, 1e-12),
                    1.0)
        begin, finish = polyline.points[index], polyline.points[index + 1]
        curvature = float(polyline.tangent_curvatures[index])
        heading = float(polyline.headings[index]) + curvature * length * (share - 0.5)
        return Reference(float(begin[0] + share * (finish[0] - begin[0])),
                         float(begin[1] + share * (finish[1] - begin[1])),
                         heading, speed, speed * curvature)


class TimedTracker(PolylineTracker):
    """Keeps to a polyline's planned motion in time (see the module)."""

    def __init__(self, polyline: Polyline, end_tolerance: float,
                 profile: SpeedProfile) -> None:
        super().__init__(polyline, end_tolerance, profile)
        self._timing = Timing(polyline, profile)

    def _command(self, pose: Pose2D, fraction: float, offset: float, remaining: float,
                 prediction: Prediction, limits: Limits, gains: TrackerGains,
                 landing: bool) -> Command:
        timing, period = self._timing, limits.period_s
        instant = timing.match(pose, period)
        reference, onward = timing.at(instant), timing.at(instant + period)
        beside = ((reference.y - pose.y) * math.cos(reference.heading)
                  - (reference.x - pose.x) * math.sin(reference.heading))
        heading_error = wrap_angle(reference.heading - pose.theta)
        speed = 0.0  # facing too far off: a turn in place first
        if abs(heading_error) <= gains.turn_first_angle:
            # the end's last millimetres in one period, from rest to rest, as the tracker does
            speed = max(onward.speed * math.cos(heading_error),
                        min(abs(remaining) / period, limits.linear_accel * period))
        overrun = prediction.overrun_when(limits.limited)[0]
        speed = math.copysign(min(speed, limits.linear_speed,
                                  braking_speed(max(abs(remaining) - overrun, 0.0),
                                                limits.linear_braking or gains.deceleration,
                                                period, prediction, limits.limited, landing)),
                              remaining)  # backing up to the end, if past it
        target = reference.heading + math.atan(gains.cross_track_gain * beside)
        steering = steering_rate(wrap_angle(target - pose.theta), gains.heading_gain, limits)
        angular = onward.turn_rate + steering
        if abs(angular) > limits.angular_speed:  # out of reach: slower, on the same curve
            speed *= limits.angular_speed / abs(angular)
            angular = math.copysign(limits.angular_speed, angular)
        return Command(speed, angular)

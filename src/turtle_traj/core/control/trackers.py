"""A leg's tracker: an in-place turn, or a polyline followed continuously. Pure Python.

Each steers from the pose predicted for the moment its command takes effect (`robot_model`),
so the latency between pose and command is accounted for, not guessed. The speed along a curve
is capped by its curvature at the top turn rate, by a braking profile towards the end of the
polyline and, near the end, by the predicted remaining distance per control period, so the
turtle stops on the end point. A turtle facing more than `turn_first_angle` away from the path
turns in place first; on a base with acceleration limits, where a tolerance leaves room, it
drives off slowly meanwhile (`drift`). Without acceleration limits (turtlesim) each command's
step lands on the smooth curve through the vertices (`curve_step`); with them, curves are
tracked with curvature feed-forward plus a heading set-point that steers back onto the path
(`-atan(cross_track_gain * error)`).

On a base with acceleration limits (`Limits.limited`) braking follows the limits, curves
follow their time-optimal speed profile (`profile`), and a leg ends only once a stop is within
reach. A polyline is driven forwards: the walker shows one driven backwards as a forward one.
"""

from __future__ import annotations

import math
from typing import Protocol

from turtle_traj.core.control.commands import STOP, Command
from turtle_traj.core.control.config import ControlConfig, Limits
from turtle_traj.core.control.controller import ARRIVED_M
from turtle_traj.core.control.curve_step import step_onto_curve
from turtle_traj.core.control.drift import Tube, drift_speed
from turtle_traj.core.control.dynamics import can_stop, stopping_speed
from turtle_traj.core.control.prediction import Prediction
from turtle_traj.core.control.profile import SpeedProfile, profile_for
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Polyline, Pose2D, Turn
from turtle_traj.core.geometry.sampled_curve import SampledCurve

_WINDOW_BEHIND = 3  # segments searched behind the last match
_WINDOW_AHEAD = 15  # and ahead of it: far enough to keep up, too short to skip a lap
UNPLANNED = object()  # a polyline's speed profile, before it is planned
LANDED = 1e-5  # m, rad: on the end, for a landing (`_lands`)


def braking_speed(remaining: float, deceleration: float, period_s: float,
                  prediction: Prediction, limited: bool = False, landing: bool = False) -> float:
    """Fastest speed from which the turtle still stops within `remaining`.

    Near the end a command covers what remains of the predicted remainder in one period, so it
    lands on the end point (deadbeat) when the latency is steady. When a command may act
    `late_steps` periods longer than one, it covers only its share of the remainder, and a
    misjudged period is corrected by the next command (backing up if needed: the remainder is
    signed). Such an approach stops inside the end's tolerance, short of the end; once the
    turtle stands there, one `landing` command covers the rest in one period.
    """
    braking = (stopping_speed(remaining, deceleration, period_s) if limited
               else math.sqrt(2.0 * deceleration * remaining))
    share = 1 if landing else 1 + prediction.late_steps
    return min(braking, remaining / (share * period_s))


def _lands(remaining: float, prediction: Prediction, limits: Limits) -> bool:
    """Whether to land on the end with one more command: the approach allowed for late
    commands and stopped inside the tolerance, short of the end, and the turtle stands there.
    Once per leg, so a command that acts late again cannot start a hunt (it carries the turtle
    at most the tolerance past the end). Only where the prediction is exact to the step,
    turtlesim's: a base's odometry and inertia leave it a little off."""
    return (prediction.late_steps > 0 and prediction.standing and prediction.turns_first
            and not limits.limited and abs(remaining) > LANDED)


def _finished(arrived: bool, prediction: Prediction, limits: Limits,
              landed: bool = False) -> Command | None:
    """None when a leg is over: the predicted pose is there, and the turtle itself too.

    Until then the commands on their way carry the turtle, so hold with a stop. When a command
    may act longer than predicted, the turtle must also stand still, or it would carry it on;
    but not after a landing, which carries it at most the tolerance on (`_lands`).
    A base with acceleration limits must be able to stop within the next period.
    """
    if (arrived and (prediction.late_steps == 0 or prediction.standing or landed)
            and (not limits.limited or can_stop(prediction.velocity, limits))):
        return None
    return STOP


class TrackerGains(Protocol):
    """The polyline tracker's gains (the exact follower's `Tunable`s)."""

    heading_gain: float  # turn rate per radian of heading error [1/s]
    cross_track_gain: float  # how hard curves pull back onto the path [1/m]
    deceleration: float  # braking towards the end, without acceleration limits [m/s^2]
    turn_first_angle: float  # heading error beyond which it turns before driving [rad]


def steering_rate(error: float, gain: float, limits: Limits) -> float:
    """The turn rate that corrects a heading error: proportional, and on a base with an
    angular acceleration limit no faster than it can stop turning when the error is gone
    (sqrt(2 alpha |error|)), or a high gain would overshoot, rate-limited."""
    rate = gain * abs(error)
    if limits.angular_accel:
        rate = min(rate, math.sqrt(2.0 * limits.angular_accel * abs(error)))
    return math.copysign(rate, error)


def _clamp(value: float, limit: float) -> float:
    return max(-limit, min(limit, value))


class TurnTracker:
    """Turns by the leg's sweep, counting the rotation actually made (it may exceed pi)."""

    def __init__(self, turn: Turn, pose: Pose2D) -> None:
        self.turn = turn
        self.turned = wrap_angle(pose.theta - turn.start_heading)
        self.previous = pose.theta
        self.landed = False  # the one landing command is sent (`_lands`)

    @property
    def fraction(self) -> float:
        """How much of the turn is made, 0 to 1 (a turn of no sweep is made)."""
        if self.turn.sweep_rad == 0.0:
            return 1.0
        return min(max(self.turned / self.turn.sweep_rad, 0.0), 1.0)

    def update(self, pose: Pose2D, prediction: Prediction,
               config: ControlConfig) -> Command | None:
        predicted = prediction.pose
        self.turned += wrap_angle(pose.theta - self.previous)
        self.previous = pose.theta
        remaining = self.turn.sweep_rad - self.turned
        error = remaining - wrap_angle(predicted.theta - pose.theta)
        landing = False
        if abs(error) < config.heading_tolerance:
            if self.landed or not _lands(error, prediction, config.limits):
                return _finished(abs(remaining) < config.heading_tolerance, prediction,
                                 config.limits, self.landed)
            self.landed = landing = True
        overrun = prediction.overrun_when(config.limited)[1]
        rate = min(config.angular_speed,
                   braking_speed(max(abs(error) - overrun, 0.0), config.angular_braking,
                                 config.period_s, prediction, config.limited, landing))
        return Command(0.0, math.copysign(rate, error))


class PolylineTracker:
    """Tracks a polyline, keeping its place along it from one update to the next."""

    def __init__(self, polyline: Polyline, end_tolerance: float,
                 profile: SpeedProfile | None | object = None, tube: Tube | None = None) -> None:
        self.polyline = polyline
        self._tube = tube  # the tolerance's room round the path as drawn; None: exact
        self.end_tolerance = end_tolerance
        self.segment = 0
        self.fraction = 0.0  # of the polyline's length, up to where the turtle is (one lap)
        self._profile = profile  # with acceleration limits: None on a straight line
        self.landed = False  # the one landing command is sent (`_lands`)
        self._segments = polyline.segments
        self._curve: SampledCurve | None = None  # the curve the steps land on (`curve_step`)

    def _candidates(self) -> list[int] | range:
        """The segments searched: a window around the last match (wrapping on a loop)."""
        count = self._segments.count
        first, last = self.segment - _WINDOW_BEHIND, self.segment + _WINDOW_AHEAD
        if self.polyline.repeat:
            return [index % count for index in range(first, last + 1)]
        return range(min(max(first, 0), count - 1), min(max(last, 0), count - 1) + 1)

    def _project(self, pose: Pose2D) -> tuple[int, float, float]:
        """Nearest segment near the last one: index, fraction along it, signed offset."""
        return self._segments.project(pose.x, pose.y, self._candidates())

    def _remaining(self, pose: Pose2D, segment: int, fraction: float) -> float:
        """Distance left to the end (inf on a repeating polyline), signed: negative past it."""
        polyline = self.polyline
        if polyline.repeat:
            return math.inf
        last = len(polyline.points) - 2
        end = polyline.points[-1]
        heading = polyline.headings[last]
        to_end = (end[0] - pose.x) * math.cos(heading) + (end[1] - pose.y) * math.sin(heading)
        along_rest = polyline.length - polyline.cumulative_length[segment + 1]
        return along_rest + (to_end if segment == last else
                             (1.0 - fraction) * polyline.segment_lengths[segment])

    def _arrived(self, pose: Pose2D, segment: int, remaining: float) -> bool:
        """At the end: along the polyline within the tolerance and, straight, as near as the
        walker accepts (`ARRIVED_M`: a pose far beside the end is not there), or straight
        within the tolerance on the last segment."""
        if self.polyline.repeat:
            return False
        end = self.polyline.points[-1]
        straight = math.hypot(end[0] - pose.x, end[1] - pose.y)
        return ((abs(remaining) <= self.end_tolerance
                 and straight <= max(self.end_tolerance, ARRIVED_M))
                or (segment == len(self.polyline.points) - 2
                    and straight <= self.end_tolerance))

    def locate(self, pose: Pose2D) -> tuple[int, float]:
        """The segment nearest `pose`, near the last one, and the fraction along it."""
        return self._project(pose)[:2]

    def update(self, pose: Pose2D, prediction: Prediction, limits: Limits,
               gains: TrackerGains, nearest: tuple[int, float]) -> Command | None:
        """Steer from the predicted pose; progress and arrival are the actual pose's.

        :param nearest: the segment nearest the actual pose and the fraction along it
            (`State.nearest`, or `locate`).
        """
        polyline, predicted = self.polyline, prediction.pose
        actual_segment, actual_fraction = nearest
        self.fraction = (polyline.cumulative_length[actual_segment] + actual_fraction
                         * polyline.segment_lengths[actual_segment]) / max(polyline.length, 1e-12)
        self.segment, fraction, offset = self._project(predicted)
        remaining = self._remaining(predicted, self.segment, fraction)
        landing = False
        if self._arrived(predicted, self.segment, remaining):
            if self.landed or not _lands(remaining, prediction, limits):
                arrived = self._arrived(pose, actual_segment,
                                        self._remaining(pose, actual_segment, actual_fraction))
                return _finished(arrived, prediction, limits, self.landed)
            self.landed = landing = True
        return self._command(predicted, fraction, offset, remaining, prediction, limits, gains,
                             landing)

    def _command(self, pose: Pose2D, fraction: float, offset: float, remaining: float,
                 prediction: Prediction, limits: Limits, gains: TrackerGains,
                 landing: bool) -> Command:
        """The command for the predicted `pose`, `fraction` along the current segment and
        `offset` beside it (left positive), `remaining` from the end."""
        facing = pose.theta
        curvature, path_heading = self._heading_at(fraction, limits)
        heading_error = wrap_angle(path_heading - facing)

        speed = self._speed(fraction, remaining, curvature, prediction, limits, landing,
                            limits.linear_braking or gains.deceleration)
        if abs(heading_error) > gains.turn_first_angle:
            speed = self._speed_while_turning(pose, speed, heading_error, limits)
        elif self._steps_onto_curve(limits) and speed > 0.0:
            return step_onto_curve(self._sampled_curve(), pose, self._arc(fraction), speed,
                                   limits, prediction.turns_first)
        speed *= math.cos(heading_error)
        # turtlesim turns first and then moves along the new heading, so on an arc the motion
        # leads the heading by the turn of one period: aim half a chord behind the tangent.
        lead = (abs(speed) * curvature * limits.period_s / 2.0 if prediction.turns_first
                else 0.0)
        target = path_heading - lead - math.atan(gains.cross_track_gain * offset)
        steering = steering_rate(wrap_angle(target - facing), gains.heading_gain, limits)
        angular = _clamp(abs(speed) * curvature + steering, limits.angular_speed)
        return Command(speed, angular)

    def _speed_while_turning(self, pose: Pose2D, speed: float, heading_error: float,
                             limits: Limits) -> float:
        """Facing away past the turn-first angle: none (a turn in place), or on a base with
        acceleration limits and a tolerance, as much as keeps the drift within it (`drift`)."""
        if self._tube is None or not limits.limited or speed <= 0.0:
            return 0.0
        return min(speed, drift_speed(self._tube.room(pose.x, pose.y), heading_error, limits))

    def _speed(self, fraction: float, remaining: float, curvature: float,
               prediction: Prediction, limits: Limits, landing: bool,
               braking: float) -> float:
        """The speed along the path for this period, before the heading's share: the top
        speed, the base's profile or the curve's turn rate, and braking towards the end (signed:
        negative to back up to it)."""
        speed = limits.linear_speed
        if limits.limited:
            profiled = self._profiled_speed(fraction, prediction.velocity, limits)
            if remaining != math.inf:
                # the profile ends at rest, so it allows nothing on its last millimetre: a
                # base that stopped a hair short (its motors lag, its tyres slip) may still
                # creep there in one period, a move from rest to rest within reach
                profiled = max(profiled, min(abs(remaining) / limits.period_s,
                                             limits.linear_accel * limits.period_s))
            speed = min(speed, profiled)
        elif isinstance(self._profile, SpeedProfile):  # a rounded path's, at the full turn rate
            speed = min(speed, self._profile.speed_at(self._arc(fraction)))
        elif abs(curvature) > 1e-9:  # an exact path's curve, at the top turn rate
            speed = min(speed, limits.angular_speed / abs(curvature))
        if remaining != math.inf:
            overrun = prediction.overrun_when(limits.limited)[0]
            speed = min(speed, braking_speed(max(abs(remaining) - overrun, 0.0),
                                             braking, limits.period_s,
                                             prediction, limits.limited, landing))
            speed = math.copysign(speed, remaining)
        return speed

    def _heading_at(self, fraction: float, limits: Limits) -> tuple[float, float]:
        """The curvature and the heading to steer to, `fraction` along the current segment.

        The curve's tangent, which turns along each chord, not at its ends, is the heading on a
        base with limits and where the steps land on the smooth curve (`curve_step`): steered to
        the chords' headings, a base that changes its turn rate gradually beats against its
        angular acceleration limit at every vertex (a 0.5 m circle: a 7-period cycle, 1.2 mm
        outside it) and starts a circle from rest turning at half its rate (0.6 mm outside it).
        On turtlesim a rounded path's chords are aimed at, with the lead `update` adds."""
        polyline, segment = self.polyline, self.segment
        if not (limits.limited or self._steps_onto_curve(limits)):
            return float(polyline.curvatures[segment]), float(polyline.headings[segment])
        curvature = float(polyline.tangent_curvatures[segment])
        return curvature, float(polyline.headings[segment]) + curvature * float(
            polyline.segment_lengths[segment]) * (fraction - 0.5)

    def _sampled_curve(self) -> SampledCurve:
        """The smooth curve through the polyline's vertices, made on first use."""
        if self._curve is None:
            self._curve = SampledCurve(self.polyline)
        return self._curve

    def _steps_onto_curve(self, limits: Limits) -> bool:
        """An exact path's curve on a robot that takes each command at once lands each step on
        the curve (`curve_step`). A rounded path's profile takes the whole turn rate and leaves
        the steering the tolerance's reserve, which the heading set-point keeps within."""
        return not limits.limited and not isinstance(self._profile, SpeedProfile)

    def _arc(self, fraction: float) -> float:
        """How far along the polyline `fraction` of the current segment is, metres."""
        return float(self.polyline.cumulative_length[self.segment]
                     + fraction * self.polyline.segment_lengths[self.segment])

    def _profiled_speed(self, fraction: float, velocity: Command,
                        limits: Limits) -> float:
        """The profile's speed where this command's period ends (from a standstill the
        profile starts at 0: it is the window that accelerates the base). The profile is the
        plan's (`Plan.profiles`), planned with the request rather than in the control loop."""
        polyline = self.polyline
        if self._profile is UNPLANNED:  # not planned with the plan: the settings changed
            self._profile = profile_for(polyline, limits)
        if self._profile is None:  # a straight line
            return limits.linear_speed
        arc = self._arc(fraction)
        reach = abs(velocity.linear) + (limits.linear_accel or 1e6) * limits.period_s
        ahead = min(reach, limits.linear_speed) * limits.period_s
        if polyline.repeat:
            return self._profile.speed_at((arc + ahead) % max(polyline.length, 1e-12))
        return self._profile.speed_at(arc + ahead)

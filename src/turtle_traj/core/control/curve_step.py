"""A step onto the curve, for a robot that takes each command at once. Pure Python.

Without acceleration limits (turtlesim) the follower picks, each period, the command whose step
ends on the smooth curve through the path's vertices (`SampledCurve`), a step further along it.
Turtlesim turns first and then moves straight, so the turn aims the step at that point; a robot
that drives arcs turns twice as far, its arc's chord leaving at half the turn. Each step takes
back half of the robot's offset from the curve (as much of it as the top turn rate leaves), so
a command that acts for two periods, as a late one may, lands it on the curve rather than
beyond it. Where the turn a step alongside the curve needs exceeds the top turn rate, the step
is shortened; where no step is short enough, the robot turns in place towards the point ahead.
"""

from __future__ import annotations

import math

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.config import Limits
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.sampled_curve import SampledCurve

CORRECTION = 0.5  # the share of the offset from the curve one step takes back
_SHORTER = 0.9  # each try's step, of the one before
_TRIES = 40  # down to 1.5% of the first step


def _aim(pose: Pose2D, x: float, y: float, turns_first: bool) -> tuple[float, float]:
    """The turn and the distance of a step from `pose` that ends at (x, y)."""
    dx, dy = x - pose.x, y - pose.y
    turn = wrap_angle(math.atan2(dy, dx) - pose.theta)
    distance = math.hypot(dx, dy)
    if not turns_first:  # an arc of turn 2a has a chord at a to its start, 2r sin(a) long
        distance *= turn / math.sin(turn) if abs(turn) > 1e-9 else 1.0
        turn *= 2.0
    return turn, distance


def step_onto_curve(curve: SampledCurve, pose: Pose2D, arc: float, speed: float,
                    limits: Limits, turns_first: bool = True) -> Command:
    """This period's command towards the curve.

    :param pose: the pose the command starts from (the model's prediction).
    :param arc: how far along the curve the point nearest `pose` is, metres.
    :param speed: the most the curve's turn rate and the braking towards its end allow, m/s;
        a step slanting back onto the curve is no faster.
    :param turns_first: the robot turns, then moves straight (turtlesim); else it drives arcs.
    """
    period = limits.period_s
    nearest_x, nearest_y = curve.point_at(arc)
    offset_x, offset_y = pose.x - nearest_x, pose.y - nearest_y
    most = limits.angular_speed * period
    first_turn = 0.0
    for attempt in range(_TRIES):
        ahead_x, ahead_y = curve.point_at(arc + speed * _SHORTER ** attempt * period)
        # the step alongside the curve must be within the top turn rate; the correction
        # back onto it takes what is left
        alongside, _ = _aim(pose, ahead_x + offset_x, ahead_y + offset_y, turns_first)
        if attempt == 0:
            first_turn = alongside
        if abs(alongside) <= most:
            turn, distance = _aim(pose, ahead_x + (1.0 - CORRECTION) * offset_x,
                                  ahead_y + (1.0 - CORRECTION) * offset_y, turns_first)
            return Command(min(distance / period, speed), max(-most, min(most, turn)) / period)
    return Command(0.0, math.copysign(min(abs(first_turn) / period, limits.angular_speed),
                                      first_turn))

"""A step onto the curve, for a robot that takes each command at once. Pure Python.

Without acceleration limits (turtlesim) the follower picks, each period, the command whose step
ends on the smooth curve through the path's vertices (`SampledCurve`), a step further along it.
Turtlesim turns first and then moves straight, so the turn aims the step at that point; a robot
that drives arcs turns twice as far, its arc's chord leaving at half the turn. A step also takes
back a share of the robot's offset from the curve, in proportion to its length and at most half
(`CORRECTION` per `CORRECTION_M`, as much as the top turn rate leaves): a command that acts for
two periods, as a late one may, still lands short of the curve rather than beyond it, and a
short step (braking onto a stroke's end) does not turn the robot away from the curve's heading.
Where the turn a step alongside the curve needs exceeds the top turn rate, the step is
shortened; where no step is short enough (the robot faces away from the curve), it turns
towards it at the top rate, slowed by the cosine of the angle it faces away.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.config import Limits
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.sampled_curve import SampledCurve

# The share of the offset from the curve a step of CORRECTION_M or more takes back; a shorter
# one takes back less, in proportion. A 2.6 mm step braking onto a stroke's end that took back
# half of a 0.1 mm offset would turn the robot 0.019 rad off the curve's heading, which the
# stroke would end with; over a longer CORRECTION_M (5 cm) the offset a rose's tight petals
# leave is still 0.3 mm at its end
CORRECTION = 0.5
CORRECTION_M = 0.03
# a turn this much over the top one is clamped to it: its step lands at most 1% of a period's
# top turn times the step off the curve (5 um at turtlesim's 1 m/s and 2 rad/s)
_OVER_TOP = 1.01
_SHORTEST = 0.01  # the shortest step tried, of the one the speed allows
_HALVINGS = 10  # the longest step within the top turn rate, to 0.1% of the one allowed


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

    def alongside(step: float) -> tuple[float, tuple[float, float]]:
        """The turn of a step of this length alongside the curve, keeping the offset, and the
        curve's point it is alongside."""
        ahead = curve.point_at(arc + step)
        return _aim(pose, ahead[0] + offset_x, ahead[1] + offset_y, turns_first)[0], ahead

    step = speed * period
    first_turn, ahead = alongside(step)
    if abs(first_turn) > most * _OVER_TOP:  # the longest step within the top turn, if any
        step, ahead = _longest_step(alongside, step, first_turn, most)
        if step == 0.0:  # turning at the top rate, slower as it faces away
            return Command(speed * max(math.cos(first_turn), 0.0),
                           math.copysign(limits.angular_speed, first_turn))
    share = CORRECTION * min(1.0, step / CORRECTION_M)
    turn, distance = _aim(pose, ahead[0] + (1.0 - share) * offset_x,
                          ahead[1] + (1.0 - share) * offset_y, turns_first)
    return Command(min(distance / period, speed), max(-most, min(most, turn)) / period)


def _longest_step(alongside: Callable[[float], tuple[float, tuple[float, float]]], step: float,
                  turn: float, most: float) -> tuple[float, tuple[float, float]]:
    """The longest step shorter than `step` whose turn alongside the curve is at most `most`,
    and its point on the curve; 0 where none is. The turn grows about as the step does, so the
    step scaled down to the top turn is tried first (on a curve driven at the top turn rate it
    is the one); else the step is halved towards it."""
    scaled = step * most / abs(turn) * (1.0 - 1e-6)
    scaled_turn, ahead = alongside(scaled)
    if abs(scaled_turn) <= most:
        return scaled, ahead
    low = step * _SHORTEST
    low_turn, low_ahead = alongside(low)
    if abs(low_turn) > most:
        return 0.0, low_ahead
    high = scaled
    for _ in range(_HALVINGS):
        middle = 0.5 * (low + high)
        middle_turn, middle_ahead = alongside(middle)
        if abs(middle_turn) <= most:
            low, low_ahead = middle, middle_ahead
        else:
            high = middle
    return low, low_ahead

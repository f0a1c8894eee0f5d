"""The smooth curve through a polyline's vertices, and the step that lands a robot on it (pure),
checked against circles computed here."""

import math
from dataclasses import replace

import numpy as np
import pytest

from turtle_traj.core.control.config import Limits
from turtle_traj.core.control.curve_step import CORRECTION, CORRECTION_M, step_onto_curve
from turtle_traj.core.geometry.path import Polyline, Pose2D
from turtle_traj.core.geometry.sampled_curve import SampledCurve

LIMITS = Limits(linear_speed=2.0, angular_speed=2.0, linear_accel=0.0, angular_accel=0.0,
                period_s=0.016)


def _arc_points(radius: float, sweep: float, count: int) -> np.ndarray:
    """`count` points on a circle about the origin, anticlockwise from (radius, 0)."""
    angles = np.linspace(0.0, sweep, count)
    return radius * np.column_stack((np.cos(angles), np.sin(angles)))


def _off_circle(point, radius: float) -> float:
    return abs(math.hypot(*point) - radius)


def test_the_curve_passes_through_every_vertex_and_hugs_the_circle_the_chords_cut():
    radius, sweep = 1.0, math.pi
    points = _arc_points(radius, sweep, 13)  # 15 degree chords: 8.6 mm sagitta
    curve = SampledCurve(Polyline(points))
    arcs = Polyline(points).cumulative_length
    for arc, vertex in zip(arcs, points, strict=True):
        assert curve.point_at(float(arc)) == pytest.approx(tuple(vertex), abs=1e-12)
    sagitta = radius * (1.0 - math.cos(sweep / 12 / 2))
    # inner chords: both ends' tangents are the circle's, so the cubic all but lies on it
    for start, end in zip(arcs[1:-2], arcs[2:-1], strict=True):
        for share in (0.25, 0.5, 0.75):
            assert _off_circle(curve.point_at(start + share * (end - start)), radius) < (
                0.01 * sagitta)
    chord_middle = 0.5 * (points[5] + points[6])
    assert _off_circle(chord_middle, radius) == pytest.approx(sagitta)


def test_an_open_curve_leaves_along_its_first_chord_and_stops_at_its_ends():
    points = _arc_points(1.0, math.pi / 2, 7)
    polyline = Polyline(points)
    curve = SampledCurve(polyline)
    (x0, y0), (x1, y1) = curve.point_at(0.0), curve.point_at(1e-6)
    assert math.atan2(y1 - y0, x1 - x0) == pytest.approx(float(polyline.headings[0]), abs=1e-4)
    assert curve.point_at(-1.0) == pytest.approx(tuple(points[0]))
    assert curve.point_at(polyline.length + 1.0) == pytest.approx(tuple(points[-1]))


def test_a_loop_s_curve_wraps_round_and_is_smooth_at_its_closing_vertex():
    points = _arc_points(1.0, 2 * math.pi, 25)
    points[-1] = points[0]
    polyline = Polyline(points, repeat=True)
    curve = SampledCurve(polyline)
    length = polyline.length
    assert curve.point_at(length + 0.3) == pytest.approx(curve.point_at(0.3), abs=1e-12)
    for arc in (-0.01, -0.002, 0.002, 0.01):  # either side of the closing vertex
        assert _off_circle(curve.point_at(arc), 1.0) < 1e-4


def _turn_then_move(pose: Pose2D, linear: float, angular: float, period: float) -> Pose2D:
    theta = pose.theta + angular * period
    return Pose2D(pose.x + linear * period * math.cos(theta),
                  pose.y + linear * period * math.sin(theta), theta)


def _arc_move(pose: Pose2D, linear: float, angular: float, period: float) -> Pose2D:
    turn = angular * period
    if abs(turn) < 1e-12:
        return _turn_then_move(pose, linear, 0.0, period)
    r = linear / angular
    return Pose2D(pose.x + r * (math.sin(pose.theta + turn) - math.sin(pose.theta)),
                  pose.y - r * (math.cos(pose.theta + turn) - math.cos(pose.theta)),
                  pose.theta + turn)


RADIUS = 0.5
CIRCLE = _arc_points(RADIUS, 2.0, 400)  # 2.5 mm chords


def _on_circle_at(angle: float, outward: float = 0.0) -> tuple[Pose2D, float]:
    """A pose on (or `outward` of) the circle at `angle`, facing along it, and its arc."""
    r = RADIUS + outward
    return Pose2D(r * math.cos(angle), r * math.sin(angle), angle + math.pi / 2), RADIUS * angle


@pytest.mark.parametrize(('turns_first', 'move'), [(True, _turn_then_move), (False, _arc_move)],
                         ids=['turtlesim', 'arcs'])
def test_a_step_lands_on_the_curve_a_step_further_along(turns_first, move):
    curve = SampledCurve(Polyline(CIRCLE))
    pose, arc = _on_circle_at(0.5)
    speed = 0.5 * LIMITS.angular_speed * RADIUS  # half the turn rate the circle allows
    command = step_onto_curve(curve, pose, arc, speed, LIMITS, turns_first)
    landed = move(pose, command.linear, command.angular, LIMITS.period_s)
    assert _off_circle((landed.x, landed.y), RADIUS) < 1e-5
    travelled = RADIUS * (math.atan2(landed.y, landed.x) - 0.5)
    assert travelled == pytest.approx(speed * LIMITS.period_s, rel=1e-3)


def test_a_step_takes_back_its_share_of_the_offset_as_far_as_the_turn_rate_allows():
    curve = SampledCurve(Polyline(CIRCLE))
    for speed in (0.4, 4.0):  # steps of 6.4 mm and 64 mm: a share in proportion, at most half
        share = CORRECTION * min(1.0, speed * LIMITS.period_s / CORRECTION_M)
        pose, arc = _on_circle_at(0.5, outward=0.0001)
        command = step_onto_curve(curve, pose, arc, speed, replace(LIMITS, angular_speed=50.0))
        landed = _turn_then_move(pose, command.linear, command.angular, LIMITS.period_s)
        assert math.hypot(landed.x, landed.y) - RADIUS == pytest.approx(
            (1.0 - share) * 0.0001, abs=2e-6)
    # 10 mm off: turning at the top rate, still moving, and closer
    pose, arc = _on_circle_at(0.5, outward=0.01)
    command = step_onto_curve(curve, pose, arc, 0.4, LIMITS)
    assert command.angular == pytest.approx(LIMITS.angular_speed)
    assert command.linear == pytest.approx(0.4)  # slanting back no faster
    landed = _turn_then_move(pose, command.linear, command.angular, LIMITS.period_s)
    assert math.hypot(landed.x, landed.y) - RADIUS < 0.01 - 0.0001


def test_a_short_step_onto_a_stroke_s_end_keeps_the_stroke_s_heading():
    """Braking onto the end of a straight stroke 0.1 mm beside it, the last 2.6 mm: the step
    ends on the stroke's end and its heading within 0.002 rad of the stroke's (taking back half
    the offset in that one step would turn it 0.019 rad away)."""
    line = SampledCurve(Polyline(np.array([(0.0, 0.0), (1.0, 0.0)])))
    pose = Pose2D(1.0 - 0.0026, 0.0001, 0.0)
    command = step_onto_curve(line, pose, 1.0 - 0.0026, 0.0026 / LIMITS.period_s, LIMITS)
    landed = _turn_then_move(pose, command.linear, command.angular, LIMITS.period_s)
    assert abs(landed.theta) < 0.002
    assert landed.x == pytest.approx(1.0, abs=1e-5)
    assert 0.0 < landed.y < 0.0001


def test_a_step_beyond_the_turn_rate_is_shortened_and_one_that_cannot_be_turns_its_fastest():
    curve = SampledCurve(Polyline(CIRCLE))
    pose, arc = _on_circle_at(0.5)
    too_fast = 2.0 * LIMITS.angular_speed * RADIUS  # twice what the turn rate allows
    command = step_onto_curve(curve, pose, arc, too_fast, LIMITS)
    assert abs(command.angular) <= LIMITS.angular_speed + 1e-12
    assert 0.0 < command.linear < too_fast
    landed = _turn_then_move(pose, command.linear, command.angular, LIMITS.period_s)
    assert _off_circle((landed.x, landed.y), RADIUS) < 1e-5
    # facing 0.3 rad to the right of the curve: no step reaches it within one period's turn,
    # so it turns left at the top rate, slowed as it faces away
    askew = Pose2D(pose.x, pose.y, pose.theta - 0.3)
    command = step_onto_curve(curve, askew, arc, 0.4, LIMITS)
    assert command.angular == LIMITS.angular_speed
    assert command.linear == pytest.approx(0.4 * math.cos(0.3), rel=0.01)

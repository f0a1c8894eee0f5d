"""Driving on while turning onto the path, within a tolerance (core.control.drift)."""

import math
from dataclasses import replace

import numpy as np
import pytest
import shapely

from turtle_traj.core.control.config import Limits
from turtle_traj.core.control.drift import Tube, closing_time_s, drift_speed

PAPER = Limits(linear_speed=0.5, angular_speed=1.0, period_s=0.016, linear_accel=0.5,
               angular_accel=1.0)
STEP_S = 1e-4


def _turned(duration: float, limits: Limits, speed: float, error: float) -> tuple[float, float]:
    """The fastest turn from rest to rest that lasts `duration` (its rate up at the angular
    acceleration, at the top rate if reached, down at the angular acceleration to stop at the
    end), at `speed` throughout, integrated finely: the angle it turns, and the sideways drift
    from a path `error` away from the first heading, which it turns towards."""
    alpha, top = limits.angular_accel, limits.angular_speed
    turned, drift = 0.0, 0.0
    for t in np.arange(0.0, duration, STEP_S) + STEP_S / 2:
        drift += speed * math.sin(error - turned) * STEP_S
        turned += min(alpha * t, top, alpha * (duration - t)) * STEP_S
    return turned, drift


@pytest.mark.parametrize('error', [0.3, 0.6, math.pi / 4, 1.2])
def test_the_fastest_turn_of_the_closing_time_turns_through_the_error(error):
    turned, _ = _turned(closing_time_s(error, PAPER), PAPER, 0.0, error)
    assert turned == pytest.approx(error, abs=1e-3)


@pytest.mark.parametrize('error', [0.3, 0.6, math.pi / 4, 1.2])
@pytest.mark.parametrize('room', [0.02, 0.05])
def test_the_drift_at_the_speed_allowed_keeps_within_the_room_and_uses_most_of_it(error, room):
    """The bound takes sin(error) as the error: at 1.2 rad that gives away about a tenth."""
    speed = drift_speed(room, error, PAPER)
    _, drift = _turned(closing_time_s(error, PAPER), PAPER, speed, error)
    assert 0.85 * room < drift <= room


def test_no_speed_without_room_or_facing_a_quarter_turn_away():
    assert drift_speed(0.0, 0.7, PAPER) == 0.0
    assert drift_speed(-0.01, 0.7, PAPER) == 0.0
    assert drift_speed(0.05, math.pi / 2, PAPER) == 0.0
    assert drift_speed(0.05, 0.7, PAPER) > 0.0


def test_the_room_is_the_tolerance_less_the_distance_from_the_path_as_drawn():
    drawn = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    tube = Tube(drawn, 0.05)
    line = shapely.LineString(drawn)
    for x, y in [(0.5, 0.02), (1.03, 0.5), (0.5, -0.08), (1.2, 1.2)]:
        assert tube.room(x, y) == pytest.approx(0.05 - line.distance(shapely.Point(x, y)))


def _staircase() -> np.ndarray:
    """A grid planner's diagonal: 24 cells of 5 cm along x, then along y, in turn."""
    moves = np.tile([[0.05, 0.0], [0.0, 0.05]], (24, 1))
    return np.array([2.0, 2.0]) + np.concatenate(([[0.0, 0.0]], np.cumsum(moves, axis=0)))


def test_a_base_drives_off_while_it_turns_onto_a_staircase_within_the_tolerance_and_sooner():
    """The staircase within 5 cm, from facing along x: the plan runs along the diagonal, 45
    degrees away, past the exact follower's turn-first angle. Given the tolerance's room, the
    robot moves off before it faces the plan, stays within 5 cm of the staircase (measured
    here, with shapely) and arrives sooner than the same plan driven with no room (turning in
    place to the turn-first angle first)."""
    from turtle_traj.apps.score.courses import PAPER_LIMITS, follow_request
    from turtle_traj.apps.score.loop import drive
    from turtle_traj.core.geometry.path import Pose2D
    from turtle_traj.core.parameters.settings import settings_from_values
    from turtle_traj.core.parameters.table import DEFAULTS
    from turtle_traj.core.planning import planner
    from turtle_traj.sim.physics import Inertia

    points = _staircase()
    settings = settings_from_values({**DEFAULTS, **PAPER_LIMITS, 'arena': 'none'})
    start = Pose2D(float(points[0, 0]), float(points[0, 1]), 0.0)
    plan = planner.plan('follow_path', follow_request(points, corner_tolerance=0.05), start,
                        settings)
    assert plan.tolerance == 0.05
    limits = settings.control.limits
    inertia = Inertia(limits.linear_accel, limits.angular_accel)
    drifting = drive(plan, start, settings, inertia=inertia)
    turning = drive(replace(plan, tolerance=0.0), start, settings, inertia=inertia)
    assert drifting.run.ending[0] and turning.run.ending[0]
    staircase = shapely.LineString(points)
    xy = drifting.xy()
    assert float(shapely.distance(staircase, shapely.points(xy)).max()) <= 0.05
    moved = np.hypot(*(xy - points[0]).T) > 0.002
    first_move = int(np.argmax(moved))
    heading_then = drifting.poses[first_move].theta
    assert math.pi / 4 - heading_then > 0.6  # still past the turn-first angle (0.6 rad)
    assert drifting.elapsed_s < turning.elapsed_s - 0.15

"""Cusps turned short (pure): where a path doubles back, the robot turns a width before the
cusp and leaves as far past it, within that width of the path as drawn; checked against
shapely's distances and lengths."""

import math

import numpy as np
import pytest
import shapely

from turtle_traj.core.geometry.corners import MAX_ROUNDED_RAD
from turtle_traj.core.geometry.cusps import cusps_cut_short
from turtle_traj.core.geometry.path import Polyline, Turn


def _doubling_back(degrees: float, pen: bool = True) -> tuple:
    """From (0, 0) 2 m along x to the cusp (2, 0), a turn of `degrees`, and 2 m back."""
    back = math.radians(180.0 - degrees)
    cusp = np.array([2.0, 0.0])
    end = cusp + 2.0 * np.array([-math.cos(back), math.sin(back)])
    first = Polyline(np.array([[0.0, 0.0], cusp]))
    second = Polyline(np.array([cusp, end]), pen=pen)
    return first, Turn(2.0, 0.0, 0.0, math.radians(degrees)), second


@pytest.mark.parametrize('degrees', [180.0, 175.0])
def test_a_path_that_doubles_back_turns_a_width_short_of_the_cusp(degrees):
    legs = _doubling_back(degrees)
    drawn = np.concatenate([legs[0].points, legs[2].points])
    width = 0.2
    first, turn, second = cusps_cut_short(legs, drawn, width, MAX_ROUNDED_RAD)
    assert (turn.x, turn.y) == pytest.approx((2.0 - width, 0.0))
    assert tuple(first.points[-1]) == pytest.approx((turn.x, turn.y))
    assert tuple(second.points[0]) == pytest.approx((turn.x, turn.y))
    # the turn ends facing along the leg it leaves on
    leaving = math.atan2(*(second.points[1] - second.points[0])[::-1])
    assert math.cos(turn.start_heading + turn.sweep_rad - leaving) == pytest.approx(1.0)
    assert math.copysign(1.0, turn.sweep_rad) == 1.0  # the same way round as asked
    line = shapely.LineString(drawn)
    for leg in (first, second):
        assert shapely.distance(line, shapely.points(leg.points)).max() <= width + 1e-9
        assert shapely.distance(line, shapely.LineString(leg.points).segmentize(0.001)
                                ).max() <= width + 1e-9
    saved = legs[0].length + legs[2].length - first.length - second.length
    across = 2.0 * width * math.sin(math.radians(180.0 - degrees) / 2.0)  # the cusp's chord
    assert saved == pytest.approx(2.0 * width - across, rel=1e-6)


def test_a_turn_that_is_rounded_or_changes_the_pen_stays_at_the_cusp():
    legs = _doubling_back(150.0)
    drawn = np.concatenate([legs[0].points, legs[2].points])
    assert cusps_cut_short(legs, drawn, 0.2, MAX_ROUNDED_RAD) == legs
    legs = _doubling_back(180.0, pen=False)
    assert cusps_cut_short(legs, drawn, 0.2, MAX_ROUNDED_RAD) == legs


def test_a_cut_is_at_most_half_of_the_shorter_leg():
    first, turn, second = _doubling_back(180.0)
    short = Polyline(np.array([[2.0, 0.0], [1.9, 0.0]]))
    drawn = np.concatenate([first.points, short.points])
    _, moved, left = cusps_cut_short((first, turn, short), drawn, 0.2, MAX_ROUNDED_RAD)
    assert moved.x == pytest.approx(1.95)
    assert left.length == pytest.approx(0.05)

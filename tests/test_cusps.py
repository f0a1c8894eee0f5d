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


def _headings(legs) -> list[float]:
    """The robot's heading along the legs: each polyline segment's, each turn's end."""
    out = []
    for leg in legs:
        if isinstance(leg, Turn):
            out.append(leg.start_heading + leg.sweep_rad)
        else:
            step = np.diff(leg.points, axis=0)
            out.extend(np.arctan2(step[:, 1], step[:, 0]))
    return out


def _check_cut(cut, drawn, width, sweep, bent=1e-9):
    """`cut` turns where its polylines meet (headings continuous across each turn, no bend
    in a polyline), all the same way round as `sweep` and by as much (less what the sides
    curve within `width`, at most `bent`), within `width` of `drawn`."""
    turns = [leg for leg in cut if isinstance(leg, Turn)]
    assert sum(t.sweep_rad for t in turns) == pytest.approx(sweep, abs=bent)
    assert all(math.copysign(1.0, t.sweep_rad) == math.copysign(1.0, sweep) for t in turns)
    for previous, turn, following in zip(cut[:-2:2], cut[1::2], cut[2::2], strict=True):
        assert tuple(previous.points[-1]) == pytest.approx((turn.x, turn.y))
        assert tuple(following.points[0]) == pytest.approx((turn.x, turn.y))
        arriving, leaving = _headings([previous])[-1], _headings([following])[0]
        assert math.cos(turn.start_heading - arriving) == pytest.approx(1.0)
        assert math.cos(turn.start_heading + turn.sweep_rad - leaving) == pytest.approx(1.0)
    line = shapely.LineString(drawn)
    for leg in cut[::2]:
        assert shapely.distance(line, shapely.LineString(leg.points).segmentize(0.001)
                                ).max() <= width + 1e-9
        bends = np.abs(np.diff(np.unwrap(_headings([leg])))) if len(leg.points) > 2 else [0.0]
        assert max(bends) <= math.radians(1.0) + 1e-9


@pytest.mark.parametrize('degrees', [180.0, 175.0])
def test_a_path_that_doubles_back_turns_a_width_short_of_the_cusp(degrees):
    legs = _doubling_back(degrees)
    drawn = np.concatenate([legs[0].points, legs[2].points])
    width = 0.2
    cut = cusps_cut_short(legs, drawn, width, MAX_ROUNDED_RAD)
    assert (cut[1].x, cut[1].y) == pytest.approx((2.0 - width, 0.0))
    _check_cut(cut, drawn, width, math.radians(degrees))
    # straight back where the legs overlap; across the cusp's chord, turned twice, where not
    assert len(cut) == (3 if degrees == 180.0 else 5)
    polylines = cut[::2]
    saved = legs[0].length + legs[2].length - sum(leg.length for leg in polylines)
    across = 2.0 * width * math.sin(math.radians(180.0 - degrees) / 2.0)  # the cusp's chord
    assert saved == pytest.approx(2.0 * width - across, rel=1e-6)


def test_a_cusp_whose_sides_curve_apart_is_left_along_its_side_not_across_a_bend():
    """The top of a heart: both sides leave the cusp along one line and curve apart, so the
    connection across meets the far side at a bend the follower cannot steer through; it turns
    in place there too."""
    t = np.linspace(0.0, 1.0, 200)
    right = np.column_stack((0.5 * t ** 2, 1.0 - t))[::-1]  # up its right side to the cusp
    left = np.column_stack((-0.5 * t ** 2, 1.0 - t))  # down its left side from the cusp
    arriving, leaving = _headings([Polyline(right)])[-1], _headings([Polyline(left)])[0]
    sweep = (leaving - arriving) % (2.0 * math.pi)  # a left turn
    legs = (Polyline(right), Turn(0.0, 1.0, arriving, sweep), Polyline(left))
    drawn = np.concatenate([right, left])
    width = 0.1
    cut = cusps_cut_short(legs, drawn, width, MAX_ROUNDED_RAD)
    assert len(cut) == 5
    _check_cut(cut, drawn, width, sweep, bent=0.25)
    across = cut[2]
    assert len(across.points) == 2
    assert shapely.distance(shapely.LineString(left), shapely.points(across.points[-1])
                            ) == pytest.approx(0.0, abs=1e-9)


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


def test_every_cusp_of_a_path_is_cut_however_many_legs_the_first_became():
    """A 175 degree cusp becomes five legs (turned twice across its chord); a cusp after it,
    the path's last, is cut short too."""
    first, turn, second = _doubling_back(175.0)
    back = math.radians(5.0)  # the second leg's direction is 175 degrees
    end = second.points[-1]
    third = Polyline(np.array([end, end + 2.0 * np.array([math.cos(back), -math.sin(back)])]))
    legs = (first, turn, second, Turn(float(end[0]), float(end[1]), math.pi - back, math.pi),
            third)
    drawn = np.concatenate([first.points, second.points, third.points])
    cut = cusps_cut_short(legs, drawn, 0.2, MAX_ROUNDED_RAD)
    turns = [leg for leg in cut if isinstance(leg, Turn)]
    assert len(cut) == 7 and len(turns) == 3
    assert math.dist((turns[-1].x, turns[-1].y), end) == pytest.approx(0.2, abs=1e-9)
    _check_cut(cut, drawn, 0.2, math.radians(175.0) + math.pi)

"""Back-to-back moves driven as one request (`core.fleet.chains`): the same path, turned in
place where the drawing turns, the turtles still apart."""

import math

import numpy as np
import pytest
import shapely

from turtle_traj.api.ros_interface import make_request
from turtle_traj.core.fleet.chains import chain, chained, joined
from turtle_traj.core.fleet.moves import Share, routes
from turtle_traj.core.fleet.pieces import pieces_in, request_s
from turtle_traj.core.fleet.timing import Move, simulate
from turtle_traj.core.geometry.path import Polyline, Pose2D, Turn
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.planning import planner
from turtle_traj.core.planning.sketches.base import PlanError
from turtle_traj.core.registry import BY_NAME

CONFIG = DEFAULT_SETTINGS.control
ANCHOR = Pose2D(1.5, 4.0, 0.0)


def _text_plan():
    return planner.plan('text', make_request(BY_NAME['text'], {'text': 'ROS 2', 'height': 1.5}),
                        ANCHOR, DEFAULT_SETTINGS)


def _as_the_node_plans(move: Move, facing: float):
    """The follow-path a trajectory node plans for `move`, from its first point at `facing`."""
    given = {'points': [tuple(point) for point in move.points]}
    if move.corner_angle:
        given['corner_angle'] = move.corner_angle
    start = Pose2D(*move.points[0], facing)
    return planner.plan('follow_path', make_request(BY_NAME['follow_path'], given), start,
                        DEFAULT_SETTINGS).path


def test_one_turtle_draws_the_text_in_fewer_requests_as_the_drawing_does():
    """Alone, a turtle's back-to-back moves all chain. Each pen-down request, as a node plans
    it, draws exactly the drawing's strokes and turns in place exactly where the drawing turns,
    by as much (checked against the drawing's own legs); the time saved is the requests'."""
    plan = _text_plan()
    pieces = pieces_in(plan.path, CONFIG, corner_angle=DEFAULT_SETTINGS.defaults.corner_angle)
    route = routes([Share(tuple(range(len(pieces))), 0.0)], pieces, [ANCHOR], CONFIG)[0]
    timing = simulate([route], [ANCHOR], 0.6)
    moves = chain(timing, 0, [ANCHOR], 0.6, CONFIG)
    assert len(moves) < len(route) / 3
    assert [index for move in moves for index in move.pieces] == list(range(len(pieces)))
    assert sum(move.duration_s for move in moves) == pytest.approx(
        sum(move.duration_s for move in route) - (len(route) - len(moves)) * request_s(CONFIG))

    turns = {(round(leg.x, 9), round(leg.y, 9)): leg.sweep_rad for leg in plan.path.legs
             if isinstance(leg, Turn) and leg.sweep_rad}
    ink = shapely.union_all([shapely.LineString(leg.points) for leg in plan.path.legs
                             if isinstance(leg, Polyline) and leg.pen])
    facing = ANCHOR.theta
    for move in moves:
        if move.pieces:
            legs = _as_the_node_plans(move, facing).legs
            drawn = [leg for leg in legs if isinstance(leg, Polyline)]
            assert sum(leg.length for leg in drawn) == pytest.approx(
                sum(pieces[index].polyline.length for index in move.pieces))
            for leg in drawn:  # on the drawing's strokes, all of it
                assert shapely.distance(ink, shapely.MultiPoint(leg.points)) < 1e-9
            for leg in legs[1:]:  # its turns after the first: the drawing's, where it turns
                if isinstance(leg, Turn):
                    assert leg.sweep_rad == pytest.approx(turns[round(leg.x, 9),
                                                                 round(leg.y, 9)])
            polylines = [pieces[index].polyline for index in move.pieces]
            at_junctions = sum((round(a.points[-1][0], 9), round(a.points[-1][1], 9)) in turns
                               for a, b in zip(polylines, polylines[1:], strict=False))
            assert sum(isinstance(leg, Turn) for leg in legs[1:]) == at_junctions
        facing = move.heading


def test_a_request_mixes_no_pen_states_and_a_way_does_not_turn():
    way = Move(np.array([(1.0, 1.0), (2.0, 1.0)]), 1.0, heading=0.0)
    on = Move(np.array([(2.0, 1.0), (3.0, 1.0)]), 1.0, heading=0.0)
    assert joined([way, Move(on.points, 1.0, pen=True, pieces=(0,))], 0.0, CONFIG) is None
    assert joined([way, on], 0.0, CONFIG).points.tolist() == [[1.0, 1.0], [3.0, 1.0]]
    turned = Move(way.points, 1.0, heading=1.0)  # it turns at its end: a go-to would not
    assert joined([turned, on], 0.0, CONFIG) is None
    up = Move(np.array([(2.0, 1.0), (2.0, 2.0)]), 1.0, heading=math.pi / 2)
    assert joined([way, up], 0.0, CONFIG) is None
    assert joined([way, Move(np.array([(2.5, 1.0), (3.0, 1.0)]), 1.0)], 0.0, CONFIG) is None


def test_pieces_chain_only_where_a_corner_angle_tells_their_turns_from_their_bends():
    """A piece bent by 0.3 rad inside, then a turn of 0.2 rad onto the next: no corner angle
    turns in place at the one and not at the other."""
    bent = Move(np.array([(1.0, 1.0), (2.0, 1.0), (2.0 + math.cos(0.3), 1.0 + math.sin(0.3))]),
                2.0, pen=True, heading=0.3, pieces=(0,))
    end = bent.points[-1]
    onto = Move(np.array([end, end + (math.cos(0.5), math.sin(0.5))]), 1.0, pen=True,
                heading=0.5, pieces=(1,), turns_first=True)
    assert joined([bent, onto], 0.0, CONFIG) is None
    sharper = Move(np.array([end, end + (math.cos(1.3), math.sin(1.3))]), 1.0, pen=True,
                   heading=1.3, pieces=(1,), turns_first=True)
    both = joined([bent, sharper], 0.0, CONFIG)
    assert 0.3 < both.corner_angle < 1.0 and both.pieces == (0, 1)
    assert both.duration_s == pytest.approx(3.0 - request_s(CONFIG))


def test_the_fleets_chained_timing_keeps_the_turtles_apart_and_ends_sooner():
    """The demo's SVG among three turtles: chained where it changes nothing for the others,
    the turtles are still apart at every sampled instant, every piece is drawn once, and the
    drawing ends sooner."""
    from tests.test_fleet_sharing import svg_among
    from tests.test_fleet_timing import _tracks, closest_approach
    from turtle_traj.core.fleet.parking import Parking
    from turtle_traj.core.fleet.refine import refine
    from turtle_traj.core.fleet.sharing import share

    pieces, starts = svg_among(3)
    parking = Parking(pieces, 0.6, DEFAULT_SETTINGS.arena)
    sharing = refine(share(pieces, starts, CONFIG, 0.6, parking=parking), pieces, starts, CONFIG,
                     0.6, parking=parking)
    timing = chained(sharing.timing, starts, 0.6, CONFIG)
    assert timing.makespan_s < sharing.timing.makespan_s - 0.1
    assert sum(map(len, timing.routes)) < sum(map(len, sharing.timing.routes))
    drawn = sorted(index for route in timing.routes for move in route for index in move.pieces)
    assert drawn == list(range(len(pieces)))
    tracks = _tracks(timing.routes, starts, timing, step_s=0.02)
    assert closest_approach(tracks) >= 0.6 - 1e-9


def test_a_travel_turns_in_place_to_face_its_way_however_little():
    """A go-to 0.3 rad off its way turns in place first. One a hair off (0.015 rad over
    0.1 m, where the curve onto the way stays within half a millimetre of it) steers, and
    arrives a little beside its end; the fleet's travels ask for the least corner angle, and
    turn in place first, as the plan times them."""
    from turtle_traj.fleet.link import TRAVEL_CORNER_ANGLE

    start = Pose2D(2.0, 2.0, 0.0)

    def first_leg(angle, distance, **given):
        goal = {'x': 2.0 + distance * math.cos(angle), 'y': 2.0 + distance * math.sin(angle)}
        return planner.plan('go_to', make_request(BY_NAME['go_to'], {**goal, **given}), start,
                            DEFAULT_SETTINGS).path.legs[0]
    turn = first_leg(0.3, 1.0)
    assert isinstance(turn, Turn) and turn.sweep_rad == pytest.approx(0.3)
    assert isinstance(first_leg(0.015, 0.1), Polyline)
    turn = first_leg(0.015, 0.1, corner_angle=TRAVEL_CORNER_ANGLE)
    assert isinstance(turn, Turn) and turn.sweep_rad == pytest.approx(0.015)


def test_a_follow_path_turns_in_place_where_the_request_says():
    """corner_angle in the request overrides the node's parameter (0.35 rad) on a curve's
    samples (bends of 0.2 rad every centimetre); out of range or not a number, it is refused
    with a reason."""
    points = [(2.0 + 0.01 * index, 2.0) for index in range(2)]
    for bend in (0.2, 0.4):
        points.append((points[-1][0] + 0.01 * math.cos(bend),
                       points[-1][1] + 0.01 * math.sin(bend)))
    start = Pose2D(2.0, 2.0, 0.0)

    def turns(**given):
        path = planner.plan('follow_path', make_request(BY_NAME['follow_path'], {
            'points': points, **given}), start, DEFAULT_SETTINGS).path
        return [leg.sweep_rad for leg in path.legs if isinstance(leg, Turn)]
    assert turns() == []
    assert turns(corner_angle=0.1) == [pytest.approx(0.2), pytest.approx(0.2)]
    for bad in (math.nan, 0.001, 4.0):
        with pytest.raises(PlanError, match='corner_angle'):
            turns(corner_angle=bad)

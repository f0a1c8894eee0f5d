"""A drawing's pieces shared out among turtles (`core.fleet.sharing`), against brute force."""

import itertools
import math

import numpy as np
import pytest
import shapely

from turtle_traj.api.ros_interface import make_request
from turtle_traj.core.fleet.pieces import Piece, pieces_in, request_s, travel_s
from turtle_traj.core.fleet.sharing import lower_bound_s, share
from turtle_traj.core.geometry.path import Polyline, Pose2D, Turn
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.planning import planner
from turtle_traj.core.registry import BY_NAME

CONFIG = DEFAULT_SETTINGS.control
ANCHOR = Pose2D(1.5, 4.0, 0.0)


def _text_plan():
    return planner.plan('text', make_request(BY_NAME['text'], {'text': 'ROS 2', 'height': 1.5}),
                        ANCHOR, DEFAULT_SETTINGS)


def test_the_pieces_are_the_drawings_pen_down_legs_in_its_order():
    plan = _text_plan()
    drawn = [leg for leg in plan.path.legs if isinstance(leg, Polyline) and leg.pen]
    whole = pieces_in(plan.path, CONFIG, longest=np.inf)
    assert [piece.polyline for piece in whole] == drawn
    assert all(piece.time_s >= piece.polyline.length / CONFIG.linear_speed for piece in whole)


def test_long_legs_are_cut_into_even_pieces_that_join_into_them():
    plan = planner.plan('star', make_request(BY_NAME['star'], {'size': 1.2}), ANCHOR,
                        DEFAULT_SETTINGS)
    drawn = [leg for leg in plan.path.legs if isinstance(leg, Polyline) and leg.pen]
    pieces = pieces_in(plan.path, CONFIG, longest=0.4)
    assert len(pieces) > len(drawn) and all(p.polyline.length <= 0.4 + 1e-9 for p in pieces)
    joined = iter(pieces)
    for leg in drawn:
        parts, length = [], 0.0
        while length < leg.length - 1e-9:
            parts.append(next(joined).polyline)
            length += parts[-1].length
        assert [p.length for p in parts] == pytest.approx([leg.length / len(parts)] * len(parts))
        assert np.allclose(parts[0].points[0], leg.points[0])
        assert np.allclose(parts[-1].points[-1], leg.points[-1])
        assert all(np.allclose(a.points[-1], b.points[0])
                   for a, b in zip(parts, parts[1:], strict=False))


def test_one_turtle_draws_the_planners_tour_in_the_planners_time():
    """One turtle's share is the whole tour, timed within 2% of what the planner says the
    drawing takes (its pen-up moves are turns and drives as `travel_s` times them), with two
    requests for each piece (the way there, the piece) and each turn in place braked at the
    node's angular deceleration (which the planner's least time leaves out)."""
    plan = _text_plan()
    pieces = pieces_in(plan.path, CONFIG)
    alone = share(pieces, [ANCHOR], CONFIG)
    assert alone.shares[0].pieces == tuple(range(len(pieces)))
    requests_s = 2 * len(pieces) * request_s(CONFIG)
    top, braking = CONFIG.angular_speed, CONFIG.angular_deceleration
    braked_s = sum(min(top / (2.0 * braking), abs(leg.sweep_rad) / top) for leg in
                   plan.path.legs if isinstance(leg, Turn) and abs(leg.sweep_rad) > 1e-6)
    assert alone.makespan_s == pytest.approx(plan.least_time_s(CONFIG) + requests_s + braked_s,
                                             rel=0.02)


def _pieces(count: int, seed: int) -> list[Piece]:
    rng = np.random.default_rng(seed)
    pieces = []
    for _ in range(count):
        start = rng.uniform(2.0, 9.0, 2)
        end = start + rng.uniform(-1.5, 1.5, 2)
        line = Polyline(np.array([start, end]))
        pieces.append(Piece(line, line.length / CONFIG.linear_speed))
    return pieces


def _brute_force(pieces, starts) -> float:
    """The least makespan over every cut of the tour into contiguous parts and every order of
    the turtles along it, each part timed independently here (two requests a piece)."""
    def part_s(part, start):
        total, here = 0.0, start
        for piece in part:
            begin, end = piece.ends(False)
            total += travel_s(here, begin, CONFIG) + piece.time_s + 2 * request_s(CONFIG)
            here = end
        return total
    best = float('inf')
    for cuts in itertools.combinations_with_replacement(range(len(pieces) + 1), len(starts) - 1):
        bounds = [0, *cuts, len(pieces)]
        parts = [pieces[a:b] for a, b in zip(bounds, bounds[1:], strict=False)]
        for order in itertools.permutations(starts):
            best = min(best, max(part_s(part, start)
                                 for part, start in zip(parts, order, strict=True)))
    return best


@pytest.mark.parametrize('seed', range(3))
@pytest.mark.parametrize('turtles', [2, 3])
def test_the_split_is_the_best_contiguous_one(seed, turtles):
    pieces = _pieces(7, seed)
    starts = [Pose2D(1.0 + 4.0 * k, 1.0, 0.0) for k in range(turtles)]
    sharing = share(pieces, starts, CONFIG)
    assert sorted(i for s in sharing.shares for i in s.pieces) == list(range(len(pieces)))
    assert all(list(s.pieces) == list(range(s.pieces[0], s.pieces[0] + len(s.pieces)))
               for s in sharing.shares if s.pieces)  # each a contiguous part
    assert sharing.makespan_s == pytest.approx(_brute_force(pieces, starts), rel=1e-5)
    assert sharing.lower_bound_s <= sharing.makespan_s


def test_another_turtle_never_makes_the_drawing_slower():
    pieces = pieces_in(_text_plan().path, CONFIG)
    starts = [ANCHOR, Pose2D(8.5, 5.5, 0.0), Pose2D(5.5, 8.5, 0.0), Pose2D(5.5, 2.5, 0.0)]
    makespans = [share(pieces, starts[:count], CONFIG).makespan_s for count in range(1, 5)]
    assert all(b <= a + 1e-6 for a, b in zip(makespans, makespans[1:], strict=False))
    assert makespans[-1] < 0.5 * makespans[0]
    assert lower_bound_s(pieces, starts, CONFIG) <= makespans[-1]


def test_no_turtle_is_refused_with_a_reason():
    with pytest.raises(ValueError, match='no turtle'):
        share(_pieces(2, 0), [], CONFIG)


def test_shared_with_a_clearance_the_turtles_keep_it_at_every_instant():
    """The sharing chosen with a clearance comes with the waits that keep the turtles that far
    apart: their motion, sampled from its timing, never brings two closer."""
    from tests.test_fleet_timing import _tracks, closest_approach
    from turtle_traj.core.fleet.moves import routes

    pieces = pieces_in(_text_plan().path, CONFIG)
    starts = [ANCHOR, Pose2D(8.5, 5.5, 0.0), Pose2D(5.5, 8.5, 0.0)]
    sharing = share(pieces, starts, CONFIG, clearance=0.6)
    moves = routes(sharing.shares, pieces, starts, CONFIG)
    assert closest_approach(_tracks(moves, starts, sharing.timing, step_s=0.01)) >= 0.6 - 1e-9
    assert sharing.timing.makespan_s >= sharing.timing.drawn_s >= sharing.makespan_s - 1e-6
    alone = share(pieces, [ANCHOR], CONFIG).makespan_s
    assert sharing.timing.drawn_s < 0.6 * alone


def svg_among(count: int) -> tuple[list[Piece], list[Pose2D]]:
    """The demo's SVG in pieces, and where `up --turtles count` puts the turtles (turtle1 at
    the drawing's start)."""
    from turtle_traj.apps.sim import starting_places

    example = BY_NAME['svg'].example
    plan = planner.plan('svg', make_request(BY_NAME['svg'], dict(example.given)),
                        Pose2D(*example.start), DEFAULT_SETTINGS)
    starts = [Pose2D(*example.start), *(Pose2D(*p) for p in starting_places(count)[1:])]
    return pieces_in(plan.path, CONFIG), starts


def test_refining_with_the_waits_counted_ends_the_svg_sooner_and_keeps_the_clearance():
    """The demo's SVG among three turtles: the split cut for the least makespan without waits
    is refined (cuts moved, parts reversed) to end sooner with them, still apart."""
    from tests.test_fleet_timing import _tracks, closest_approach
    from turtle_traj.core.fleet.moves import routes
    from turtle_traj.core.fleet.parking import Parking
    from turtle_traj.core.fleet.refine import refine

    pieces, starts = svg_among(3)
    parking = Parking(pieces, 0.6, DEFAULT_SETTINGS.arena)
    split = share(pieces, starts, CONFIG, clearance=0.6, parking=parking)
    refined = refine(split, pieces, starts, CONFIG, 0.6, parking=parking)
    # every turtle parked: the drawing is done
    assert refined.timing.makespan_s < split.timing.makespan_s - 1.0
    assert sorted(i for s in refined.shares for i in s.pieces) == list(range(len(pieces)))
    moves = routes(refined.shares, pieces, starts, CONFIG, parking)
    assert closest_approach(_tracks(moves, starts, refined.timing, step_s=0.02)) >= 0.6 - 1e-9


def test_a_stroke_that_ends_a_part_late_goes_to_a_turtle_that_waits_idle_beside_it():
    """Turtle 1 has two strokes, the second 4 m away beside turtle 2, which has none: moving
    cuts cannot help (turtle 2's empty part sits before turtle 1's, so a cut gives it the
    first stroke, far from it). The refinement gives it the far stroke: it draws that, turtle
    1 the near one, and the drawing ends sooner than turtle 1 drawing both (without waits:
    each travels there, turns and draws)."""
    from turtle_traj.core.fleet.moves import Share
    from turtle_traj.core.fleet.refine import refine
    from turtle_traj.core.fleet.sharing import Sharing, _timed

    near = Polyline(np.array([[2.0, 2.0], [3.0, 2.0]]))
    far = Polyline(np.array([[2.0, 6.0], [3.0, 6.0]]))
    pieces = [Piece(polyline, 1.0 / CONFIG.linear_speed) for polyline in (near, far)]
    starts = [Pose2D(2.0, 1.0, 0.0), Pose2D(1.0, 6.0, 0.0)]
    both = _timed(Sharing((Share((0, 1), 0.0), Share((), 0.0)), 0.0), pieces, starts, CONFIG,
                  0.6, (), None, None)
    refined = refine(both, pieces, starts, CONFIG, 0.6)
    assert [share.pieces for share in refined.shares] == [(0,), (1,)]
    # sooner by at least the way between the strokes, less turtle 2's way to the far one
    between = travel_s(pieces[0].ends(False)[1], pieces[1].ends(False)[0], CONFIG)
    approach = travel_s(starts[1], pieces[1].ends(False)[0], CONFIG)
    assert between - approach > 1.0
    assert refined.timing.makespan_s <= both.timing.makespan_s - (between - approach)


def test_a_turtle_that_drew_parks_clear_of_the_drawing_near_where_it_ended():
    """The demo's SVG covers most of the arena: a turtle that ends on it parks at the spot
    nearest its end that keeps the clearance from every piece and from the spots taken before;
    one that ends clear of it stays there; each faces the way it drove there."""
    from turtle_traj.core.fleet.parking import Parking
    from turtle_traj.core.geometry.shapes import Arena

    example = BY_NAME['svg'].example
    plan = planner.plan('svg', make_request(BY_NAME['svg'], dict(example.given)),
                        Pose2D(*example.start), DEFAULT_SETTINGS)
    pieces = pieces_in(plan.path, CONFIG)
    arena = DEFAULT_SETTINGS.arena
    assert isinstance(arena, Arena)
    parking = Parking(pieces, 0.6, arena)
    on = [pieces[0].polyline.points[0], pieces[len(pieces) // 2].polyline.points[0]]
    ends = [Pose2D(*map(float, on[0]), 0.0), Pose2D(*map(float, on[1]), 1.0),
            Pose2D(10.0, 1.0, 0.5)]
    drawn = shapely.MultiLineString([piece.polyline.points for piece in pieces])

    def gap(pose):
        return float(shapely.distance(shapely.Point(pose.x, pose.y), drawn))
    assert gap(ends[0]) < 0.6 and gap(ends[1]) < 0.6 and gap(ends[2]) >= 0.6
    taken: list[Pose2D] = []
    for end in ends:
        spot = parking.spot(end, taken)
        assert gap(spot) >= 0.6 and arena.contains([(spot.x, spot.y)])
        assert all(math.dist((spot.x, spot.y), (t.x, t.y)) >= 0.6 for t in taken)
        # no spot on the grid or straight ahead (every 5 cm) that keeps those distances is
        # nearer
        xs, ys = np.meshgrid(np.arange(arena.min_x + arena.margin, arena.max_x - arena.margin
                                       + 1e-9, 0.25),
                             np.arange(arena.min_y + arena.margin, arena.max_y - arena.margin
                                       + 1e-9, 0.25))
        ahead = [(end.x + k * 0.05 * math.cos(end.theta), end.y + k * 0.05 * math.sin(end.theta))
                 for k in range(1, 81)]
        spots = np.concatenate([np.stack([xs.ravel(), ys.ravel()], axis=1), ahead])
        fine = (shapely.distance(shapely.points(spots), drawn) >= 0.6) & arena.inside(spots)
        for t in taken:
            fine &= np.hypot(*(spots - (t.x, t.y)).T) >= 0.6
        nearest = float(np.hypot(*(spots[fine] - (end.x, end.y)).T).min())
        assert math.dist((spot.x, spot.y), (end.x, end.y)) <= nearest + 1e-9
        if spot != end:
            assert math.isclose(spot.theta, math.atan2(spot.y - end.y, spot.x - end.x))
        taken.append(spot)
    assert taken[2] == ends[2]  # it ended clear of the drawing: it stays


def test_a_turtle_with_nothing_to_draw_that_stands_on_the_drawing_parks_off_it():
    """It would keep the others from the pieces near it for ever; one that stands clear stays."""
    from turtle_traj.core.fleet.moves import Share, routes
    from turtle_traj.core.fleet.parking import Parking

    example = BY_NAME['star'].example
    plan = planner.plan('star', make_request(BY_NAME['star'], dict(example.given)),
                        Pose2D(*example.start), DEFAULT_SETTINGS)
    pieces = pieces_in(plan.path, CONFIG)
    parking = Parking(pieces, 0.6, DEFAULT_SETTINGS.arena)
    on = Pose2D(*map(float, pieces[0].polyline.points[1]), 0.0)
    clear = Pose2D(1.0, 1.0, 0.0)
    assert not parking.clear(on) and parking.clear(clear)
    everything = Share(tuple(range(len(pieces))), 0.0)
    drawer, idle_on, idle_clear = routes([everything, Share((), 0.0), Share((), 0.0)],
                                         pieces, [Pose2D(*example.start), on, clear], CONFIG,
                                         parking)
    assert not idle_clear and idle_on and not any(move.pen for move in idle_on)
    parked = idle_on[-1].end
    drawn = shapely.MultiLineString([piece.polyline.points for piece in pieces])
    assert shapely.distance(shapely.Point(parked), drawn) >= 0.6
    assert math.dist(parked, (clear.x, clear.y)) >= 0.6


def test_twenty_turtles_share_the_svg_apart_in_a_fifth_of_one_turtles_time():
    """The demo's SVG among the 20 turtles `up --turtles 20` places: every piece drawn once,
    the turtles apart at every sampled instant (steps aside included), ending sooner than a
    fifth of one turtle's time."""
    from tests.test_fleet_timing import _tracks, closest_approach
    from turtle_traj.core.fleet.aside import SpotAside
    from turtle_traj.core.fleet.parking import Parking
    from turtle_traj.core.fleet.refine import share_apart

    pieces, starts = svg_among(20)
    arena = DEFAULT_SETTINGS.arena
    ink = shapely.union_all([shapely.LineString(piece.polyline.points) for piece in pieces])
    parking = Parking(pieces, 0.6, arena)
    sharing = share_apart(pieces, starts, CONFIG, 0.6, parking=parking,
                          aside=SpotAside(CONFIG, 0.6, arena, parking))
    drawn = sorted(index for route in sharing.timing.routes for move in route
                   for index in move.pieces)
    assert drawn == list(range(len(pieces)))
    for route in sharing.timing.routes:  # every turtle that moved ends parked clear of it
        if route:
            assert shapely.distance(shapely.Point(route[-1].end), ink) >= 0.6 - 1e-9
    tracks = _tracks(sharing.timing.routes, starts, sharing.timing, step_s=0.02)
    assert closest_approach(tracks) >= 0.6 - 1e-9
    alone = share(pieces, starts[:1], CONFIG).makespan_s
    assert sharing.lower_bound_s <= sharing.timing.makespan_s < 0.2 * alone


def test_pieces_beside_a_turtle_that_stands_still_are_left_undrawn_and_named():
    """A turtle that does not draw stands on the text's first stroke: the pieces within the
    clearance of it are set aside, and the answer names them, in drawing order."""
    from types import SimpleNamespace

    from turtle_traj.core.fleet.run import FleetRun
    from turtle_traj.fleet.in_progress import _verdict

    pieces = pieces_in(_text_plan().path, CONFIG)
    first = pieces[0].polyline.points[0]
    blocker = Pose2D(float(first[0]), float(first[1]), 0.0)
    run = FleetRun(pieces, ['turtle1', 'turtle2'], [Pose2D(1.0, 1.0, 0.0), Pose2D(10.0, 1.0, 0.0)],
                   CONFIG, 0.6, standing=[blocker], arena=DEFAULT_SETTINGS.arena)
    near = {index for index, piece in enumerate(pieces) if shapely.distance(
        shapely.LineString(piece.polyline.points), shapely.Point(first)) < 0.6}
    assert run.blocked == near and 0 in near
    run.drawn = set(range(len(pieces))) - near
    success, _, message = _verdict(SimpleNamespace(run=run, failure=None))
    assert not success
    assert f'pieces {", ".join(str(index + 1) for index in sorted(near))},' in message


def test_at_a_corner_of_the_drawing_the_pieces_own_request_turns_onto_it():
    """A piece the drawing turns onto by more than the corner angle (a follow-path from the
    piece before it turns there in place too) is sent as one request with its turn; a smaller
    turn stays a request of its own."""
    from turtle_traj.core.fleet.moves import Share, routes

    plan = _text_plan()
    corner = DEFAULT_SETTINGS.defaults.corner_angle
    pieces = pieces_in(plan.path, CONFIG, corner_angle=corner)
    sharp = [(leg.x, leg.y) for leg in plan.path.legs
             if isinstance(leg, Turn) and abs(leg.sweep_rad) > corner]
    cornered = [piece for piece in pieces if piece.turned_onto(False)]
    assert 0 < len(cornered) < len(pieces)
    for piece in cornered:  # each begins where the plan turns sharply
        assert min(math.dist(piece.polyline.points[0], at) for at in sharp) < 1e-9
    route = routes([Share(tuple(range(len(pieces))), 0.0)], pieces, [ANCHOR], CONFIG)[0]
    drawn = [index for index, move in enumerate(route) if move.pieces]
    for index in drawn:
        piece = pieces[route[index].pieces[0]]
        before = route[index - 1]
        if piece.turned_onto(False) and before.pieces:  # joined to the piece before it
            begin = piece.ends(False)[0]
            end = pieces[before.pieces[0]].ends(False)[1]
            assert route[index].duration_s == pytest.approx(
                piece.time_s + request_s(CONFIG) + travel_s(end, begin, CONFIG))
    folded = sum(1 for index in drawn if pieces[route[index].pieces[0]].turned_onto(False)
                 and route[index - 1].pieces)
    assert folded > 0
    unfolded = routes([Share(tuple(range(len(pieces))), 0.0)], pieces_in(plan.path, CONFIG),
                      [ANCHOR], CONFIG)[0]
    assert len(unfolded) == len(route) + folded  # one request fewer at each such corner


@pytest.mark.parametrize('seed', range(6))
def test_the_bottleneck_assignment_is_the_least_longest_then_the_least_total(seed):
    """Against every assignment of 4 parts to 6 turtles, on random costs with ties."""
    from turtle_traj.core.fleet.assignment import bottleneck_assignment

    rng = np.random.default_rng(seed)
    costs = rng.integers(1, 12, size=(6, 4)).astype(float)
    turtle_of = bottleneck_assignment(costs)
    assert len(set(turtle_of)) == 4  # a turtle each
    every = [(max(costs[t, p] for p, t in enumerate(turtles)),
              sum(costs[t, p] for p, t in enumerate(turtles)))
             for turtles in itertools.permutations(range(6), 4)]
    longest = min(pair[0] for pair in every)
    total = min(pair[1] for pair in every if pair[0] == longest)
    assert max(costs[t, p] for p, t in enumerate(turtle_of)) == longest
    assert sum(costs[t, p] for p, t in enumerate(turtle_of)) == total

"""Turtles kept apart by timing alone (`core.fleet.timing`), checked by sampling their motion."""

import math

import numpy as np
import pytest

from turtle_traj.core.fleet.timing import Deadlock, Move, simulate
from turtle_traj.core.geometry.path import Pose2D

CLEARANCE = 0.6


def closest_approach(tracks: list[np.ndarray]) -> float:
    """The least distance between two turtles' centres at the same instant, over tracks sampled
    at the same times ((T, 2) each, the shorter ones standing at their last point)."""
    length = max(len(track) for track in tracks)
    padded = [np.concatenate([track, np.repeat(track[-1:], length - len(track), axis=0)])
              for track in tracks]
    nearest = math.inf
    for first in range(len(padded)):
        for second in range(first + 1, len(padded)):
            gaps = np.hypot(*(padded[first] - padded[second]).T)
            nearest = min(nearest, float(gaps.min()))
    return nearest


def _line(a, b, speed: float = 1.0) -> Move:
    points = np.array([a, b], dtype=float)
    return Move(points, float(np.hypot(*(points[1] - points[0]))) / speed)


def _tracks(routes, starts, timing, step_s: float = 0.005) -> list[np.ndarray]:
    """Each turtle's position every `step_s`, moving along each move at an even speed from
    when the timing starts it, standing between moves (computed here, from the timing)."""
    times = np.arange(0.0, timing.makespan_s + step_s, step_s)
    tracks = []
    for route, start, begun in zip(routes, starts, timing.starts_s, strict=True):
        track = np.repeat([[start.x, start.y]], len(times), axis=0)
        for move, at in zip(route, begun, strict=True):
            points = move.points
            lengths = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(points, axis=0).T))))
            share = np.clip((times - at) / max(move.duration_s, 1e-9), 0.0, 1.0)
            along = share * lengths[-1]
            moving = times >= at
            track[moving, 0] = np.interp(along[moving], lengths, points[:, 0])
            track[moving, 1] = np.interp(along[moving], lengths, points[:, 1])
        tracks.append(track)
    return tracks


def _random_routes(rng, starts, moves: int, span: tuple[float, float]) -> list[list[Move]]:
    """From each start, `moves` lines to random points in the square `span` x `span`, each at
    a random speed."""
    routes = []
    for start in starts:
        here, route = (start.x, start.y), []
        for _ in range(moves):
            there = tuple(rng.uniform(*span, 2))
            route.append(_line(here, there, speed=rng.uniform(0.5, 2.0)))
            here = there
        routes.append(route)
    return routes


def test_two_crossing_turtles_take_turns():
    starts = [Pose2D(0.0, 5.0, 0.0), Pose2D(5.0, 0.0, 0.0)]
    routes = [[_line((0, 5), (10, 5))], [_line((5, 0), (5, 10))]]
    timing = simulate(routes, starts, CLEARANCE)
    assert timing.starts_s == ((0.0,), (10.0,))  # the second waits for the first to pass
    assert timing.makespan_s == pytest.approx(20.0)
    assert closest_approach(_tracks(routes, starts, timing)) >= CLEARANCE


def test_turtles_on_paths_apart_never_wait():
    starts = [Pose2D(0.0, 0.0, 0.0), Pose2D(0.0, 2.0, 0.0)]
    routes = [[_line((0, 0), (5, 0))], [_line((0, 2), (5, 2))]]
    timing = simulate(routes, starts, CLEARANCE)
    assert timing.waited_s == (0.0, 0.0) and timing.makespan_s == pytest.approx(5.0)


def test_two_turtles_swapping_places_are_a_deadlock_found_before_they_move():
    starts = [Pose2D(0.0, 0.0, 0.0), Pose2D(3.0, 0.0, 0.0)]
    routes = [[_line((0, 0), (3, 0))], [_line((3, 0), (0, 0))]]
    with pytest.raises(Deadlock, match='turtles 1, 2 each wait'):
        simulate(routes, starts, CLEARANCE)


def test_random_routes_keep_their_clearance_at_every_instant():
    """Of 20 random fleets of three, those that do not block each other for good (most) keep
    their clearance at every sampled instant, and start every move."""
    completed = 0
    for seed in range(20):
        starts = [Pose2D(float(x), 0.0, 0.0) for x in (0.0, 4.0, 8.0)]
        routes = _random_routes(np.random.default_rng(seed), starts, 4, (0.0, 8.0))
        try:
            timing = simulate(routes, starts, CLEARANCE)
        except Deadlock:
            continue
        completed += 1
        assert closest_approach(_tracks(routes, starts, timing)) >= CLEARANCE - 1e-9
        assert [len(begun) for begun in timing.starts_s] == [4, 4, 4]
    assert completed >= 10


def _step_aside():
    from turtle_traj.core.fleet.aside import SpotAside
    from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
    return SpotAside(DEFAULT_SETTINGS.control, CLEARANCE, DEFAULT_SETTINGS.arena)


def test_turtles_swapping_places_step_aside_and_keep_their_clearance():
    """The swap that deadlocks by waiting alone: the turtle in the way steps off and back once
    the other has passed; apart at every instant, every move of theirs driven in order."""
    starts = [Pose2D(3.0, 5.0, 0.0), Pose2D(6.0, 5.0, math.pi)]
    routes = [[_line((3, 5), (6, 5))], [_line((6, 5), (3, 5))]]
    timing = simulate(routes, starts, CLEARANCE, _step_aside())
    assert timing.asides >= 1
    assert closest_approach(_tracks(timing.routes, starts, timing)) >= CLEARANCE - 1e-9
    for given, driven in zip(routes, timing.routes, strict=True):
        assert [move for move in driven if any(move is g for g in given)] == given
    second = timing.routes[1]  # stepped aside, came back, then drove its own move
    assert second[0].end != (6.0, 5.0) and second[1].end == (6.0, 5.0)
    assert second[2] is routes[1][0]
    assert timing.starts_s[1][1] >= timing.starts_s[0][0] + routes[0][0].duration_s


def test_a_turtle_that_may_not_move_is_never_asked_to_step_aside():
    starts = [Pose2D(3.0, 5.0, 0.0), Pose2D(6.0, 5.0, math.pi)]
    routes = [[_line((3, 5), (6, 5))], []]
    with pytest.raises(Deadlock):
        simulate(routes, starts, CLEARANCE, _step_aside(), staying=1)
    assert simulate(routes, starts, CLEARANCE, _step_aside()).routes[1][0].end != (6.0, 5.0)


def test_random_crowded_routes_with_steps_aside_complete_apart():
    """Fleets of eight on random routes in a 5 m square: with steps aside, every fleet ends
    its routes (no deadlock), and keeps the clearance at every sampled instant."""
    asides = 0
    for seed in range(10):
        starts = [Pose2D(2.5 + 1.6 * (k % 4), 2.5 + 5.0 * (k // 4), 0.0) for k in range(8)]
        routes = _random_routes(np.random.default_rng(seed), starts, 3, (2.5, 7.5))
        timing = simulate(routes, starts, CLEARANCE, _step_aside())
        asides += timing.asides
        assert closest_approach(_tracks(timing.routes, starts, timing, 0.01)) >= CLEARANCE - 1e-9
        for given, driven in zip(routes, timing.routes, strict=True):
            kept = [move for move in driven if any(move is g for g in given)]
            assert kept == given  # in order, none lost
            # each move from where the one before left the turtle
            assert all(move.points[0].tolist() == list(before.end)
                       for before, move in zip(driven, driven[1:], strict=False))
    assert asides >= 10  # each fleet needed steps aside: waiting alone would deadlock


def test_a_parked_turtle_pushed_aside_stays_clear_of_the_drawing():
    """turtle2 has parked 1.2 m below a stroke of the drawing, on turtle1's way: it steps
    aside for good, to a spot the clearance from the way and from the drawing (the nearest
    spot off the way alone is too near the stroke)."""
    import shapely

    from turtle_traj.core.fleet.aside import SpotAside
    from turtle_traj.core.fleet.parking import Parking
    from turtle_traj.core.fleet.pieces import Piece
    from turtle_traj.core.geometry.path import Polyline
    from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS

    arena = DEFAULT_SETTINGS.arena
    stroke = shapely.LineString([(3.0, 6.2), (6.5, 6.2)])
    parking = Parking([Piece(Polyline(np.array(stroke.coords)), 3.5)], CLEARANCE, arena)
    starts = [Pose2D(2.0, 5.0, 0.0), Pose2D(4.7, 5.0, 0.0)]
    routes = [[_line((2, 5), (7, 5))], []]
    way = routes[0][0].shape
    for spots, clear in ((parking, True), (None, False)):
        aside = SpotAside(DEFAULT_SETTINGS.control, CLEARANCE, arena, spots)
        timing = simulate(routes, starts, CLEARANCE, aside)
        (off,) = timing.routes[1]  # no way back: it had nothing left to drive
        spot = shapely.Point(off.end)
        assert shapely.distance(spot, way) >= CLEARANCE
        assert (shapely.distance(spot, stroke) >= CLEARANCE) == clear

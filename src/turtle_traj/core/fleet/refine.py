"""A sharing improved with the waits counted: a local search over its cuts and directions. Pure.

The tour split (`sharing.share`) cuts the tour for the least makespan without waits. The waits
that keep the turtles apart depend on where the cuts fall and on which way each turtle draws its
part, so the split is then refined by steepest descent: each round tries every cut next to the
parts of the turtles that park last (`FOCUS_TURTLES`) moved by a few pieces either way, and each
of those parts drawn the other way round, judges each by `simulate` (the times the turtles have
parked, waits and steps aside included), and keeps the best; where none is better, it may
try giving the last or first piece or two of the part that ends last to a turtle that has
nothing to draw (`_given_away`: among many turtles, a stroke that ends a part late may be drawn
sooner by one that waits idle nearby), until nothing is better.
Better compares those times from the latest (the drawing's end) down: a change that lets the
second-last finish sooner without delaying the last is kept, so the search crosses the
plateaus where only the last one counts.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.fleet.chains import chained
from turtle_traj.core.fleet.moves import Share, routes
from turtle_traj.core.fleet.parking import Parking
from turtle_traj.core.fleet.pieces import Piece, travel_s
from turtle_traj.core.fleet.sharing import Sharing, candidates
from turtle_traj.core.fleet.timing import Deadlock, StepAside, Timing, simulate
from turtle_traj.core.geometry.path import Pose2D

SHIFTS = (1, 2, 4, 8)  # pieces a cut is moved by, either way
MAX_ROUNDS = 40
FOCUS_TURTLES = 2  # each round changes the parts of the turtles that park last, this many
NEAREST_IDLE = 2  # a part's end is offered to this many of the turtles with none, the nearest
GIVEN = (1, 2)  # pieces at a part's end offered so (each more offered costs more to judge)


@dataclass(frozen=True)
class _Part:
    turtle: int
    first: int
    stop: int
    reverse: bool


def refine(sharing: Sharing, pieces: Sequence[Piece], starts: Sequence[Pose2D],
           config: ControlConfig, clearance: float, standing: Sequence[Pose2D] = (),
           parking: Parking | None = None, aside: StepAside | None = None,
           made: dict | None = None, give_away: bool = True,
           judgements: dict | None = None) -> Sharing:
    """`sharing` (judged with `clearance`: its `timing` set) improved while a neighbour ends
    the drawing sooner, pieces given to turtles with none too where `give_away`; `standing`,
    `parking`, `aside` and `made` as for `candidates`. `judgements` keeps each sharing judged,
    for later calls on the same pieces and turtles (a refinement carried on, as `share_apart`'s
    with pieces given away, judges its first sharing and its neighbours again)."""
    assert sharing.timing is not None
    judgements = {} if judgements is None else judgements

    def judged(parts: list[_Part]) -> tuple[tuple[float, ...], Sharing] | None:
        key = (sharing.lower_bound_s, tuple(parts))
        if key not in judgements:
            judgements[key] = judged_afresh(parts)
        return judgements[key]

    def judged_afresh(parts: list[_Part]) -> tuple[tuple[float, ...], Sharing] | None:
        candidate = _sharing(parts, sharing.lower_bound_s, len(starts))
        moves = routes(candidate.shares, pieces, starts, config, parking, made)
        try:
            timing = simulate([*moves, *([] for _ in standing)], [*starts, *standing],
                              clearance, aside, len(standing))
        except Deadlock:
            return None
        return _finishes(timing), replace(candidate, shares=tuple(
            replace(part, time_s=_drawing_s(route)) for part, route in zip(
                candidate.shares, timing.routes, strict=False)), timing=timing)

    parts = _parts_of(sharing)
    first = judged(parts)
    if first is None:
        return sharing
    (best_key, best) = first
    for _ in range(MAX_ROUNDS):
        assert best.timing is not None
        latest = sorted(range(len(starts)), key=lambda turtle: -best.timing.ends_s[turtle])
        focus = latest[:FOCUS_TURTLES]
        found = [(judgement, neighbour)
                 for neighbour in _neighbours(parts, len(pieces), set(focus))
                 if (judgement := judged(neighbour)) is not None]
        better = min(found, key=lambda pair: pair[0][0], default=None)
        if give_away and (better is None or better[0][0] >= best_key):
            # else pieces given to a turtle that waits idle
            found = [(judgement, neighbour) for neighbour in _given_away(
                parts, latest[0], pieces, starts, config, max(best.timing.ends_s))
                if (judgement := judged(neighbour)) is not None]
            better = min(found, key=lambda pair: pair[0][0], default=None)
        if better is None or better[0][0] >= best_key:
            break
        (best_key, best), parts = better
    return best


def _finishes(timing: Timing) -> tuple[float, ...]:
    """When each turtle has parked, latest first (to the microsecond: a change smaller than
    that is no change): the drawing is done at the first."""
    return tuple(sorted((round(end, 6) for end in timing.ends_s), reverse=True))


def _drawing_s(route: Sequence) -> float:
    """A route's nominal time to its last piece's end (its way home left out)."""
    last = max((index for index, move in enumerate(route) if move.pieces), default=-1)
    return sum(move.duration_s for move in route[:last + 1])


def _parts_of(sharing: Sharing) -> list[_Part]:
    """The parts in tour order (a turtle without pieces holds an empty part where it was)."""
    parts, at = [], 0
    for turtle, part in sorted(enumerate(sharing.shares),
                               key=lambda item: item[1].pieces[0] if item[1].pieces else -1):
        first = part.pieces[0] if part.pieces else at
        stop = part.pieces[-1] + 1 if part.pieces else at
        parts.append(_Part(turtle, first, stop, part.reverse))
        at = stop
    return parts


def _sharing(parts: list[_Part], bound: float, turtles: int) -> Sharing:
    shares = [Share((), 0.0)] * turtles
    for part in parts:
        shares[part.turtle] = Share(tuple(range(part.first, part.stop)), 0.0, part.reverse)
    return Sharing(tuple(shares), bound)


def _neighbours(parts: list[_Part], count: int, focus: set[int]) -> Iterator[list[_Part]]:
    """Every cut next to a part of a turtle in `focus` moved by each of SHIFTS either way
    (parts may empty), every such part reversed."""
    for index in range(len(parts) - 1):
        left, right = parts[index], parts[index + 1]
        if left.turtle not in focus and right.turtle not in focus:
            continue
        for shift in (*SHIFTS, *(-s for s in SHIFTS)):
            cut = left.stop + shift
            if left.first <= cut <= right.stop and 0 <= cut <= count:
                yield [*parts[:index], replace(left, stop=cut), replace(right, first=cut),
                       *parts[index + 2:]]
    for index, part in enumerate(parts):
        if part.stop > part.first and part.turtle in focus:
            yield [*parts[:index], replace(part, reverse=not part.reverse), *parts[index + 1:]]


def _given_away(parts: list[_Part], turtle: int, pieces: Sequence[Piece],
                starts: Sequence[Pose2D], config: ControlConfig,
                latest_s: float) -> Iterator[list[_Part]]:
    """`turtle`'s part with its last or first pieces (each of GIVEN, fewer than it has) given
    to one of the NEAREST_IDLE turtles without pieces nearest them, drawn from its end nearer
    that turtle, where the turtle could get there and draw them before `latest_s` (the
    drawing's end now) without waiting: among many turtles, a stroke that ends a part late may
    be drawn sooner by one that waits idle."""
    idle = [part for part in parts if part.stop == part.first]
    part = next(each for each in parts if each.turtle == turtle)
    size = part.stop - part.first
    for count, at_end in itertools.product([c for c in GIVEN if c < size], (True, False)):
        first, stop = ((part.stop - count, part.stop) if at_end
                       else (part.first, part.first + count))
        ends = [pieces[first].ends(False)[0], pieces[stop - 1].ends(False)[1]]
        nearest = sorted(idle, key=lambda other: min(
            math.dist((starts[other.turtle].x, starts[other.turtle].y), (end.x, end.y))
            for end in ends))[:NEAREST_IDLE]
        kept = replace(part, stop=first) if at_end else replace(part, first=stop)
        for other in nearest:
            start = starts[other.turtle]
            # drawn from its end nearer the turtle
            reverse = (math.dist((start.x, start.y), (ends[1].x, ends[1].y))
                       < math.dist((start.x, start.y), (ends[0].x, ends[0].y)))
            begin = pieces[stop - 1].ends(True)[0] if reverse else ends[0]
            if (travel_s(start, begin, config)
                    + sum(piece.time_s for piece in pieces[first:stop]) >= latest_s):
                continue
            rest = [each for each in parts if each is not other]
            at = rest.index(part)
            given = _Part(other.turtle, first, stop, reverse)
            yield [*rest[:at], *((kept, given) if at_end else (given, kept)), *rest[at + 1:]]


def share_apart(pieces: Sequence[Piece], starts: Sequence[Pose2D], config: ControlConfig,
                clearance: float, standing: Sequence[Pose2D] = (),
                parking: Parking | None = None, aside: StepAside | None = None) -> Sharing:
    """The pieces shared out among turtles at `starts`, kept `clearance` apart (`candidates`):
    each of the `REFINED_CANDIDATES` best refined with the waits counted (cuts and directions),
    the best of them refined on with pieces given to turtles that have none (which costs the
    most to judge, so once), each with its back-to-back moves chained into one request where
    that changes nothing for the others (`chains`), and the one that ends soonest.

    :raises Deadlock: every sharing tried would deadlock.
    """
    made: dict = {}  # the moves, made once for every sharing judged
    found = candidates(pieces, starts, config, clearance, standing, parking, aside, made)
    everyone = [*starts, *standing]

    def with_chains(sharing: Sharing) -> Sharing:
        assert sharing.timing is not None
        return replace(sharing, timing=chained(sharing.timing, everyone, clearance, config,
                                               aside, len(standing)))
    judgements: dict = {}
    tried = [refine(sharing, pieces, starts, config, clearance, standing, parking, aside, made,
                    give_away=False, judgements=judgements)
             for sharing in found[:REFINED_CANDIDATES]]
    best = min(tried, key=lambda sharing: _finishes(sharing.timing))
    given = refine(best, pieces, starts, config, clearance, standing, parking, aside, made,
                   judgements=judgements)
    return min((with_chains(sharing) for sharing in [*tried, given]),
               key=lambda sharing: _finishes(sharing.timing))


REFINED_CANDIDATES = 3

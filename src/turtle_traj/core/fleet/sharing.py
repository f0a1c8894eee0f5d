"""A drawing's pieces shared out among several turtles, for the least makespan. Pure Python.

The drawing's pieces, in the planner's order, are one tour (`pieces.pieces_in`).

Sharing them out is a min-max multiple travelling salesman problem (NP-hard). We split the tour
(Frederickson, Hecht and Kim's k-SPLITOUR, "Approximation algorithms for some routing problems",
SIAM J. Computing 7(2), 1978): each turtle draws one contiguous part of it, so each keeps the
tour's short travel, and only the travel to its part's first piece is new. The parts are cut
for the least makespan by a binary search over it (each trial fills the parts greedily in tour
order), for every order of the turtles along the tour (up to `EXHAUSTIVE_TURTLES`; beyond, for
the whole fleet and for the shares of it nearest the drawing in `SUBSET_SHARES`, each part takes
the nearest turtle left, then its split's parts are given to the turtles by a bottleneck
assignment (`assignment`) and the tour split again for that order, while that changes: among
many turtles, fewer may crowd the drawing less). With a clearance, the orders whose splits end
soonest (`SIMULATED_ORDERS`; beyond `EXHAUSTIVE_TURTLES`, all) are then judged with the waits
that keep the turtles apart, the first ones with their cuts loosened a little too.

A lower bound of the makespan (`lower_bound_s`) is the larger of the longest piece (with the
travel to it from the nearest start) and all the drawing shared among turtles that cannot begin
before they reach it, each piece with its request and the least turn onto it. It leaves out the
crowding: where turtles must wait for each other, the bench shows how far the sharing is from it.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace

import numpy as np

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.fleet.assignment import bottleneck_assignment
from turtle_traj.core.fleet.moves import Share, routes
from turtle_traj.core.fleet.parking import Parking
from turtle_traj.core.fleet.pieces import Piece, request_s, travel_s
from turtle_traj.core.fleet.timing import Deadlock, StepAside, Timing, simulate
from turtle_traj.core.geometry.path import Pose2D


@dataclass(frozen=True)
class Sharing:
    """The pieces shared out: a part for each turtle, in the order the turtles were given."""

    shares: tuple[Share, ...]
    lower_bound_s: float
    timing: Timing | None = None  # with a clearance: when each turtle starts each move


    @property
    def makespan_s(self) -> float:
        return max(share.time_s for share in self.shares)


EXHAUSTIVE_TURTLES = 5  # every order of up to this many turtles along the tour is tried
_SEARCH_STEPS = 30  # halvings of the bracket: to a millionth of its width


class _Tour:
    """The pieces in tour order, with what each costs drawn right after the one before it (the
    travel from there included): computed once, for every cut tried."""

    def __init__(self, pieces: Sequence[Piece], config: ControlConfig) -> None:
        self.pieces, self.config = pieces, config
        ends = [piece.ends(False) for piece in pieces]
        self.begins = [begin for begin, _ in ends]
        self.after = [0.0, *(travel_s(ends[index - 1][1], ends[index][0], config)
                             + pieces[index].time_s + 2 * request_s(config)
                             for index in range(1, len(pieces)))]

    def first_s(self, start: Pose2D, index: int) -> float:
        """A turtle at `start` getting to piece `index` and drawing it."""
        return (travel_s(start, self.begins[index], self.config) + self.pieces[index].time_s
                + 2 * request_s(self.config))

    def part_s(self, first: int, stop: int, start: Pose2D) -> float:
        """A turtle at `start` drawing pieces[first:stop]."""
        if first >= stop:
            return 0.0
        total = self.first_s(start, first)
        for index in range(first + 1, stop):  # summed as `cuts` sums, to the last bit
            total += self.after[index]
        return total

    def cuts(self, starts: Sequence[Pose2D], limit: float) -> list[int] | None:
        """Where the tour is cut so that each turtle in `starts`' order draws one part within
        `limit` (greedily, as far as each can reach), or None if it cannot be."""
        cuts, stop = [0], 0
        for index, start in enumerate(starts):
            last, first, total = index == len(starts) - 1, stop, 0.0
            while stop < len(self.pieces):
                more = total + (self.first_s(start, stop) if stop == first
                                else self.after[stop])
                if more > limit and not last:
                    break
                total, stop = more, stop + 1
            if total > limit:
                return None
            cuts.append(stop)
        return cuts

    def split(self, starts: Sequence[Pose2D], low: float,
              high: float) -> tuple[float, list[int]]:
        """The least makespan within [low, high] found by halving, and its cuts."""
        best = self.cuts(starts, high)
        for _ in range(_SEARCH_STEPS):
            middle = 0.5 * (low + high)
            cuts = self.cuts(starts, middle)
            if cuts is None:
                low = middle
            else:
                high, best = middle, cuts
        return max(self.part_s(a, b, start)
                   for a, b, start in zip(best[:-1], best[1:], starts, strict=True)), best


SIMULATED_ORDERS = 6  # with a clearance, the orders whose splits end soonest without waits
# that are judged with them (more, until one does not deadlock)
LOOSER_STEPS, LOOSER_SLACK = 8, 0.04  # cuts also tried with the limit raised 4 %, 8 %, ...


def _looser(tour: _Tour, starts: Sequence[Pose2D], least: float,
            cuts: list[int]) -> list[list[int]]:
    """`cuts`, then the different cuts the greedy fill makes with looser limits."""
    tried = [cuts]
    for step in range(1, LOOSER_STEPS + 1):
        looser = tour.cuts(starts, least * (1.0 + LOOSER_SLACK * step))
        if looser is not None and looser not in tried:
            tried.append(looser)
    return tried


def _orders(starts: Sequence[Pose2D], tour: _Tour, low: float,
            high: float) -> Iterator[tuple[int, ...]]:
    """The orders of the turtles along the tour to try: all of them for a few turtles; else,
    for the whole fleet and for the `SUBSET_SHARES` of it nearest the drawing, each part in
    turn taking the turtle left nearest the tour's next stretch, then the parts of its split
    given to the turtles by a bottleneck assignment, and split again, while that changes."""
    if len(starts) <= EXHAUSTIVE_TURTLES:
        yield from itertools.permutations(range(len(starts)))
        return
    begins = tour.begins
    nearest_piece = [min(math.dist((s.x, s.y), (b.x, b.y)) for b in begins) for s in starts]
    by_distance = sorted(range(len(starts)), key=lambda k: nearest_piece[k])
    sizes = sorted({max(EXHAUSTIVE_TURTLES, round(share * len(starts)))
                    for share in SUBSET_SHARES}, reverse=True)
    for size in sizes:
        left, order = set(by_distance[:size]), []
        for part in range(size):
            anchor = begins[min(part * len(begins) // size, len(begins) - 1)]
            nearest = min(sorted(left), key=lambda k: math.dist((starts[k].x, starts[k].y),
                                                                (anchor.x, anchor.y)))
            order.append(nearest)
            left.remove(nearest)
        tried = {tuple(order)}
        yield tuple(order)
        for _ in range(REASSIGNMENTS):
            _, cuts = tour.split([starts[k] for k in order], low, high)
            costs = np.array([[tour.part_s(first, stop, start)
                               for first, stop in zip(cuts, cuts[1:], strict=False)]
                              for start in starts])
            order = bottleneck_assignment(costs)
            if tuple(order) in tried:
                break
            tried.add(tuple(order))
            yield tuple(order)


REASSIGNMENTS = 4  # beyond EXHAUSTIVE_TURTLES: rounds of splitting and assigning again
SUBSET_SHARES = (1.0, 0.75, 0.5, 0.35, 0.25)  # beyond EXHAUSTIVE_TURTLES: the shares of the
# fleet tried


def share(pieces: Sequence[Piece], starts: Sequence[Pose2D], config: ControlConfig,
          clearance: float | None = None, standing: Sequence[Pose2D] = (),
          parking: Parking | None = None, aside: StepAside | None = None) -> Sharing:
    """The best of `candidates`.

    :raises Deadlock: with a clearance, every candidate would deadlock.
    """
    return candidates(pieces, starts, config, clearance, standing, parking, aside)[0]


def candidates(pieces: Sequence[Piece], starts: Sequence[Pose2D], config: ControlConfig,
               clearance: float | None = None, standing: Sequence[Pose2D] = (),
               parking: Parking | None = None, aside: StepAside | None = None,
               made: dict | None = None) -> list[Sharing]:
    """The pieces of one turtle's tour (`pieces`, in its order) shared out among turtles
    standing at `starts` (see the module). With a `clearance`, each candidate is judged by when
    its turtles end with the waits that keep them that far apart (`timing.simulate`), and one
    that would deadlock is passed over; `standing` are turtles that do not draw, kept clear of;
    `parking`, where each parks once it drew (`moves.routes`); `aside`, where a turtle in the
    way of another steps aside (`timing.simulate`); `made`, the moves made so far
    (`moves.routes`). The sharings tried, the soonest to end first.

    :raises Deadlock: with a clearance, every candidate would deadlock.
    """
    if not starts:
        raise ValueError('no turtle to share the pieces with')
    tour = _Tour(pieces, config)
    bound = lower_bound_s(pieces, starts, config)
    alone = max(tour.part_s(0, len(pieces), start) for start in starts)
    splits = sorted(((tour.split([starts[k] for k in order], bound, alone), order)
                     for order in _orders(starts, tour, bound, alone)),
                    key=lambda split: split[0][0])
    judged: list[tuple[float, int, Sharing]] = []
    judged_orders = (1 if clearance is None else SIMULATED_ORDERS
                     if len(starts) <= EXHAUSTIVE_TURTLES else len(splits))
    for rank, ((least, cuts), order) in enumerate(splits):
        if rank >= judged_orders and judged:
            break  # the orders whose splits end soonest without waits are judged with them
        # with waits, parts a little longer for the first turtles may end sooner
        tried = ([cuts] if clearance is None or rank >= SIMULATED_ORDERS
                 else _looser(tour, [starts[k] for k in order], least, cuts))
        for cuts in tried:
            parts = dict(zip(order, zip(cuts, cuts[1:], strict=False), strict=True))
            sharing = Sharing(tuple(Share(tuple(range(*parts.get(turtle, (0, 0)))),
                                          tour.part_s(*parts.get(turtle, (0, 0)),
                                                      starts[turtle]))
                                    for turtle in range(len(starts))), bound)
            if clearance is not None:
                sharing = _timed(sharing, pieces, starts, config, clearance, standing, parking,
                                 aside, made)
            if sharing is not None:
                ends_s = sharing.timing.makespan_s if sharing.timing else sharing.makespan_s
                judged.append((round(ends_s, 9), len(judged), sharing))
    if not judged:
        raise Deadlock(f'every way of sharing the drawing among {len(starts)} turtles has two '
                       'of them wait for each other for ever')
    return [sharing for _, _, sharing in sorted(judged, key=lambda item: item[:2])]


def _timed(sharing: Sharing, pieces: Sequence[Piece], starts: Sequence[Pose2D],
           config: ControlConfig, clearance: float, standing: Sequence[Pose2D],
           parking: Parking | None, aside: StepAside | None,
           made: dict | None = None) -> Sharing | None:
    """`sharing` with the timing that keeps its turtles apart; None if it would deadlock."""
    try:
        timing = simulate([*routes(sharing.shares, pieces, starts, config, parking, made),
                           *([] for _ in standing)], [*starts, *standing], clearance, aside,
                          len(standing))
    except Deadlock:
        return None
    return replace(sharing, timing=timing)


def lower_bound_s(pieces: Sequence[Piece], starts: Sequence[Pose2D],
                  config: ControlConfig) -> float:
    """No sharing ends sooner, however near the turtles come: the longest piece, reached from
    the nearest start at the earliest; and all the drawing shared among the turtles, none of
    which draws before it could reach the drawing (the travel from where they stand)."""
    if not pieces:
        return 0.0
    begins = [[piece.ends(reverse)[0] for reverse in (False, True)] for piece in pieces]
    longest = max(piece.time_s + min(travel_s(start, begin, config)
                                      for start in starts for begin in begun)
                  for piece, begun in zip(pieces, begins, strict=True))
    reach = sorted(min(travel_s(start, begin, config) for begun in begins for begin in begun)
                   for start in starts)
    return max(longest, _shared_s(_work_s(pieces, starts, config), reach))


def _work_s(pieces: Sequence[Piece], starts: Sequence[Pose2D], config: ControlConfig) -> float:
    """What drawing every piece costs at least: its drawing, its request and the turn onto it
    from the nearest pose it could be begun from (another piece's end, or a start)."""
    ends = [[piece.ends(reverse) for reverse in (False, True)] for piece in pieces]
    total = 0.0
    for index, piece in enumerate(pieces):
        before = [*starts, *(end for other, both in enumerate(ends) if other != index
                             for _, end in both)]
        total += piece.time_s + request_s(config) + min(
            travel_s(pose, begin, config) for begin, _ in ends[index] for pose in before)
    return total


def _shared_s(work: float, reach: Sequence[float]) -> float:
    """The least M for which turtles able to begin at `reach` (ascending) have `work` of time
    between them: the sum over them of max(0, M - reach) reaches it."""
    shared = math.inf
    for count in range(1, len(reach) + 1):
        shared = (work + sum(reach[:count])) / count
        if count == len(reach) or shared <= reach[count]:
            break
    return shared

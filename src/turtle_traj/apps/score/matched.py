"""The exact follower given another controller's error: on each course, for each other
controller that finishes it off the path, the exact follower runs again with that controller's
maximum error as its `corner_tolerance`. Is it then no slower, and within that error? That is
the trade a user makes, measured: who is ahead at equal error. Beside each, on the courses that
give their path as points (`follow_path`), the minimum-time limit at that tolerance
(`core.planning.min_time`): how far the exact follower is from the fastest the robot can go;
and on a base with inertia, the exact follower once more with `corner_planning` set to
`minimum_time` (the node plans by that limit itself, in seconds of CPU rather than tenths).
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from turtle_traj.apps.score.courses import Course
from turtle_traj.apps.score.runner import Result, run_course
from turtle_traj.core.control.controllers.catalogue import EXACT
from turtle_traj.core.parameters.table import PARAMETER
from turtle_traj.core.planning import planner
from turtle_traj.core.planning.min_time import minimum_time

LARGEST_TOLERANCE_M = PARAMETER['corner_tolerance'].high
LIMIT_NODES = 60  # the limit's intervals, at first
LIMIT_MOST_NODES = 480  # and at most, doubled while its motion leaves the tube between nodes


@dataclass(frozen=True)
class Matched:
    """The exact follower at a `rival`'s maximum error (`exact`), on one course."""

    rival: Result
    exact: Result
    tolerance_m: float
    limit_s: float | None = None  # the minimum-time limit at `tolerance_m`, where computed
    by_limit: Result | None = None  # planned with corner_planning 'minimum_time', where it can

    @property
    def ahead(self) -> bool:
        """It finished no slower than the rival, within the rival's error."""
        return (self.exact.success and self.exact.time_s <= self.rival.time_s
                and self.exact.max_mm <= self.rival.max_mm)


def matched_runs(course: Course, results: Sequence[Result], work_dir: Path) -> list[Matched]:
    """The exact follower at each other controller's error on `course` (none where the request
    takes no tolerance, or the exact follower was not scored)."""
    plain = {r.controller: r for r in results}
    if EXACT not in plain or not hasattr(course.request, 'corner_tolerance'):
        return []
    matched = []
    for rival in results:
        if rival.controller == EXACT or not rival.success or rival.max_mm <= plain[EXACT].max_mm:
            continue
        tolerance = min(rival.max_mm / 1e3, LARGEST_TOLERANCE_M)
        request = copy.copy(course.request)
        request.corner_tolerance = tolerance
        result = run_course(replace(course, request=request), EXACT, work_dir=work_dir)
        limit = limit_s(course, tolerance)
        by_limit = (run_course(_planned_by_limit(replace(course, request=request)), EXACT,
                               work_dir=work_dir) if limit is not None
                    and planner.plans_by_limit(course.settings.control) else None)
        matched.append(Matched(rival, replace(result, controller=f'{EXACT} @ {rival.controller}'),
                               tolerance, limit, by_limit))
    return matched


def _planned_by_limit(course: Course) -> Course:
    """`course` with the node's `corner_planning` set to 'minimum_time'."""
    settings = course.settings
    return replace(course, settings=replace(
        settings, defaults=replace(settings.defaults, minimum_time_corners=True)))


def limit_s(course: Course, tolerance_m: float) -> float | None:
    """The minimum-time limit of a course whose request gives its path as points, from its
    start pose at rest, within `tolerance_m` of the path as the planner draws it (from the
    start, closed where asked), at the run's speeds and accelerations; None for other
    courses, or where the solver did not converge."""
    if not getattr(course.request, 'points', None):
        return None
    plan = planner.plan(course.trajectory, course.request, course.start, course.settings)
    limits = plan.control(course.settings.control).limits
    limit = minimum_time(plan.drawn_points(), tolerance_m, limits,
                         start_heading=course.start.theta, nodes=LIMIT_NODES,
                         most_nodes=LIMIT_MOST_NODES)
    return limit.time_s if limit.solved else None


def format_matched(matched: Sequence[Matched]) -> str:
    """A row per rival and course: its time and error, then the exact follower's at it, the
    limit's time, and where planned by the limit, the exact follower's time and error so."""
    lines = [f"{'course':18} {'rival':14} {'time s':>7} {'max mm':>8}   {'exact at it':>11} "
             f"{'max mm':>8} {'ahead':>5}   {'limit s':>7} {'x limit':>7}   "
             f"{'min-time plan':>13} {'max mm':>8} {'x limit':>7}"]
    for m in matched:
        exact = m.exact
        time = f'{exact.time_s:11.2f}' if exact.success else f"{'NO':>11}"
        limit = (f'{m.limit_s:7.2f} {_times(exact, m.limit_s):>7}' if m.limit_s
                 else f"{'-':>7} {'-':>7}")
        by_limit = (f'{_time(m.by_limit):>13} {m.by_limit.max_mm:8.2f} '
                    f'{_times(m.by_limit, m.limit_s):>7}' if m.by_limit and m.limit_s
                    else f"{'-':>13} {'-':>8} {'-':>7}")
        lines.append(f'{m.rival.course:18} {m.rival.controller:14} {m.rival.time_s:7.2f} '
                     f"{m.rival.max_mm:8.2f}   {time} {exact.max_mm:8.2f} "
                     f"{'yes' if m.ahead else 'no':>5}   {limit}   {by_limit}")
    ahead = sum(m.ahead for m in matched)
    lines.append(f'the exact follower is ahead at equal error in {ahead} of {len(matched)}')
    return '\n'.join(lines)


def _time(result: Result) -> str:
    return f'{result.time_s:.2f}' if result.success else 'NO'


def _times(result: Result, limit_s: float) -> str:
    """`result`'s time over the limit's, or '-' where it did not finish."""
    return f'{result.time_s / limit_s:.3f}' if result.success else '-'

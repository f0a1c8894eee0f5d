"""`turtle-traj score`: run the standard courses for one or more controllers, in-process and
in lock-step (the same figures on every run), and rank them.

The courses are `courses.standard_courses`; every figure is measured from the poses
(`runner`). The MuJoCo base's courses need MuJoCo (`pip install turtle_traj[physics]`); without
it they are left out, with a note.
"""

from __future__ import annotations

import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

from turtle_traj.api.controllers import UnknownController, resolve
from turtle_traj.apps.score.courses import ROBOTS, standard_courses
from turtle_traj.apps.score.matched import Matched, format_matched, matched_runs
from turtle_traj.apps.score.report import (
    format_ranking,
    format_table,
    ranking,
    write_csv,
    write_plots,
)
from turtle_traj.apps.score.runner import Result, run_course
from turtle_traj.core.control.controllers.catalogue import SHIPPED

DEFAULT_CONTROLLERS = tuple(SHIPPED)


def _has_mujoco() -> bool:
    try:
        import mujoco  # noqa: F401
    except ImportError:
        return False
    return True


def _progress(done: int, total: int, what: str) -> None:
    """A progress bar on stderr (one line, redrawn; a line per step when not a terminal)."""
    width = 30
    filled = width * done // max(total, 1)
    line = f'[{"#" * filled}{"." * (width - filled)}] {done}/{total} {what}'
    if sys.stderr.isatty():
        print(f'\r{line:<79}', end='' if done < total else '\n', file=sys.stderr, flush=True)
    else:
        print(line, file=sys.stderr, flush=True)


def score(controllers: Sequence[str], *, robots: Sequence[str] = ROBOTS,
          courses: Sequence[str] = (), progress=_progress, matched: bool = False
          ) -> tuple[list[Result], list[Matched]]:
    """Every chosen course for every controller (courses: names, or all), and with `matched`
    the exact follower at each other's error (`matched.matched_runs`).

    :raises UnknownController: a name that is not a controller.
    """
    for name in controllers:
        resolve(name)
    chosen = [c for c in standard_courses(tuple(robots)) if not courses or c.name in courses]
    unknown = set(courses) - {c.name for c in chosen}
    if unknown:
        raise ValueError(f"no course {', '.join(sorted(unknown))}: the courses are "
                         f"{', '.join(c.name for c in standard_courses(tuple(robots)))}")
    results, matches, total = [], [], len(chosen) * len(controllers)
    with tempfile.TemporaryDirectory() as work:
        for course in chosen:
            for controller in controllers:
                progress(len(results), total, f'{course.name}: {controller}')
                results.append(run_course(course, controller, work_dir=Path(work)))
            if matched:
                matches += matched_runs(course, results[-len(controllers):], Path(work))
    progress(total, total, 'done')
    return results, matches


def run(controllers: Sequence[str], output: Path | None, courses: Sequence[str] = (), *,
        matched: bool = False) -> int:
    """The command: tables and ranking on stdout (and the matched runs', with `matched` or an
    `output`), files in `output`; 0, or 2 on a bad name."""
    robots = ROBOTS if _has_mujoco() else tuple(r for r in ROBOTS if r != 'base')
    if robots != ROBOTS:
        print('(no MuJoCo: the base courses are left out; pip install turtle_traj[physics])')
    try:
        results, matched = score(list(dict.fromkeys(controllers)) or DEFAULT_CONTROLLERS,
                                 robots=robots, courses=courses,
                                 matched=matched or output is not None)
    except (UnknownController, ValueError) as error:
        print(f'turtle-traj score: {error}', file=sys.stderr)
        return 2
    print(format_table(results))
    print()
    print(format_ranking(ranking(results)))
    if matched:
        print('\nThe exact follower with each other controller\'s maximum error as its '
              'corner_tolerance:')
        print(format_matched(matched))
    if output is not None:
        output.mkdir(parents=True, exist_ok=True)
        write_csv(results, output / 'score.csv')
        pictures = write_plots(results, output, matched)
        print(f'\nwrote {output / "score.csv"} and {len(pictures)} pictures in {output}')
    return 0

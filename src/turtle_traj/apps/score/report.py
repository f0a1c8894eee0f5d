"""The score's tables, its ranking, and its files (CSV, one plot per course, a summary)."""

from __future__ import annotations

import csv
import math
import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from turtle_traj.apps.score.runner import Result

if TYPE_CHECKING:
    from turtle_traj.apps.score.matched import Matched

COLUMNS = ('course', 'robot', 'controller', 'success', 'time_s', 'bound_s', 'time_ratio',
           'rmse_mm', 'max_mm', 'end_mm', 'clamped_pct', 'message')


@dataclass(frozen=True)
class Standing:
    """One controller's summary over every course."""

    controller: str
    succeeded: int
    courses: int
    mean_rank: float  # over courses, of its rank on time and on maximum error (1 = best)
    median_ratio: float  # time against the bound, over the courses it finished
    median_max_mm: float


def _ranks(results: Sequence[Result], key) -> dict[str, int]:
    """Rank (1 = best) of each controller on one course: finished runs by `key`, then the rest."""
    order = sorted(results, key=lambda r: (not r.success, key(r) if r.success else 0.0))
    return {result.controller: place for place, result in enumerate(order, 1)}


def _standing(controller: str, results: Sequence[Result], places: list[int]) -> Standing:
    own = [r for r in results if r.controller == controller]
    done = [r for r in own if r.success]
    return Standing(controller, len(done), len(own), statistics.fmean(places),
                    statistics.median(r.ratio for r in done) if done else math.nan,
                    statistics.median(r.max_mm for r in done) if done else math.nan)


def ranking(results: Sequence[Result]) -> list[Standing]:
    """Controllers ordered by courses finished, then by mean rank on time and maximum error."""
    by_course: dict[str, list[Result]] = {}
    for result in results:
        by_course.setdefault(result.course, []).append(result)
    ranks: dict[str, list[int]] = {}
    for course in by_course.values():
        for key in (lambda r: r.ratio, lambda r: r.max_mm):
            for controller, place in _ranks(course, key).items():
                ranks.setdefault(controller, []).append(place)
    standings = [_standing(controller, results, places) for controller, places in ranks.items()]
    return sorted(standings, key=lambda s: (-s.succeeded, s.mean_rank))


def _width(names) -> int:
    return max([14, *(len(name) for name in names)])


def format_table(results: Sequence[Result]) -> str:
    """A row per course and controller."""
    width = _width(r.controller for r in results)
    lines = [f"{'course':18} {'controller':{width}} {'ok':>3} {'time s':>7} {'x bound':>7} "
             f"{'rmse mm':>8} {'max mm':>8} {'end mm':>7} {'clamped':>7}"]
    course = None
    for r in results:
        if r.course != course and course is not None:
            lines.append('')
        course = r.course
        lines.append(f"{r.course:18} {r.controller:{width}} {'yes' if r.success else 'NO':>3} "
                     f'{r.time_s:7.2f} {r.ratio:7.2f} {r.rmse_mm:8.2f} {r.max_mm:8.2f} '
                     f'{r.end_mm:7.1f} {r.clamped_pct:6.1f}%')
    failed = [r for r in results if not r.success]
    if failed:
        lines += ['', 'Runs that did not finish:']
        lines += [f'  {r.course} / {r.controller}: {r.message}' for r in failed]
    return '\n'.join(lines)


def format_ranking(standings: Sequence[Standing]) -> str:
    width = _width(s.controller for s in standings)
    lines = [f"{'rank':>4} {'controller':{width}} {'finished':>9} {'mean rank':>9} "
             f"{'median x bound':>14} {'median max mm':>13}"]
    for place, s in enumerate(standings, 1):
        lines.append(f'{place:4d} {s.controller:{width}} {s.succeeded:4d} of {s.courses:<2d} '
                     f'{s.mean_rank:9.2f} {s.median_ratio:14.2f} {s.median_max_mm:13.2f}')
    return '\n'.join(lines)


def write_csv(results: Sequence[Result], path: Path) -> None:
    with path.open('w', newline='') as stream:
        writer = csv.writer(stream)
        writer.writerow(COLUMNS)
        for r in results:
            writer.writerow([r.course, r.robot, r.controller, r.success, f'{r.time_s:.3f}',
                             f'{r.bound_s:.3f}', f'{r.ratio:.4f}', f'{r.rmse_mm:.3f}',
                             f'{r.max_mm:.3f}', f'{r.end_mm:.3f}', f'{r.clamped_pct:.2f}',
                             r.message])


def _file_name(course: str) -> str:
    return ''.join(c if c.isalnum() else '_' for c in course).strip('_') + '.png'


def _course_plot(plt, course: str, runs: Sequence[Result], target: Path) -> None:
    figure, axes = plt.subplots(figsize=(6, 6))
    axes.plot(*runs[0].plan.T, color='0.75', linewidth=4, label='plan')
    for r in runs:
        axes.plot(*r.path.T, linewidth=1.2, label=f"{r.controller} ({r.max_mm:.0f} mm max"
                  f"{'' if r.success else ', did not finish'})")
    axes.set_aspect('equal')
    axes.set_title(course)
    axes.set_xlabel('x [m]')
    axes.set_ylabel('y [m]')
    axes.legend(fontsize=8)
    figure.savefig(target, dpi=90, bbox_inches='tight')
    plt.close(figure)


def _summary_plot(plt, results: Sequence[Result], courses: list[str], target: Path,
                  matched: Sequence[Matched]) -> None:
    """Time against maximum error, a panel per course: a point per controller that finished,
    and a hollow one for the exact follower at each other's error, joined to that rival. Times
    are against the course's least-time bound (the exact plan's), so that all are comparable."""
    from matplotlib.ticker import NullFormatter
    controllers = list(dict.fromkeys(r.controller for r in results))
    colours = {name: f'C{index}' for index, name in enumerate(controllers)}
    columns = min(len(courses), 5)
    rows = math.ceil(len(courses) / columns)
    figure, panels = plt.subplots(rows, columns, figsize=(3.2 * columns, 2.6 * rows),
                                  squeeze=False)
    for panel, course in zip(panels.flat, courses, strict=False):
        for r in (r for r in results if r.course == course and r.success):
            panel.plot(max(r.max_mm, 1e-2), r.ratio, 'o', color=colours[r.controller],
                       label=r.controller)
        for m in (m for m in matched if m.rival.course == course and m.exact.success):
            rival, exact = m.rival, m.exact
            ratio = exact.time_s / rival.bound_s
            panel.plot([rival.max_mm, max(exact.max_mm, 1e-2)], [rival.ratio, ratio],
                       ':', color=colours[rival.controller], linewidth=0.8)
            panel.plot(max(exact.max_mm, 1e-2), ratio, 'o', mfc='none',
                       color=colours[rival.controller])
        panel.set_xscale('log')
        panel.xaxis.set_minor_formatter(NullFormatter())
        panel.set_title(course, fontsize=9)
        panel.tick_params(labelsize=7)
    for panel in panels.flat[len(courses):]:
        panel.set_visible(False)
    handles = [plt.Line2D([], [], marker='o', linestyle='', color=colours[name], label=name)
               for name in controllers]
    handles.append(plt.Line2D([], [], marker='o', mfc='none', linestyle='', color='0.3',
                              label='exact at that error'))
    figure.legend(handles=handles, loc='upper center', ncol=len(handles), fontsize=9)
    figure.supxlabel('max error [mm] (log)')
    figure.supylabel('time / least-time bound')
    figure.tight_layout(rect=(0, 0, 1, 0.97))
    figure.savefig(target, dpi=90, bbox_inches='tight')
    plt.close(figure)


def write_plots(results: Sequence[Result], folder: Path,
                matched: Sequence[Matched] = ()) -> list[Path]:
    """One PNG per course (every controller's path over the plan), and summary.png (time
    against error)."""
    import matplotlib
    matplotlib.use('Agg')
    from matplotlib import pyplot as plt
    courses = list(dict.fromkeys(r.course for r in results))
    written = []
    for course in courses:
        written.append(folder / _file_name(course))
        _course_plot(plt, course, [r for r in results if r.course == course], written[-1])
    written.append(folder / 'summary.png')
    _summary_plot(plt, results, courses, written[-1], matched)
    return written

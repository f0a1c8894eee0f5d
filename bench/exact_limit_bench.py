"""Exact drawing (tolerance 0) on turtlesim against its limit, side by side with other checkouts.

    .venv/bin/python bench/exact_limit_bench.py [--repo PATH ...]

The limit of an exact path on turtlesim, whose commands take effect at once: along a curve the
least of the top speed and the top turn rate over the curvature, each turn in place at the top
turn rate (and stopped at once: the node brakes its turns, which the text's many pay for). The
curvature at a vertex is its turn over the mean of its two segments, taken as linear along each
segment. A polyline only samples its curve, so this is an estimate: on the score's coarsely
sampled sine, each segment at its sharper end's curvature says 2% more. It is computed here from
the plan's points and the request's speeds, not taken from the node. For the score's turtlesim
courses and issue 76's sine (0.5 m, 0.5 cycles/m, 4 m long), each checkout (its own `src/`, in
a process of its own, on the pure loop the node runs) prints its time, the time over the limit,
and its largest and RMS distance from the polyline drawn.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ISSUE_SINE = {'size': 0.5, 'frequency': 0.5, 'length': 4.0}


def limit_s(path, linear_speed: float, angular_speed: float) -> float:
    """The limit of `path` (a planned Path) on turtlesim, from its points (see the module)."""
    import numpy as np

    from turtle_traj.core.geometry.path import Polyline, Turn
    total = 0.0
    for leg in path.legs:
        if isinstance(leg, Turn):
            total += abs(leg.sweep_rad) / angular_speed
            continue
        assert isinstance(leg, Polyline)
        steps = np.diff(leg.points, axis=0)
        lengths = np.hypot(*steps.T)
        headings = np.arctan2(steps[:, 1], steps[:, 0])
        turns = np.abs(np.angle(np.exp(1j * np.diff(headings))))
        if leg.repeat:  # the closing vertex too
            turns = np.concatenate((turns, [abs(np.angle(np.exp(1j * (headings[0]
                                                                      - headings[-1]))))]))
            at_vertices = turns / np.maximum(0.5 * (lengths + np.roll(lengths, -1)), 1e-12)
            at_starts, at_ends = np.roll(at_vertices, 1), at_vertices
        else:  # an open end is straight
            at_vertices = turns / np.maximum(0.5 * (lengths[:-1] + lengths[1:]), 1e-12)
            at_starts = np.concatenate(([0.0], at_vertices))
            at_ends = np.concatenate((at_vertices, [0.0]))
        # time per metre at each end of a segment, the curvature taken as linear between them
        slowness = [np.maximum(1.0 / linear_speed, curvature / angular_speed)
                    for curvature in (at_starts, at_ends)]
        total += float(np.sum(lengths * 0.5 * (slowness[0] + slowness[1])))
    return total


def measure() -> dict[str, dict[str, float]]:
    """This checkout's runs: each course's time, limit and distances from the drawn path."""
    from dataclasses import replace

    import numpy as np

    from turtle_traj.api.ros_interface import make_request
    from turtle_traj.apps.score.courses import standard_courses
    from turtle_traj.apps.score.runner import run_course
    from turtle_traj.core.geometry.path import Pose2D
    from turtle_traj.core.planning import planner
    from turtle_traj.core.registry import BY_NAME
    from turtle_traj.testing.geometry import distance_to_polyline

    courses = {course.name: course for course in standard_courses(('turtlesim',))}
    courses['issue sine'] = replace(courses['sine'], name='issue sine',
                                    request=make_request(BY_NAME['sine'], ISSUE_SINE),
                                    start=Pose2D(3.0, 5.5, 0.0))
    figures = {}
    for name, course in courses.items():
        if not hasattr(course.request, 'corner_tolerance') and name != 'issue sine':
            continue
        plan = planner.plan(course.trajectory, course.request, course.start, course.settings)
        limits = plan.control(course.settings.control).limits  # the request's speeds
        result = run_course(course, 'exact')
        distances = distance_to_polyline(np.asarray(result.path), plan.drawn_points())
        figures[name] = {
            'time_s': result.time_s,
            'limit_s': limit_s(plan.path, limits.linear_speed, limits.angular_speed),
            'max_mm': 1e3 * float(distances.max()),
            'rms_mm': 1e3 * float(np.sqrt(np.mean(distances ** 2)))}
    return figures


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repo', action='append', type=Path,
                        help='a checkout to measure (default: this one); repeat to compare')
    parser.add_argument('--measure', action='store_true', help=argparse.SUPPRESS)
    options = parser.parse_args()
    if options.measure:
        print(json.dumps(measure()))
        return
    repos = options.repo or [ROOT]
    results = {}
    for repo in repos:
        done = subprocess.run([sys.executable, __file__, '--measure'], capture_output=True,
                              text=True, check=True,
                              env={**os.environ, 'PYTHONPATH': str(repo / 'src')})
        results[repo] = json.loads(done.stdout.strip().splitlines()[-1])
    names = list(results[repos[0]])
    labels = [subprocess.run(['git', '-C', str(repo), 'rev-parse', '--short', 'HEAD'],
                             capture_output=True, text=True).stdout.strip() or repo.name
              for repo in repos]
    print('exact drawing on turtlesim (pure loop), time over the limit computed here; '
          'distances from the polyline drawn')
    print(f'{"course":12} {"limit s":>8} ' + ' '.join(f'{label:>34}' for label in labels))
    print(f'{"":12} {"":>8} ' + ' '.join(
        f'{"time s":>9} {"x limit":>7} {"max mm":>7} {"rms mm":>7}' for _ in repos))
    for name in names:
        row = f'{name:12} {results[repos[0]][name]["limit_s"]:8.2f} '
        for repo in repos:
            figure = results[repo].get(name)
            row += (f'{figure["time_s"]:9.2f} {figure["time_s"] / figure["limit_s"]:7.3f} '
                    f'{figure["max_mm"]:7.2f} {figure["rms_mm"]:7.2f} ' if figure else
                    f'{"-":>34} ')
        print(row)


if __name__ == '__main__':
    main()

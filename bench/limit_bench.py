"""The minimum-time limit (`core.planning.min_time`) on the DWPP paper's paths, at the
tolerances of issue 76's table, beside the reference's times there.

    .venv/bin/python bench/limit_bench.py [--nodes 200]

The base with inertia of the paper (0.5 m/s, 1 rad/s, 0.5 m/s^2, 1 rad/s^2): three 3 m legs
turning 45, 90 and 135 degrees, and one period of a sine (1 m over 6 m) from facing its first
leg and from facing along x. For each: the limit's time, its largest distance from the path
(integrated between the nodes), the solve's CPU time, and the limit with twice the nodes (how
much the discretisation still moves it).
"""

from __future__ import annotations

import argparse

from base_bench import sine, step_curve
from turtle_traj.core.planning.min_time import RobotLimits, minimum_time

PAPER = RobotLimits(speed=0.5, turn_rate=1.0, acceleration=0.5, angular_acceleration=1.0)
# issue 76: the reference DWPP's time at its maximum error, and ours rounded to that error
CASES = [('step 45', step_curve(45), None, 0.062, 18.7, 18.98),
         ('step 90', step_curve(90), None, 0.086, 19.5, 21.76),
         ('step 135', step_curve(135), None, 0.165, 21.4, 20.27),
         ('sine, facing its leg', sine(), None, 0.104, 16.3, 18.27),
         ('sine, facing x', sine(), 0.0, 0.104, 16.3, 18.27)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--nodes', type=int, default=200)
    options = parser.parse_args()
    print(f'{"path":22} {"tol mm":>6} {"limit s":>8} {"2x nodes":>9} {"err mm":>7} '
          f'{"solve s":>8} {"ref s":>6} {"ours s":>7}')
    for name, points, heading, tolerance, reference, ours in CASES:
        limit = minimum_time(points, tolerance, PAPER, start_heading=heading,
                             nodes=options.nodes)
        finer = minimum_time(points, tolerance, PAPER, start_heading=heading,
                             nodes=2 * options.nodes)
        flag = '' if limit.solved and finer.solved else '  (not converged)'
        print(f'{name:22} {tolerance * 1e3:6.0f} {limit.time_s:8.2f} {finer.time_s:9.2f} '
              f'{limit.max_error_m * 1e3:7.1f} {limit.solve_s:8.2f} {reference:6.1f} '
              f'{ours:7.2f}{flag}')
    straight = 9.0 / PAPER.speed + PAPER.speed / PAPER.acceleration
    print(f'a straight 9 m from rest to rest at these limits: {straight:.2f} s')


if __name__ == '__main__':
    main()

"""Every trajectory with its velocity commands delayed on the way to the simulator.

Lock-step simulated time, so every figure repeats exactly; the delay is the simulator's
`command_delay` plus up to `command_jitter` of seeded random extra, applied to each cmd_vel.
Deviation and end error are measured here, on the recorded poses against the plan the node
published on ~/plan, not taken from the node's reply.
Run: .venv/bin/python bench/latency_bench.py ['jitter 0-32 ms' ...]   (all delays by default)
"""

from __future__ import annotations

import math
import sys
import tempfile

import numpy as np
import rclpy
from nav_msgs.msg import Path as PathMsg
from rclpy.qos import DurabilityPolicy, QoSProfile

from isolation import isolate
from turtle_traj.apps.demo import run_example
from turtle_traj.apps.in_process import InProcessSystem
from turtle_traj.core.registry import TRAJECTORIES
from turtle_traj.testing.geometry import distance_to_polyline

# (label, fixed delay s, jitter s)
DELAYS = [('0 ms', 0.0, 0.0), ('16 ms', 0.016, 0.0), ('32 ms', 0.032, 0.0),
          ('64 ms', 0.064, 0.0), ('jitter 0-32 ms', 0.0, 0.032), ('jitter 0-64 ms', 0.0, 0.064)]


def run_all(delay_s: float, jitter_s: float) -> list[tuple]:
    """(name, response, measured max deviation, measured end error, where the deviation was
    largest) of every trajectory."""
    system = InProcessSystem(output_dir=tempfile.mkdtemp(), sim_parameters={
        'command_delay': delay_s, 'command_jitter': jitter_s})
    plans: list[PathMsg] = []
    system.client.create_subscription(
        PathMsg, '/turtle_traj/plan', plans.append,
        QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    rows = []
    try:
        for trajectory in TRAJECTORIES:
            plans.clear()
            response = run_example(system, trajectory)
            planned = np.array([(p.pose.position.x, p.pose.position.y)
                                for p in plans[-1].poses]) if plans else np.zeros((0, 2))
            driven = np.array([(p.x, p.y) for p in system.poses])
            worst_at = (math.nan, math.nan)
            if len(planned) >= 2 and len(driven):
                deviations = distance_to_polyline(driven, planned)
                deviation = float(deviations.max())
                worst_at = tuple(driven[int(deviations.argmax())])
            else:
                deviation = 0.0
            end_error = (math.dist(driven[-1], planned[-1])
                         if len(planned) and len(driven) else math.nan)
            rows.append((trajectory.name, response, deviation, end_error, worst_at))
    finally:
        system.close()
    return rows


def main() -> None:
    wanted = sys.argv[1:]  # labels to run, e.g. 'jitter 0-32 ms'; all by default
    isolate('latency')
    rclpy.init()
    try:
        print('turtle_traj latency benchmark: cmd_vel delayed in the simulator, lock-step time, '
              'default speeds; deviation and end error measured on the recorded poses')
        for label, delay_s, jitter_s in DELAYS:
            if wanted and label not in wanted:
                continue
            rows = run_all(delay_s, jitter_s)
            worst_dev = max(row[2] for row in rows)
            worst_end = max(row[3] for row in rows)
            ok = sum(row[1].success for row in rows)
            print(f'\ncommand delay {label}: {ok}/{len(rows)} succeeded, worst deviation '
                  f'{worst_dev:.4f} m, worst end error {worst_end:.4f} m')
            print(f'  {"trajectory":12} {"ok":>3} {"max dev m":>10} {"end err m":>10} '
                  f'{"elapsed s":>10}  max dev at')
            for name, response, deviation, end_error, (x, y) in rows:
                print(f'  {name:12} {"yes" if response.success else "NO":>3} {deviation:10.4f} '
                      f'{end_error:10.4f} {response.elapsed:10.2f}  ({x:.2f}, {y:.2f})'
                      + ('' if response.success else f'  {response.message}'))
    finally:
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()

"""Does the node answer while it plans? The longest silence a client sees from the trajectory
node while a slow plan is made: a text with 0.02 m corners on the base with acceleration limits
(TOPP-RA), the tutorial's `turtle-traj up --base --time-scale 20` (base and node in one process).

The client sends the goal, asks for a parameter every 0.1 s, and counts every answer (a
parameter reply, a feedback message) as a sign of life. It prints, per goal, the plan's wall
time (goal sent to first feedback) and the longest gap between signs of life in that time; the
command line gives a node up for dead after 5 s with neither. Each goal is cancelled at its
first feedback.

Run: .venv/bin/python bench/planning_bench.py [--goals N] [--busy K] [--src DIR ...]
  --busy K   start K busy loops for the measurement (stopped by their pid at the end)
  --src DIR  measure the `up` of another checkout's src/ (an old commit's worktree), side by
             side; the first is this checkout's own unless given as 'this'
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time

from isolation import isolate
from load import busy_loops
from turtle_traj.client.liveness import FEEDBACK_SILENCE_S, PROBE_TIMEOUT_S

LIVENESS_S = FEEDBACK_SILENCE_S + PROBE_TIMEOUT_S  # the command line's rule for a node gone
NODE = '/turtle_traj'


def measure(goals: int) -> list[tuple[float, float]]:
    """(plan wall time, longest silence), seconds, for each goal."""
    import rclpy
    from rclpy.action import ActionClient
    from rclpy.parameter_client import AsyncParameterClient
    from turtle_traj_interfaces.action import Draw

    rclpy.init()
    node = rclpy.create_node('planning_bench')
    try:
        action = ActionClient(node, Draw, f'{NODE}/draw')
        parameters = AsyncParameterClient(node, NODE)
        if not (action.wait_for_server(timeout_sec=60.0)
                and parameters.wait_for_services(timeout_sec=60.0)):
            raise SystemExit('the node did not come up within 60 s')
        results = []
        for index in range(goals):
            results.append(one_goal(node, action, parameters, Draw, index))
        return results
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


def one_goal(node, action, parameters, draw_type, index: int) -> tuple[float, float]:
    """Send one text goal, wait for its first feedback while asking for parameters, cancel it;
    a goal refused while the node has no pose yet (it is starting) is sent again."""
    import rclpy

    goal = draw_type.Goal(trajectory='text', text='ROS' if index % 2 == 0 else 'SOR',
                          height=0.5, corner_tolerance=0.02)
    for _attempt in range(60):
        signs: list[float] = []
        first_feedback: list[float] = []

        def on_feedback(_message, signs=signs, first_feedback=first_feedback) -> None:
            signs.append(time.monotonic())
            if not first_feedback:
                first_feedback.append(signs[-1])

        sent = time.monotonic()
        accepted = action.send_goal_async(goal, feedback_callback=on_feedback)
        rclpy.spin_until_future_complete(node, accepted, timeout_sec=30.0)
        result = accepted.result().get_result_async()
        asked_s, pending = 0.0, None
        while not first_feedback and not result.done():
            now = time.monotonic()
            if (pending is None or pending.done()) and now - asked_s > 0.1:  # one at a time
                pending = parameters.get_parameters(['linear_speed'])
                pending.add_done_callback(lambda _reply, signs=signs: signs.append(
                    time.monotonic()))
                asked_s = now
            rclpy.spin_once(node, timeout_sec=0.01)
        if first_feedback:
            break
        message = result.result().result.message
        if not message.startswith(('no pose', 'nothing subscribes')):  # not a start-up refusal
            raise SystemExit(f'the goal was refused: {message}')
        time.sleep(0.5)
    else:
        raise SystemExit('the node had no pose for 30 s')
    plan_s = first_feedback[0] - sent
    marks = [sent, *sorted(s for s in signs if sent <= s <= first_feedback[0])]
    silence = max(b - a for a, b in zip(marks, marks[1:], strict=False))
    accepted.result().cancel_goal_async()
    rclpy.spin_until_future_complete(node, result, timeout_sec=60.0)
    if not result.done():
        raise SystemExit('the cancelled goal did not end within 60 s')
    return plan_s, silence


def run_one(src: str | None, goals: int) -> list[tuple[float, float]]:
    """Start `up --base --time-scale 20` from `src` (None: this checkout) and measure it."""
    env = dict(os.environ)
    if src is not None:
        env['PYTHONPATH'] = os.pathsep.join(filter(None, [src, env.get('PYTHONPATH')]))
    up = subprocess.Popen([sys.executable, '-m', 'turtle_traj.cli', 'up', '--base',
                           '--time-scale', '20'], env=env, stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL)
    try:
        child = subprocess.run([sys.executable, __file__, '--measure', str(goals)], env=env,
                               capture_output=True, text=True, timeout=900)
        if child.returncode != 0:
            raise SystemExit(f'measurement failed: {child.stderr.strip()[-2000:]}')
        return [tuple(map(float, line.split())) for line in child.stdout.split('\n') if line]
    finally:
        up.terminate()
        up.wait(30)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--goals', type=int, default=4)
    parser.add_argument('--busy', type=int, default=0)
    parser.add_argument('--src', action='append', default=[])
    parser.add_argument('--measure', type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    isolate('planning')
    if args.measure is not None:  # the client, in a process of its own
        for plan_s, silence in measure(args.measure):
            print(plan_s, silence)
        return 0
    sources = args.src or ['this']
    with busy_loops(args.busy):
        rows = [(src, run_one(None if src == 'this' else src, args.goals)) for src in sources]
    print(f'text ROS, height 0.5 m, corners 0.02 m, up --base --time-scale 20, '
          f'{args.busy} busy loop(s); client gives up after {LIVENESS_S:g} s of silence')
    print(f'{"source":40} {"plan s (median, max)":>22} {"longest silence s (median, max)":>33}')
    for src, results in rows:
        plans, silences = zip(*results, strict=True)
        print(f'{src:40} {statistics.median(plans):10.2f} {max(plans):10.2f} '
              f'{statistics.median(silences):16.2f} {max(silences):16.2f}')
    return 0


if __name__ == '__main__':
    sys.exit(main())

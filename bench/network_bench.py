"""Tracking across two hosts on a lossy link, and after cuts: the README's two-machine recipe.

    .venv/bin/python bench/network_bench.py [--runs 3] [--plot bench/network_loss.png]

Needs root. Two network namespaces on a veth pair (`turtle_traj.testing.two_hosts`): our
simulator and a pose log on host a, the trajectory node and the command line on host b, default
discovery.
nftables drops a random share of the packets leaving each host, both ways. The kernel's
`numgen random` cannot be seeded: the runs at each loss are independent draws.

Per loss (0, 1, 5, 10, 20%) and path (a 1 m square, a circle 1 m across, the text "ROS" 0.5 m
tall), each run from a reset turtle: whether the CLI's call succeeded, its duration, and the
maximum deviation measured on host a (every pose the turtle had, against the plan the node
published; the node's own figure is printed beside it). Then link cuts of 0.5, 2 and 10 s in
the middle of a circle: how the run ended and how long after the cut, and the time from the
link's return to the first call that succeeds. Every call has its own timeout: one that hangs
is counted, never waited for.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from isolation import isolate
from turtle_traj.testing.pose_log import PoseLog
from turtle_traj.testing.two_hosts import TwoHosts, reported_deviation_m, why_unavailable

LOSSES = (0, 1, 5, 10, 20)
PATHS = {'square': ('draw', 'square', '--size', '1'),
         'circle': ('draw', 'circle', '--size', '1'),
         'ROS': ('write', 'ROS', '--height', '0.5')}
CUTS_S = (0.5, 2.0, 10.0)
RUN_LIMIT_S = 150.0  # the CLI's --timeout: it cancels a run still going after this
CALL_TIMEOUT_S = RUN_LIMIT_S + 60.0  # a call that has not answered by then has hung
POSE_TIMEOUT_S = 0.5  # the node's default


@dataclass
class Run:
    path: str
    loss: int
    succeeded: bool
    duration_s: float
    deviation_mm: float  # measured on the simulator's host
    reported_mm: float  # what the node said (nan: it said none)
    said: str


def _outcome(output: str) -> str:
    """The line of a call's output that says how it ended."""
    lines = output.strip().splitlines()
    return next((line.strip() for line in lines
                 if re.search(r'\b(done|aborted|error|refused|cancell?ed)\b', line)),
                lines[-1].strip() if lines else 'no answer')


class Bench:
    def __init__(self, hosts: TwoHosts, log: Path) -> None:
        self.hosts, self.log = hosts, log
        self.hung = 0

    def call(self, *args: str, timeout_s: float = CALL_TIMEOUT_S):
        try:
            return self.hosts.call('b', *args, '--wait', '30', timeout_s=timeout_s)
        except subprocess.TimeoutExpired:
            self.hung += 1
            return None

    def reset(self) -> None:
        done = self.call('reset')
        if done is None or done.returncode != 0:
            raise SystemExit(f'reset failed: {done and done.stdout + done.stderr}')

    def run(self, path: str, loss: int) -> Run:
        self.reset()
        self.hosts.loss(loss)
        start = time.monotonic()
        try:
            done = self.call(*PATHS[path], '--timeout', str(RUN_LIMIT_S))
        finally:
            end = time.monotonic()
            self.hosts.loss(0)
        said = '' if done is None else (done.stdout + done.stderr).strip()
        time.sleep(0.3)  # the last poses reach the log
        deviation_mm = PoseLog.read(self.log).deviation_m(start, end) * 1e3
        return Run(path, loss, done is not None and done.returncode == 0, end - start,
                   deviation_mm, reported_deviation_m(said) * 1e3,
                   _outcome(said) if said else 'no answer')

    def cut(self, cut_s: float) -> tuple[str, float, float]:
        """A circle cut for `cut_s` after 3 s: its end (message, seconds after the cut) and
        the time from the link's return to the first call that succeeds."""
        self.reset()
        circle = self.hosts.start('b', *PATHS['circle'], '--wait', '30')
        time.sleep(3.0)
        self.hosts.link(False)
        cut_at = time.monotonic()
        ended_s = math.nan
        while time.monotonic() - cut_at < cut_s:
            if math.isnan(ended_s) and circle.poll() is not None:
                ended_s = time.monotonic() - cut_at
            time.sleep(0.01)
        self.hosts.link(True)
        back = time.monotonic()
        try:
            said, _ = circle.communicate(timeout=CALL_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            circle.kill()
            said, _ = circle.communicate()
            self.hung += 1
        if math.isnan(ended_s):
            ended_s = time.monotonic() - cut_at
        while time.monotonic() - back < 60.0:
            done = self.call('move', '0.2')
            if done is not None and done.returncode == 0:
                return _outcome(said), ended_s, time.monotonic() - back
            print(f'  after the cut: {_outcome(done.stdout + done.stderr) if done else "hung"}')
        return _outcome(said), ended_s, math.inf


def _table(runs: list[Run]) -> None:
    print(f'{"path":8} {"loss":>5} {"ok":>5} {"duration s":>16} {"max dev mm":>16} '
          f'{"node mm":>8}')
    for path in PATHS:
        for loss in LOSSES:
            these = [run for run in runs if run.path == path and run.loss == loss]
            if not these:
                continue
            ok = sum(run.succeeded for run in these)
            durations = [run.duration_s for run in these]
            deviations = [run.deviation_mm for run in these]
            print(f'{path:8} {loss:>4}% {ok:>2}/{len(these):<2} '
                  f'{np.median(durations):7.1f} (<={max(durations):5.1f}) '
                  f'{np.median(deviations):7.2f} (<={max(deviations):5.2f}) '
                  f'{max(run.reported_mm for run in these):8.2f}')
    for run in runs:
        if not run.succeeded:
            print(f'  {run.path} at {run.loss}%: {run.said}')


def _plot(runs: list[Run], out: Path) -> None:
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(6.4, 4.0))
    for offset, path in zip((-0.3, 0.0, 0.3), PATHS, strict=True):
        these = [run for run in runs if run.path == path]
        axes.plot([run.loss + offset for run in these],
                  [run.deviation_mm for run in these], 'o', label=path, alpha=0.8)
    axes.set_xlabel('packet loss each way [%]')
    axes.set_ylabel('max deviation from the path [mm]')
    axes.set_xticks(LOSSES)
    axes.set_title('Two hosts: tracking under packet loss (measured on the simulator\'s host)',
                   fontsize=9)
    axes.grid(alpha=0.3)
    axes.legend()
    figure.tight_layout()
    figure.savefig(out, dpi=100)
    print(f'plot: {out}')


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--runs', type=int, default=3, help='runs per loss and path')
    parser.add_argument('--losses', type=int, nargs='*', default=list(LOSSES))
    parser.add_argument('--paths', nargs='*', default=list(PATHS), choices=list(PATHS))
    parser.add_argument('--cuts', type=float, nargs='*', default=list(CUTS_S))
    parser.add_argument('--plot', type=Path, default=None, help='PNG of deviation vs loss')
    options = parser.parse_args()
    if (problem := why_unavailable()) is not None:
        raise SystemExit(f'network bench: {problem}')
    isolate('network')
    log = Path(tempfile.mkdtemp(prefix='turtle_traj_network_')) / 'poses.log'
    started = time.monotonic()
    with TwoHosts(int(os.environ['ROS_DOMAIN_ID'])) as hosts:
        hosts.run('a', 'turtle_traj.sim', stderr=subprocess.DEVNULL)
        hosts.log_poses('a', log)
        hosts.run('b', 'turtle_traj', stderr=subprocess.DEVNULL)
        bench = Bench(hosts, log)
        runs = []
        for loss in options.losses:
            for _ in range(options.runs):
                for path in options.paths:
                    runs.append(bench.run(path, loss))
                    print(f'  {path} at {loss}%: {runs[-1].said}', flush=True)
        _table(runs)
        if options.plot:
            _plot(runs, options.plot)
        print(f'\n{"cut s":>6} {"ended s after cut":>18} {"first success s":>16}  how it ended')
        for cut_s in options.cuts:
            said, ended_s, back_s = bench.cut(cut_s)
            print(f'{cut_s:6.1f} {ended_s:18.2f} {back_s:16.2f}  {said}', flush=True)
        print(f'\nhung calls: {bench.hung}; bench took {time.monotonic() - started:.0f} s')


if __name__ == '__main__':
    main()

"""The two-machine recipe (docs/tutorials/two-machines.md), for real: our simulator and a pose
log on host a, the trajectory node and the command line on host b, two network namespaces on a
veth pair with default discovery (`turtle_traj.testing.two_hosts`); then packet loss, link cuts
and a simulator restarted.

Deviations are measured on host a, from every pose the turtle had, against the plan the node
published, and must agree with the node's own figure. Needs root: without it these tests are
skipped, naming why; under CI they run, and a missing permission fails them.
"""

from __future__ import annotations

import math
import os
import re
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from turtle_traj.testing.pose_log import PoseLog
from turtle_traj.testing.two_hosts import (
    TwoHosts,
    reported_deviation_m,
    reported_elapsed_s,
    why_unavailable,
)

_PROBLEM = why_unavailable()
pytestmark = [pytest.mark.system,
              pytest.mark.skipif(_PROBLEM is not None and not os.environ.get('CI'),
                                 reason=f'two hosts: {_PROBLEM}')]
POSE_TIMEOUT_S = 0.5  # the node's default
COMMAND_TIMEOUT_S = 1.0  # turtlesim stops a turtle that has had no command for this long
CALL_TIMEOUT_S = 60.0  # a call not answered by then has hung
# What a lost command can cost: the stream of commands stalls until its repair (heartbeats every
# 4 ms, answered at once: fastdds.xml), and meanwhile the command before acts on. Mid-leg the
# echo shows the node the late command and it steers back; at a leg's end the approach allows
# for the 99th percentile of how late commands come. A stall longer than any seen yet (the first
# on a link that was clean, or a node starved of CPU) can catch the last full-speed command of a
# leg: one period more of it, 16 mm at the default 1 m/s, past the corner. Measured in a loop of
# the 5% test: at most 0.5 mm quiet, 16.0 and 12.8 mm in 4 runs under two busy loops; with the
# repair at Fast DDS's default delays (10 ms heartbeats) 25.7 and 28.1 mm, two periods. The
# bound is one period, with a margin; the bench gives the figures over many runs.
LOSSY_DEVIATION_M = 0.02
# A 0.2 m move after a cut, by the node's clock. Its approach slows with the latency's spread
# (each command covers its share of what remains): 0.22-0.44 s with a steady latency, 1.2-1.3 s
# after a spread of 2 periods seen mid-move, 0.74 s once in the loaded full suite. A cut's
# stall remembered as jitter made it a 6.1 s crawl (31 periods). Not the call's wall time: a
# new CLI process takes 2.4-3.6 s to start and find the node under four busy loops; from the
# link's return to the answer took 12.3 s once in the full suite beside two.
AFTER_CUT_MOVE_S = 3.0


class Hosts:
    """The two hosts, the programs on them and the pose log on host a."""

    def __init__(self, made: TwoHosts, log: Path) -> None:
        self.made, self.log = made, log
        self.sim = self.start_sim()
        made.log_poses('a', log)
        made.run('b', 'turtle_traj', stderr=subprocess.DEVNULL)
        # the command line's calls, on host b: one process for them all (a process a call
        # spent 0.6-1.0 s of each starting and finding the node)
        self.cli = made.session('b')

    def start_sim(self) -> subprocess.Popen:
        return self.made.run('a', 'turtle_traj.sim', stderr=subprocess.DEVNULL)

    def call(self, *args: str, timeout_s: float = CALL_TIMEOUT_S) -> subprocess.CompletedProcess:
        return self.cli.call(*args, timeout_s=timeout_s)

    def start(self, *args: str) -> subprocess.Popen:
        """A call left running (a trajectory to cut)."""
        return self.made.start('b', *args)

    def measured(self, *args: str) -> tuple[subprocess.CompletedProcess, float, float]:
        """Run a trajectory from a reset turtle: its answer, the deviation measured on host a
        (m) and the one the node reported."""
        reset = self.call('reset', '--wait', '30')
        assert reset.returncode == 0, reset.stdout + reset.stderr
        start = time.monotonic()
        done = self.call(*args, '--wait', '30')
        end = time.monotonic()
        time.sleep(0.2)  # the last poses reach the log
        deviation = PoseLog.read(self.log).deviation_m(start, end)
        assert not math.isnan(deviation), 'no plan or no pose reached host a'
        return done, deviation, reported_deviation_m(done.stdout)

    def driving(self, call: _Answers, since: float) -> None:
        """Wait until the turtle moves after `since`: `call`'s run has begun. A command-line
        process takes seconds to start and find the node on a loaded machine: once in a loaded
        full suite its goal came about 4.4 s after it started, so the simulator a test killed
        2.5 s in had been silent 1.9 s by then, and the goal was refused, too late for a test
        that times a running call's end."""
        while self.last_move_s() <= since:
            assert call.process.poll() is None, call.said()
            assert time.monotonic() - since < CALL_TIMEOUT_S, 'the run never began'
            time.sleep(0.05)

    def last_move_s(self) -> float:
        """When the turtle last moved (monotonic s), from the log on host a."""
        poses = PoseLog.read(self.log).poses
        moved = np.flatnonzero(np.abs(np.diff(poses[:, 1:], axis=0)).sum(axis=1) > 1e-7)
        return float(poses[moved[-1] + 1, 0]) if len(moved) else -math.inf


@pytest.fixture(scope='module')
def hosts(tmp_path_factory, ros_domain_id):
    with TwoHosts(ros_domain_id) as made:
        started = Hosts(made, tmp_path_factory.mktemp('two_hosts') / 'poses.log')
        # Up: the node on host b has found the simulator on host a by discovery across the
        # link, on its own time. Until then a reset is refused, saying which service is
        # missing; the tests begin once one succeeds.
        began = time.monotonic()
        while (reset := started.call('reset', '--wait', '30')).returncode != 0:
            assert 'not available' in reset.stderr + reset.stdout, reset.stderr + reset.stdout
            assert time.monotonic() - began < 30.0, 'the node never found the simulator'
        yield started


def _succeeded(done: subprocess.CompletedProcess) -> None:
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_readme_recipe_draws_across_two_hosts(hosts):
    done, deviation, reported = hosts.measured('draw', 'square', '--size', '0.5')
    _succeeded(done)
    assert 'square done' in done.stdout
    assert deviation < 0.001, done.stdout  # on failure: the node's own figures and time
    assert reported == pytest.approx(deviation, abs=1e-4)  # the node's figure is the truth


@pytest.mark.parametrize(('loss', 'paths'), [
    (1, [('draw', 'square', '--size', '0.5')]),
    (5, [('draw', 'square', '--size', '0.5'), ('draw', 'circle', '--size', '0.5'),
         ('write', 'T', '--height', '0.3')])])  # corners, a curve, the pen (the bench: more)
def test_a_lossy_link_still_draws_every_kind_of_path(hosts, loss, paths):
    hosts.made.loss(loss)
    try:
        runs = [hosts.measured(*path) for path in paths]
    finally:
        hosts.made.loss(0)
    for done, deviation, reported in runs:
        _succeeded(done)
        print(f'{loss}% loss: deviation {deviation * 1e3:.2f} mm (node: {reported * 1e3:.2f})')
        assert deviation < LOSSY_DEVIATION_M
        # the node sees fewer poses than the turtle had (a lost pose is not resent: it reads
        # the newest), so its figure may be a little lower, never higher
        assert deviation - 5e-4 <= reported <= deviation + 1e-4


def test_at_twenty_percent_a_run_completes_or_says_why_not(hosts):
    # No bound on the deviation here: a repair can itself be lost, and the command before a
    # stall of several periods then acts on (bench/network_bench.py gives the figures).
    hosts.made.loss(20)
    try:
        done, deviation, _ = hosts.measured('draw', 'square', '--size', '0.5')
    finally:
        hosts.made.loss(0)
    print(f'20% loss: deviation {deviation * 1e3:.2f} mm: {(done.stdout or "-").splitlines()[0]}')
    if done.returncode != 0:
        assert re.search(r'aborted: .+', done.stdout + done.stderr), done.stdout + done.stderr


class _Answers:
    """A call left running, its output read line by line as it comes, each with when."""

    def __init__(self, process: subprocess.Popen) -> None:
        self.process = process
        self.lines: list[tuple[float, str]] = []  # (monotonic s, line)
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        for line in self.process.stdout:
            self.lines.append((time.monotonic(), line))

    def answered_s(self, text: str, since: float, until: float) -> float:
        """Seconds from `since` to the first line that holds `text`, watched until `until`
        (inf: not said by then). The answer, not the process's end: a command-line process
        under load took up to 1.8 s more to close its ROS context and exit (3 of 54 over
        1.5 s in a loop beside two busy loops), with every answer within 0.51 s of a cut."""
        while time.monotonic() < until:
            if said := [when for when, line in self.lines if text in line]:
                return said[0] - since
            time.sleep(0.01)
        return math.inf

    def said(self) -> str:
        """Everything it said, once it has ended (within CALL_TIMEOUT_S)."""
        self.process.wait(timeout=CALL_TIMEOUT_S)
        self._reader.join(timeout=CALL_TIMEOUT_S)
        return ''.join(line for _, line in self.lines)

    def kill(self) -> None:
        """End it now, if it has not ended."""
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()


@pytest.mark.parametrize('cut_s', [0.5, 2.0, 10.0])
def test_a_cut_link_ends_the_run_and_the_next_call_succeeds(hosts, cut_s):
    _succeeded(hosts.call('reset', '--wait', '30'))
    began = time.monotonic()
    circle = _Answers(hosts.start('draw', 'circle', '--size', '1', '--wait', '30'))
    try:
        hosts.driving(circle, began)
        time.sleep(0.5)  # well into the circle (6.3 s long)
        assert circle.process.poll() is None, circle.said()
        hosts.made.link(False)
        cut = time.monotonic()
        ended_s = circle.answered_s('no pose on /turtle1/pose', cut,
                                    cut + min(cut_s, POSE_TIMEOUT_S + 1.0))
        if cut_s > 5.0:
            # a call made during the cut answers at once: the node is on this host
            during = hosts.call('move', '0.2', '--wait', '5', timeout_s=20)
            assert during.returncode != 0
            assert 'no pose on /turtle1/pose' in during.stdout + during.stderr
            assert time.monotonic() < cut + cut_s
        time.sleep(max(cut + cut_s - time.monotonic(), 0.0))
        stopped_s = hosts.last_move_s() - cut
        hosts.made.link(True)
        said = circle.said()
        time.sleep(0.3)
        # and the commands held for the link were dropped, not delivered late (lifespan)
        stale_s = hosts.last_move_s() - cut
    finally:
        hosts.made.link(True)
        circle.kill()
    if cut_s > POSE_TIMEOUT_S:
        assert 'no pose on /turtle1/pose' in said and circle.process.returncode != 0, said
        assert ended_s < POSE_TIMEOUT_S + 1.0
        # nothing reaches the turtle: turtlesim's command timeout stops it
        assert stopped_s < COMMAND_TIMEOUT_S + 0.1
        assert stale_s == stopped_s
    else:  # no longer than pose_timeout: the run may ride it out
        assert circle.process.returncode == 0 or 'no pose on /turtle1/pose' in said, said
    done = hosts.call('move', '0.2', '--wait', '30')
    _succeeded(done)
    # driven at its usual pace: no latency learnt in the cut slows its approach (the node's own
    # figure; the call's wall time is mostly a new process starting on a loaded machine)
    assert reported_elapsed_s(done.stdout) < AFTER_CUT_MOVE_S, done.stdout  # nan: none printed


def test_a_simulator_restarted_on_its_host_is_driven_again(hosts):
    reset = hosts.call('reset', '--wait', '30')
    _succeeded(reset)
    began = time.monotonic()
    circle = _Answers(hosts.start('draw', 'circle', '--size', '1', '--wait', '30'))
    try:
        hosts.driving(circle, began)
        time.sleep(0.5)  # well into the circle (6.3 s long)
    except BaseException:
        circle.kill()
        raise
    hosts.sim.kill()
    hosts.sim.wait()
    killed = time.monotonic()
    answered_s = circle.answered_s('no pose on /turtle1/pose', killed,
                                   killed + POSE_TIMEOUT_S + 1.0)
    try:
        said = circle.said()
    finally:
        circle.kill()
    assert circle.process.returncode != 0
    assert answered_s < POSE_TIMEOUT_S + 1.0, said
    hosts.sim = hosts.start_sim()
    restarted = time.monotonic()
    while PoseLog.read(hosts.log).poses[-1, 0] < restarted:  # it is up: it publishes poses
        assert time.monotonic() - restarted < 30.0, 'the simulator did not come back'
        time.sleep(0.1)
    up = time.monotonic()
    # The node finds the new simulator by discovery across the link, on its own time: until
    # it hears a pose, a call is refused, saying so. Within 5 s of the simulator's first
    # pose, calls made one after another succeed.
    while (done := hosts.call('move', '0.2', '--wait', '30')).returncode != 0:
        said = done.stdout + done.stderr  # a refusal and a failure are written to stderr
        assert 'no pose on /turtle1/pose' in said, said
        assert time.monotonic() - up < 5.0, said
    assert 'move done' in done.stdout
    assert time.monotonic() - up < 5.0

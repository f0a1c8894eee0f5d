"""The node's control timer moves to mid-step of a simulator running as a program of its own (on
its own clock, as the real turtlesim): wherever the two started, after a second the ticks fall
half a step after the poses arrive. Measured from outside the lock: each tick's time, and the
poses' arrival at a separate node in the same process."""

from __future__ import annotations

import statistics
import time

import pytest

from turtle_traj.core.turtlesim_contract import STEP_S

pytestmark = pytest.mark.system  # starts a program: `make check` leaves it out

SETTLE_S = 1.5  # the lock needs a fifth of a second of poses; the simulator, time to start
MEASURE_S = 1.5


def test_the_control_ticks_fall_in_mid_step_of_a_simulator_on_its_own_clock(
        rclpy_context, monkeypatch, tmp_path):
    from rclpy.node import Node
    from turtlesim.msg import Pose

    from turtle_traj.node.run_manager import RunManager
    from turtle_traj.node.trajectory_node import TrajectoryNode
    from turtle_traj.rosutils.runtime import events_executor
    from turtle_traj.testing.processes import program

    ticks: list[float] = []
    tick = RunManager.on_control_timer

    def timed_tick(self) -> None:
        ticks.append(time.monotonic())
        tick(self)
    monkeypatch.setattr(RunManager, 'on_control_timer', timed_tick)
    arrivals: list[float] = []
    with program('turtle_traj.sim', cwd=tmp_path):
        node = TrajectoryNode(context=rclpy_context)
        watcher = Node('pose_arrivals', context=rclpy_context)
        watcher.create_subscription(Pose, 'turtle1/pose',
                                    lambda _: arrivals.append(time.monotonic()), 100)
        executor = events_executor(context=rclpy_context)
        executor.add_node(node)
        executor.add_node(watcher)
        try:
            end = time.monotonic() + SETTLE_S + MEASURE_S
            while time.monotonic() < end:
                executor.spin_once(timeout_sec=0.05)
        finally:
            executor.shutdown()
            watcher.destroy_node()
            node.destroy_node()
    since = end - MEASURE_S
    measured = [t for t in ticks if t >= since]
    assert len(arrivals) > 50 and len(measured) > 50, (len(arrivals), len(measured))
    # each tick's time after the latest pose's arrival, in steps
    after = [(t - max(a for a in arrivals if a <= t)) / STEP_S for t in measured]
    assert 0.3 <= statistics.median(after) <= 0.7, sorted(after)
    # and the timer keeps the simulator's rate: one tick a step, as the steps came (the
    # simulator's timer, like turtlesim's, never catches up a step it was held from)
    steps = [a for a in arrivals if a >= since]
    step_s = (steps[-1] - steps[0]) / (len(steps) - 1)
    assert step_s == pytest.approx(STEP_S, rel=0.05)
    assert (measured[-1] - measured[0]) / (len(measured) - 1) == pytest.approx(step_s, rel=0.02)

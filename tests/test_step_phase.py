"""The control ticks lock to mid-step of the robot's steps (`StepPhase`), checked against the
poses' own schedule: a robot stepping every 16 ms at a phase of its own, a node timer that fires
as rcl's does (its next call fixed as it fires, the period set in the callback taking effect a
tick later)."""

from __future__ import annotations

import random

import numpy as np
import pytest

from turtle_traj.core.control.step_phase import DEAD_BAND, KNOWN, StepPhase

STEP_S = 0.016


def _run(pose_phase: float, seconds: float, *, pose_period_s: float = STEP_S,
         delay=lambda k: 0.0, late=lambda n: 0.0, driving=lambda t: False,
         calls: list[float] | None = None) -> list[float]:
    """Tick times of a timer locked by `StepPhase` to poses published at `pose_phase` (in
    steps) of each period and delivered `delay(k)` later; a tick fires `late(n)` after its
    call time (the times it was called for go to `calls`); a run is driven while
    `driving(t)`."""
    calls = [] if calls is None else calls
    phase = StepPhase(STEP_S)
    arrivals = sorted(pose_phase * pose_period_s + k * pose_period_s + delay(k)
                      for k in range(int(seconds / pose_period_s)))
    ticks, call_s, period, n = [], 0.0, STEP_S, 0
    for arrival in arrivals:
        while call_s + late(n) < arrival:
            fired = call_s + late(n)
            calls.append(call_s)
            call_s += period  # rcl: the next call is fixed as the timer fires
            period = phase.next_period(call_s, driving=driving(fired))
            ticks.append(fired)
            n += 1
        phase.pose_arrived(arrival)
    return ticks


def _after_poses(ticks: list[float], pose_phase: float) -> list[float]:
    """Each tick's phase after the pose of its step, in steps (0 to 1)."""
    return [((tick / STEP_S) - pose_phase) % 1.0 for tick in ticks]


@pytest.mark.parametrize('pose_phase', [0.0, 0.03, 0.25, 0.49, 0.51, 0.75, 0.97])
def test_ticks_move_to_mid_step_whatever_the_phase_they_started_at(pose_phase):
    ticks = _run(pose_phase, 3.0)
    settled = _after_poses(ticks[-60:], pose_phase)
    assert all(abs(after - 0.5) <= DEAD_BAND for after in settled), settled
    # locked, the timer keeps the robot's rate: one tick a step
    assert (ticks[-1] - ticks[-61]) / 60 == pytest.approx(STEP_S, rel=0.02)


@pytest.mark.parametrize('pose_phase', [0.0, 0.25, 0.49, 0.51, 0.97])
def test_the_lock_settles_in_a_fifth_of_a_second_of_poses(pose_phase):
    # a run sent as soon as the node has heard the simulator starts locked (in 33 of 75 runs,
    # the two-host recipe's first run began 0.15 to 0.5 s after the node's first pose)
    ticks = _run(pose_phase, 1.0)
    after = _after_poses([tick for tick in ticks if tick >= 0.2], pose_phase)
    assert all(abs(phase - 0.5) <= DEAD_BAND for phase in after), after


def test_while_a_run_is_driven_the_ticks_move_a_little_at_a_time():
    # a run from the first pose: the ticks move towards mid-step by an eighth of a step a tick
    # at most (towards mid-step is away from both edges: each command acts one step, as
    # predicted), and the lock settles all the same
    calls: list[float] = []
    _run(0.03, 2.0, driving=lambda t: True, calls=calls)
    assert np.diff(calls) == pytest.approx(STEP_S, abs=STEP_S / 8 + 1e-9)
    assert max(abs(np.diff(calls) - STEP_S)) > STEP_S / 16  # it did move them
    after = _after_poses([call for call in calls if call >= 1.0], 0.03)
    assert all(abs(phase - 0.5) <= DEAD_BAND for phase in after), after


def test_late_poses_and_late_ticks_do_not_pull_the_lock_off_mid_step():
    noise = random.Random(7)
    delays = {k: noise.uniform(0.0, 0.003) + (0.04 if k % 50 == 0 else 0.0)
              for k in range(400)}  # a few ms each, and a stall every 50th
    calls: list[float] = []
    _run(0.2, 6.0, delay=delays.__getitem__, late=lambda n: noise.uniform(0.0, 0.002),
         calls=calls)
    settled = _after_poses(calls[-100:], 0.2)
    # the step is where the least delayed poses arrive (a tenth of them are delayed less than
    # 0.3 ms), not their mean (1.5 ms late, which would put the calls 0.09 step later)
    assert sum(settled) / len(settled) == pytest.approx(0.5 + 0.0003 / STEP_S, abs=0.04)


def test_ticks_run_late_by_chance_leave_the_schedule_in_mid_step():
    # a loaded executor runs each callback up to 6 ms late: the timer's calls, which the
    # lateness does not move, stay in mid-step (locking the times the callbacks ran instead
    # moved the whole schedule by each one's lateness)
    noise = random.Random(3)
    calls: list[float] = []
    _run(0.6, 4.0, late=lambda n: noise.uniform(0.0, 0.006), calls=calls)
    settled = _after_poses([call for call in calls if call >= 1.0], 0.6)
    assert all(abs(after - 0.5) <= DEAD_BAND for after in settled), settled


def test_poses_at_another_rate_leave_the_timer_at_its_period():
    phase = StepPhase(STEP_S)
    for k in range(200):  # a base's odometry at 30 Hz
        phase.pose_arrived(k / 30.0)
    assert phase.step_phase() is None
    assert phase.next_period(200 / 30.0 + 0.005) == STEP_S


def test_before_enough_poses_the_timer_keeps_its_period():
    phase = StepPhase(STEP_S)
    for k in range(KNOWN):  # one phase fewer than KNOWN: the first has no interval
        phase.pose_arrived(k * STEP_S)
    assert phase.tick_error(0.2) is None
    assert phase.next_period(0.2) == STEP_S

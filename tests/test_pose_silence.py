"""The watchdog's measure of silence (node/pose_silence.py), on clocks the test moves."""

from __future__ import annotations

import math

from rclpy.time import Time

from turtle_traj.node.pose_silence import PoseSilence

BEAT_S = 0.05


class Clocks:
    """A node clock and a wall clock, both set by the test (the node clock on simulated time
    unless told otherwise, when the two are one)."""

    def __init__(self, *, simulated: bool = True) -> None:
        self.node_s, self.wall_s = 100.0, 0.0
        self.ros_time_is_active = simulated

    def now(self) -> Time:
        return Time(nanoseconds=round(self.node_s * 1e9))

    @property
    def handle(self) -> Clocks:  # read as rclpy's clocks are: handle.get_now().nanoseconds
        return self

    def get_now(self) -> Time:
        return self.now()

    def wall(self) -> float:
        return self.wall_s


def _silence(clocks: Clocks) -> PoseSilence:
    return PoseSilence(clocks, BEAT_S, wall=clocks.wall)


def test_before_any_pose_and_after_forgetting_the_silence_is_endless():
    clocks = Clocks()
    silence = _silence(clocks)
    assert silence.seconds() == math.inf
    silence.heard()
    silence.forget()
    assert silence.seconds() == math.inf


def test_a_moving_node_clock_measures_the_silence_whatever_the_wall_clock_does():
    clocks = Clocks()
    silence = _silence(clocks)
    silence.heard()
    clocks.node_s += 0.3
    clocks.wall_s += 7.0  # a loaded machine: simulated time is what counts
    silence.beat()
    assert math.isclose(silence.seconds(), 0.3)


def test_a_standing_node_clock_counts_wall_time_beat_by_beat():
    clocks = Clocks()
    silence = _silence(clocks)
    silence.heard()
    for _ in range(12):  # the simulator (and its /clock) gone: beats on time
        clocks.wall_s += BEAT_S
        silence.beat()
    assert math.isclose(silence.seconds(), 12 * BEAT_S)


def test_a_late_beat_counts_as_two_at_most_and_a_pose_starts_the_count_again():
    clocks = Clocks()
    silence = _silence(clocks)
    silence.heard()
    clocks.wall_s += 5.0  # a callback held the whole process (and simulated time) for 5 s
    silence.beat()
    assert math.isclose(silence.seconds(), 2 * BEAT_S)
    clocks.wall_s += 0.02
    silence.heard()
    clocks.wall_s += 0.03
    silence.beat()
    assert math.isclose(silence.seconds(), 0.03)  # from the pose, not from the beat before


def test_on_the_wall_clock_a_stall_of_this_process_is_not_the_simulators_silence():
    clocks = Clocks(simulated=False)
    silence = _silence(clocks)
    silence.heard()
    clocks.wall_s += 0.02
    assert math.isclose(silence.seconds(), 0.02)  # between beats, as time passes
    for _ in range(20):  # the simulator gone, this process running: every beat counts
        clocks.wall_s += BEAT_S
        silence.beat()
    assert math.isclose(silence.seconds(), 20 * BEAT_S + 0.02)
    silence.heard()
    clocks.wall_s += 1.4  # the executor ran none of the callbacks: a pose waits in the queue
    assert math.isclose(silence.seconds(), 2 * BEAT_S)
    silence.beat()
    silence.heard()  # the pose that waited
    assert silence.seconds() == 0.0


def test_beats_while_a_node_of_the_process_computes_beside_its_executor_count_no_silence():
    """Lock-step holds the simulator while a node plans beside its executor (the fleet
    coordinator, for seconds under load): the node clock stands still, yet that is no silence;
    once the work is handed over, beats count again."""
    clocks, computing = Clocks(), [True]
    silence = PoseSilence(clocks, BEAT_S, wall=clocks.wall, held=lambda: computing[0])
    silence.heard()
    for _ in range(40):  # 2 s of beats on time, the world held
        clocks.wall_s += BEAT_S
        silence.beat()
    assert silence.seconds() <= 2 * BEAT_S
    computing[0] = False
    for _ in range(12):
        clocks.wall_s += BEAT_S
        silence.beat()
    assert math.isclose(silence.seconds(), 12 * BEAT_S)

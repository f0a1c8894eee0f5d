"""The node's control timer, kept in the middle of the robot's steps (`StepPhase`)."""

from __future__ import annotations

from collections.abc import Callable

from rclpy.clock import Clock, ClockType
from rclpy.node import Node

from turtle_traj.core.control.step_phase import StepPhase
from turtle_traj.rosutils.clock_read import now_ns


class ControlTimer:
    """Calls `on_tick` every `period_s` on the node clock. On wall-clock time, the ticks are
    moved to mid-step of a robot whose poses arrive at that period (`pose_arrived`, called as
    each pose arrives): the timer's period is set until they are, at once between runs and
    gently while one is driven (`driving` says whether one is). On simulated time the robot
    steps on the node's own clock: nothing to lock."""

    def __init__(self, node: Node, period_s: float, on_tick: Callable[[], None],
                 driving: Callable[[], bool]) -> None:
        self._on_tick = on_tick
        self._driving = driving
        self._phase = StepPhase(period_s)
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._node_clock = node.get_clock()
        self._period_ns = round(period_s * 1e9)
        self.timer = node.create_timer(period_s, self._tick)

    @property
    def _locks(self) -> bool:
        """On wall-clock time (`use_sim_time` may be set live)."""
        return not self._node_clock.ros_time_is_active

    def pose_arrived(self) -> None:
        if self._locks:
            self._phase.pose_arrived(self._now_s())

    def _tick(self) -> None:
        self._on_tick()
        until_next_ns = self.timer.time_until_next_call() if self._locks else None
        if until_next_ns is not None:  # (fixed as the timer fired)
            next_call_s = self._now_s() + until_next_ns * 1e-9
            period_s = self._phase.next_period(next_call_s, driving=self._driving())
        else:
            period_s = self._phase.period_s
        period_ns = round(period_s * 1e9)
        if period_ns != self._period_ns:
            self.timer.timer_period_ns = self._period_ns = period_ns

    def _now_s(self) -> float:
        return now_ns(self._steady) * 1e-9

"""How long the driven turtle's poses have been silent, as the node's watchdog judges it."""

from __future__ import annotations

import math
import time
from collections.abc import Callable

from rclpy.clock import ROSClock

from turtle_traj.rosutils.clock_read import now_ns


class PoseSilence:
    """Time since the last pose. On simulated time, on the node clock (the same verdict under
    any load), and on the wall clock only while the node clock stands still (a simulator that
    published /clock has vanished). Wall time counts only while the watchdog keeps its beat: a
    process that could not run its callbacks could not hear the poses either, and they wait
    in its queue. So on the wall clock (no simulated time) a stall of this process is not the
    simulator's silence: on rclpy 7.1.6's MultiThreadedExecutor the node's callbacks stalled
    for up to 1.4 s while every pose was on its way (tests/test_multithreaded.py). Nor is the
    time a node of this process computes beside its executor (`offload`): lock-step holds the
    simulator meanwhile, as for a callback (the fleet coordinator's plan stood simulated time
    still for seconds under load, and a turtle driving its own request took it for silence).
    """

    def __init__(self, clock: ROSClock, beat_s: float,
                 wall: Callable[[], float] = time.monotonic,
                 held: Callable[[], bool] = lambda: False) -> None:
        """:param held: whether a node of this process computes beside its executor now."""
        self._clock, self._beat_s, self._wall, self._held = clock, beat_s, wall, held
        self._pose_ns: int | None = None  # the node clock as the last pose arrived
        self._wall_s = math.inf  # since the last pose, counted beat by beat
        self._last_beat_s = wall()

    def heard(self) -> None:
        """A pose arrived now."""
        self._pose_ns, self._wall_s = now_ns(self._clock), 0.0
        self._last_beat_s = self._wall()  # wall silence counts from here

    def was_busy(self) -> None:
        """This node was busy until now with work the world may have waited for (a plan:
        lock-step holds the simulator while a node computes, and only the wall clock runs):
        silence counts from now, when a pose had arrived before. A simulator that vanished
        meanwhile is found a pose_timeout later."""
        if self._pose_ns is not None:
            self.heard()

    def forget(self) -> None:
        """As if no pose had ever arrived (a new turtle)."""
        self._pose_ns = None

    def beat(self) -> None:
        """The watchdog's beat. A late one means this process was busy (a long callback, a
        starved machine): that gap counts as one beat, not as silence of the simulator; a beat
        while a node of this process computes beside its executor counts none."""
        now = self._wall()
        if not self._held():
            self._wall_s += min(now - self._last_beat_s, 2 * self._beat_s)
        self._last_beat_s = now

    def seconds(self) -> float:
        """Seconds without a pose (inf before the first)."""
        if self._pose_ns is None:
            return math.inf
        if self._clock.ros_time_is_active:  # simulated time
            silence = (now_ns(self._clock) - self._pose_ns) * 1e-9
            if silence > 0.0:
                return silence
        return self._wall_s + min(self._wall() - self._last_beat_s, 2 * self._beat_s)

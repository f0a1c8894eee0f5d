"""How long the driven turtle's poses have been silent, as the node's watchdog judges it."""

from __future__ import annotations

import math
import time
from collections.abc import Callable

from rclpy.clock import Clock
from rclpy.time import Time


class PoseSilence:
    """Time since the last pose: on the node clock (simulated time gives the same verdict under
    any load), and on the wall clock only while the node clock stands still (a simulator that
    published /clock has vanished). Wall time then counts only while the watchdog keeps its
    beat: a long callback elsewhere in a lock-step process also holds simulated time still,
    and no simulator vanished then.
    """

    def __init__(self, clock: Clock, beat_s: float,
                 wall: Callable[[], float] = time.monotonic) -> None:
        self._clock, self._beat_s, self._wall = clock, beat_s, wall
        self._pose_time: Time | None = None
        self._wall_s = math.inf  # since the last pose, counted beat by beat
        self._last_beat_s = wall()

    def heard(self) -> None:
        """A pose arrived now."""
        self._pose_time, self._wall_s = self._clock.now(), 0.0
        self._last_beat_s = self._wall()  # wall silence counts from here

    def was_busy(self) -> None:
        """This process could not hear poses until now (it planned a run: a text with rounded
        corners takes seconds): silence counts from now, when a pose had arrived before. Poses
        that came meanwhile are still queued; a simulator that vanished is found a
        pose_timeout later."""
        if self._pose_time is not None:
            self.heard()

    def forget(self) -> None:
        """As if no pose had ever arrived (a new turtle)."""
        self._pose_time = None

    def beat(self) -> None:
        """The watchdog's beat. A late one means this process was busy (a long callback, a
        starved machine): that gap counts as one beat, not as silence of the simulator."""
        now = self._wall()
        self._wall_s += min(now - self._last_beat_s, 2 * self._beat_s)
        self._last_beat_s = now

    def seconds(self) -> float:
        if self._pose_time is None:
            return math.inf
        silence = (self._clock.now() - self._pose_time).nanoseconds * 1e-9
        return silence if silence > 0.0 else self._wall_s

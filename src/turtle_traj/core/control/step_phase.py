"""Where the control ticks fall in the robot's step, and the timer period that keeps them in its
middle. Pure.

The robot steps on its own clock (turtlesim's 16 ms timer) and takes, at each step, the command
that has arrived by then. A node ticking on another clock at the same rate sends each command at
a fixed phase of that step, set by when the two programs started: a command that arrives just
before a step is a step late after the least delay, and one that arrives just after it, a step
early. At that knife-edge the commands' latency flips between two values (the model sees jitter
and hedges: slower drawings), or stays on one side until a stall flips it at a corner (a
deadbeat approach then draws one step past it). A tick half a step after the poses arrive puts
the command's arrival as far from both edges as it can be: only a delay of half a step moves it.

Each pose is published as the robot steps, so the least delayed poses' arrival times give the
step's phase (on this node's clock, whatever the robot's clock says). The timer's schedule is what
is locked, not the times its callbacks ran (a loaded executor runs them late, by chance): a timer's
next call is fixed as it fires, so `next_period`, given that call's time, returns the period that
brings the call after it towards mid-step; a dead band leaves a locked timer at its period. Between
runs the whole error is corrected at once, so the lock settles in the first tenths of a second of
poses, before the first run. While a run is driven, a quarter of it, at most an eighth of a step a
tick: the poses' phase moves by a millisecond or two once the turtle is driven, and a tick that
moves towards mid-step moves away from both edges, so no command acts a step more or less than
predicted.
"""

from __future__ import annotations

import math
from collections import deque

TARGET = 0.5  # steps after the pose's arrival: mid-step
MAX_CORRECTION = 0.5  # steps: the most one period is shortened or lengthened (any phase, once)
DRIVING_GAIN = 0.25  # of the error corrected each tick while a run is driven
DRIVING_MAX_CORRECTION = 0.125  # steps: the most a period changes while a run is driven
DEAD_BAND = 0.1  # steps: a phase error this small is left alone
STEADY = (0.75, 1.25)  # an arrival this many steps after the one before shows the phase
WINDOW = 64  # arrivals remembered (about 1 s of turtlesim's)
# steady arrivals that show the phase: 0.13 s of turtlesim's poses; more refine it
KNOWN = 8
# The step is where the least delayed poses arrive: this share of them arrives earlier. A pose
# is only ever delayed (a busy simulator, link or executor), so their mean arrival is late by
# the delays' mean: 0.8-2.4 ms later than their 10th percentile in the two-host loop under load,
# and a tick half a step after the mean came that much nearer the step's far edge.
EARLY_SHARE = 0.1


class StepPhase:
    """The phase of the robot's steps, from the poses' arrival times, and the tick period.

    :param period_s: the control timer's period, and the step it locks to: the lock holds only
        while the poses arrive at that rate (a base's odometry at another rate is left alone).
    """

    def __init__(self, period_s: float) -> None:
        self.period_s = period_s
        self._origin_s: float | None = None
        self._last_arrival_s: float | None = None
        self._phases: deque[float] = deque(maxlen=WINDOW)  # radians, of steady arrivals

    def pose_arrived(self, now_s: float) -> None:
        """A pose arrived (seconds, on the clock the ticks are given on)."""
        if self._origin_s is None:
            self._origin_s = now_s
        last, self._last_arrival_s = self._last_arrival_s, now_s
        if last is None:
            return
        interval = (now_s - last) / self.period_s
        if not STEADY[0] <= interval <= STEADY[1]:
            return  # a late pose, or one read with others: its time tells no phase
        self._phases.append(2.0 * math.pi * self._in_steps(now_s))

    def step_phase(self) -> float | None:
        """When the least delayed poses arrive (EARLY_SHARE arrive earlier), as a fraction of
        a step after the origin (None: not yet known, or they do not arrive once a period)."""
        if len(self._phases) < KNOWN:
            return None
        mean = math.atan2(sum(map(math.sin, self._phases)), sum(map(math.cos, self._phases)))
        offsets = sorted((phase - mean + math.pi) % (2.0 * math.pi) - math.pi
                         for phase in self._phases)
        early = offsets[int(EARLY_SHARE * len(offsets))]
        return ((mean + early) / (2.0 * math.pi)) % 1.0

    def tick_error(self, now_s: float) -> float | None:
        """How far after mid-step a tick at `now_s` falls, in steps (-0.5 to 0.5)."""
        arrival = self.step_phase()
        if arrival is None:
            return None
        return (self._in_steps(now_s) - arrival - TARGET + 0.5) % 1.0 - 0.5

    def next_period(self, next_call_s: float, *, driving: bool = False) -> float:
        """The timer period to set at a tick whose next call is at `next_call_s` (seconds): one
        that brings the call after it to mid-step, or while `driving` (a run is driven) a
        quarter of the way; the period itself once the calls are there, and before the phase
        is known."""
        error = self.tick_error(next_call_s)
        if error is None or abs(error) < DEAD_BAND:
            return self.period_s
        if driving:
            limit, error = DRIVING_MAX_CORRECTION, DRIVING_GAIN * error
        else:
            limit = MAX_CORRECTION
        return self.period_s * (1.0 - max(-limit, min(limit, error)))

    def _in_steps(self, time_s: float) -> float:
        return ((time_s - self._origin_s) / self.period_s) % 1.0

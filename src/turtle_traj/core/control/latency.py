"""Latency compensation: where the turtle will be when the next command takes effect.

A command acts one or more simulator steps after the pose it was computed from (pose ->
controller -> simulator), more under load. turtlesim's pose echoes the velocities in effect at
its step (the linear one as a magnitude, in float32), so the newest command sent whose values
match the echo is the one acting; those sent after it are still on their way. Replaying them
with turtlesim's own integration (heading first, then position along the new heading) predicts
the pose from which the next command will act. Pure Python: no ROS.

On a straight line every command is the same, and an echo would match them all; so each
command is moved by a few float32 steps (`distinct`: a relative 4e-6 at most, towards the
command before it) until its echo is unlike any other remembered. The echo then names the
command in effect on any path.

A backlog: turtlesim takes one queued command per step, the oldest, and its subscription keeps
7. Commands that arrive in a burst (a stall of a reliable stream on a lossy link, then its
repair; a starved sender) therefore queue up, and as one is sent and one taken every period,
the queue never shrinks again: every later command acts up to 6 periods (96 ms) late, measured
across two hosts at 5% loss. `backlog` is how many commands wait beyond the least latency seen
lately; the control loop sends nothing for that many periods, and the queue drains (a step
without a new command goes on with the last one, as turtlesim does).
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from turtle_traj.core.control.commands import COMMAND_LIFESPAN_S, STOP, Command
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Pose2D

_HISTORY = 32  # commands remembered: far more than any latency we can steer through
# Observations over which the latency's variation is judged (16 s of driving; idle poses tell
# nothing, and the link is what it was): on a link that loses 1% of its packets a command stalls
# every second or two, so a 2 s memory forgot the last stall often enough for the next to catch a
# leg's end at full deadbeat speed (text "ROS": 6.9 mm against 0.9 mm with 16 s,
# bench/network_bench.py).
_SPREAD_WINDOW = 1024
# A period above the least latency is timing jitter (two timers' phases), unless it lasts: then
# it is a command queued for good.
_JITTER_PERIODS, _JITTER_LASTS = 1, 32


_STANDING = (0.0, 0.0)  # the echo of a turtle that stands: a stop in effect, or no command


def _as_echoed(command: Command) -> tuple[float, float]:
    """The (linear_velocity, angular_velocity) a turtlesim pose reports for `command`."""
    return float(np.float32(abs(command.linear))), float(np.float32(command.angular))


class LatencyPredictor:
    """Commands sent but not yet in effect, and the pose they will lead to.

    :param period_s: how long each command acts (the simulator step, turtlesim's 16 ms).
    """

    def __init__(self, period_s: float) -> None:
        self.period_s = period_s
        # A command later than its lifespan was not delivered: the link stalled (a cut), and
        # no speed near a leg's end would help. Such a latency is not remembered as jitter, or
        # a 0.5 s cut would slow every approach to a crawl for the next 16 s of driving.
        self._stall = max(round(COMMAND_LIFESPAN_S / period_s), 1)
        # False for a pose source whose velocities are measured (odometry): an echo that
        # matches no command then says nothing, and no command counts as in flight.
        self.echoes_commands = True
        self._sent: deque[Command] = deque(maxlen=_HISTORY)
        self._sent_echoes: deque[tuple[float, float]] = deque(maxlen=_HISTORY)  # _as_echoed
        self.in_flight = 0  # commands sent after the one the last pose showed in effect
        self._seen_in_effect = False
        self._recent: deque[int] = deque(maxlen=_SPREAD_WINDOW)
        self._recent_counts = [0] * (_HISTORY + 1)  # of each count in _recent: its least, most
        self._echo = _STANDING
        self._sent_since_pose = 0  # commands sent since the last pose was observed
        self._above_least = 0  # observations in a row with more in flight than the least

    def distinct(self, command: Command) -> Command:
        """`command` moved by the fewest float32 steps that give it an echo unlike those of the
        commands remembered: its speed (its turn rate, when it has no speed), towards the last
        command sent, then on towards zero. So it keeps within any limit of speed that it was
        within, and its change from the one before grows by a few float32 steps at most. A stop
        stays a stop."""
        if not self.echoes_commands or command == STOP:
            return command
        taken = set(self._sent_echoes)
        if _as_echoed(command) not in taken:
            return command
        on_linear = command.linear != 0.0
        exact = command.linear if on_linear else command.angular
        last = self.last_sent.linear if on_linear else self.last_sent.angular
        value, towards = np.float32(exact), np.float32(last)
        if abs(float(value) - last) > abs(exact - last):  # rounded away from the last one
            value = np.nextafter(value, towards)
        for _ in range(_HISTORY + 1):
            candidate = (Command(float(value), command.angular) if on_linear
                         else Command(command.linear, float(value)))
            if _as_echoed(candidate) not in taken:
                return candidate
            if value == towards:
                towards = np.float32(0.0)
            value = np.nextafter(value, towards)
            if value == 0.0:
                break
        return command  # a value fewer float32 steps from zero than commands remembered

    def sent(self, command: Command) -> None:
        """Record a command as it is published."""
        self._sent.append(command)
        self._sent_echoes.append(_as_echoed(command))
        self._sent_since_pose += 1

    def _moves_older_than(self, back: int) -> bool:
        """Whether a command that moves was sent before the one `back` commands ago, and after
        the one the last pose showed in effect. A turtle that stood and still stands cannot be
        on a stop sent after such a command: turtlesim takes commands in order, and that one
        would have moved it first. (Its echo would name the stop: at the start of a run, ten
        commands on their way looked like none, and the turtle was sent ten more.)"""
        echoes = list(self._sent_echoes)
        last_in_effect = (self.in_flight + self._sent_since_pose if self._seen_in_effect
                          else len(echoes))  # how far back; the whole history before any
        return any(echoes[-1 - older] != _STANDING
                   for older in range(back + 1, min(last_in_effect, len(echoes))))

    def observe(self, linear_echo: float, angular_echo: float) -> int:
        """Update the count of commands in flight from a pose's velocity echo; return it.

        A run of identical commands matches more than once; the match nearest the previous
        count wins, as latency changes slowly. An echo that matches nothing means, before any
        command was seen in effect, that all are still in flight; later it is someone else's
        command (a stale one, the 1 s timeout) and the last count stands.
        """
        echo = (linear_echo, angular_echo)
        matches = [back for back, sent in enumerate(reversed(self._sent_echoes))
                   if sent == echo]
        if echo == _STANDING and self._echo == _STANDING:
            matches = [back for back in matches if not self._moves_older_than(back)]
        self._sent_since_pose = 0
        if matches:
            # Between two poses one command is sent and one takes effect: the count holds.
            self.in_flight = min(matches, key=lambda back: abs(back - self.in_flight))
            self._seen_in_effect = True
            least = self._least() if self._recent else 0
            # A run of equal commands tells nothing of the latency; a stall is not jitter.
            if len(matches) == 1 and self.in_flight - least <= self._stall:
                self._remember(self.in_flight)
        elif not self._seen_in_effect and self.echoes_commands:
            self.in_flight = len(self._sent)
        above = bool(self._recent) and self.in_flight > self._least()
        self._above_least = self._above_least + 1 if above else 0
        self._echo = echo
        return self.in_flight

    @property
    def backlog(self) -> int:
        """Commands queued at the simulator beyond the least latency seen lately (and a
        period of jitter, for a while): a queue that a burst filled and that nothing drains."""
        if not self._recent:
            return 0
        jitter = _JITTER_PERIODS if self._above_least < _JITTER_LASTS else 0
        return max(self.in_flight - self._least() - jitter, 0)

    def held(self) -> None:
        """A period passed with no command sent: the oldest in flight took effect."""
        self.in_flight = max(self.in_flight - 1, 0)

    @property
    def spread(self) -> int:
        """How many periods the latency varied by lately: 0 when it is steady (lock-step, or
        a fixed delay), so that the prediction is exact; more under jitter."""
        if not self._recent:
            return 0
        most = next(count for count in range(_HISTORY, -1, -1) if self._recent_counts[count])
        return most - self._least()

    def forget_spread(self) -> None:
        """Judge the latency afresh: the link was cut or the simulator restarted, and what the
        commands met before says little of what they meet now."""
        self._recent.clear()
        self._recent_counts = [0] * (_HISTORY + 1)
        self._above_least = 0

    def _remember(self, in_flight: int) -> None:
        if len(self._recent) == self._recent.maxlen:
            self._recent_counts[self._recent[0]] -= 1
        self._recent.append(in_flight)
        self._recent_counts[in_flight] += 1

    def _least(self) -> int:
        """The fewest commands in flight seen lately (the window holds a count)."""
        return next(count for count, seen in enumerate(self._recent_counts) if seen)

    def overrun(self) -> tuple[float, float]:
        """How far (m, rad) the turtle may move beyond the prediction: a command may arrive up
        to `spread` periods late, and until then the one before it goes on acting."""
        late_s = self.spread * self.period_s
        acting = [Command(*self._echo), *self._pending()]
        return (max(abs(command.linear) for command in acting) * late_s,
                max(abs(command.angular) for command in acting) * late_s)

    @property
    def last_sent(self) -> Command:
        """The command that will be in effect when the next one takes over: the last one
        sent, or before any, the velocity the last pose reported (a magnitude, for turtlesim)."""
        return self._sent[-1] if self._sent else Command(*self._echo)

    @property
    def still(self) -> bool:
        """Nothing moves the turtle: it stands, and every command on its way is a stop."""
        return self._echo == _STANDING and all(command == STOP for command in self._pending())

    def _pending(self) -> list[Command]:
        return list(self._sent)[len(self._sent) - self.in_flight:] if self.in_flight else []

    def predict(self, pose: Pose2D) -> Pose2D:
        """The pose after every command in flight has acted for one period."""
        x, y, theta = pose.x, pose.y, pose.theta
        for command in self._pending():
            theta += command.angular * self.period_s
            x += command.linear * math.cos(theta) * self.period_s
            y += command.linear * math.sin(theta) * self.period_s
        return Pose2D(x, y, wrap_angle(theta))

"""The controller's model of the robot: where it will be when the next command takes effect. Pure.

The model, in one page:

* **The robot steps, and takes commands in order.** At each step (turtlesim's 16 ms) it takes
  the oldest command that has arrived and not been taken, if any, and integrates with the one in
  effect; a step with none keeps the last (turtlesim and our bases do exactly this). A command
  acts until the next one is taken: one step each when the robot has a queue, longer when this
  node sent the next one late (a busy executor, a skipped period).
* **Two clocks, one offset.** Commands are stamped as they are sent (node clock, counted in
  steps). Poses arrive one per robot step, in order, even late ones: counting them counts the
  robot's steps. A command first seen in effect at pose `k`, sent at step `t`, took `k - t`
  steps to arrive and act; that offset is the link's latency as the robot's clock sees it. Its
  floor (`RunningFloor`, of the median of three) is the latency without a queue; how much
  later than the one before a command arrives (95th percentile) is the jitter. A lost pose,
  or a cut link, lowers the offsets for good: the floor falls with the second lower one.
* **An observer says which command is in effect** (`observers`): turtlesim's pose echoes its
  velocities, and the command whose echo matches is in effect; a base's odometry measures its
  velocity instead, which names no command, and the latency that best explains the last poses'
  motion says which one is due. What the robot is (how its step moves it, when it stands, which
  observer it needs) is one description, `observers.Robot`.
* **The prediction** replays the command in effect and every command in flight from the pose,
  each from the step it arrives (its stamp plus the latency, and not before the step after the
  one before it) to the next one's, with turtlesim's integration (heading first, then position
  along the new heading). In lock-step each arrives the step after the one before, exactly.
* **The uncertainty** is a distribution, not a worst case. `late_steps`, how many steps longer
  than one the next command may act, is the jitter's 99th percentile (an approach that misses
  it draws past the leg's end) plus how much later than one step the 95th percentile of this
  node's control timer fires after the tick before. Each is a running quantile
  (`RunningQuantile`): a stall seen once moves it by a fraction of a step, which the next
  observations take back (for the 99th, within about 1.5 s of driving), so approaches stay
  brisk; jitter that lasts, as loss on a link does, is hedged: such an approach stops inside
  the end's tolerance, and one more command lands on the end once the turtle stands there.
  On a base with inertia the approach is the whole braking, at its limit, and a command of it
  acting a step late leaves the base a step further on for good: there the quantile is per
  braking, not per command (`braking_overrun`): one late command among the last 6400 makes
  the braking allow for a step (seen by the echo: a latency fitted to odometry wavers by a
  step as a fit does, and is left out).
* **Faults are observations.** A stalled link holds commands back, and its repair lets them
  through together, to queue at turtlesim's 7-deep subscription: either way commands are
  overdue (in flight longer than the floor), `excess` says how many beyond the jitter, and the
  control loop sends nothing meanwhile (the command before acts on, as predicted); the queue
  drains (a hold still ends a run that makes no progress). One command waiting (a busy robot
  stepped before it arrived) is drained only where holding the last command a step longer
  drives the robot as the next would (a straight line, a steady turn, a stop); elsewhere, a
  braking above all, the hold would shift the rest of the motion by a step, so it stays: the
  floor takes it in, as predicted, and it buffers the next late arrival. A command in flight
  past its 0.2 s lifespan was dropped by the writer (a loss repaired too late): it is in flight
  no longer. A cut link loses poses too: the step count falls behind, and the floor with it, at
  the second command seen. An executor that dispatches late: the stamps say how long each
  command acted; poses it delivers late still count the steps.
"""

from __future__ import annotations

import math
from collections import deque

from turtle_traj.core.control.commands import COMMAND_LIFESPAN_S, STOP, Command
from turtle_traj.core.control.echo import HISTORY, STANDING, Echo, as_echoed
from turtle_traj.core.control.observers import TURTLESIM, PoseReading, Robot, Sent
from turtle_traj.core.control.prediction import Prediction
from turtle_traj.core.control.quantile import RunningFloor, RunningQuantile, WindowQuantile
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Pose2D

CONFIDENCE = 0.95  # the share of commands that act no later than predicted
# The share a leg's approach allows for: a command there that acts a step late is drawn, one
# step at full speed past the end (a lost packet repaired, at 5% loss one command in twenty)
APPROACH_CONFIDENCE = 0.99
# On a base with inertia the approach is the whole braking, at the deceleration limit: any one
# of its commands that acts a step late shifts the rest of it, and the base, already braking as
# hard as it can, stops that step past the end. Braking from top speed takes about a second of
# commands; for the approach's confidence each of them must act on time with this one: the
# most of the last 1 / (1 - confidence) commands (6400, 100 s of driving; `WindowQuantile`).
BRAKING_COMMANDS = 64
BRAKING_WINDOW = round(BRAKING_COMMANDS / (1.0 - APPROACH_CONFIDENCE))
RATE = 0.25  # steps: the most one observation moves a running quantile
# A robot that steps on its own timer, the link's timing not yet seen: a leg's end allows for
# a command a step late, as if one had been seen. Else the first stall of the sending process
# at a corner (a loaded machine) lets the last command of the approach act a step longer, up
# to 10 mm past it at the exact follower's braking. The allowance fades as commands are seen
# to act on time, by RATE * (1 - APPROACH_CONFIDENCE) each: below half a step after 200
# commands, about 3 s of driving.
COLD_START_LATE_STEPS = 1.0


class RobotModel:
    """Commands sent, the evidence of which one acts, and the prediction they make.

    It is the `observers.CommandLog` its observer reads (`remembered`, `echoes`, `first`,
    `count`, `in_effect`, `poses`, `floor`, `at_rest`).

    :param step_s: how long each command acts at least (the robot's step, turtlesim's 16 ms).
    :param robot: what the robot is: turtlesim, or a base seen through its odometry.
    :param late_prior: how many steps late a command may act at a leg's end before any
        command was seen to act (`APPROACH_CONFIDENCE`'s quantile before its observations;
        see `COLD_START_LATE_STEPS`).
    """

    def __init__(self, step_s: float, *, robot: Robot = TURTLESIM,
                 late_prior: float = 0.0) -> None:
        self.step_s = step_s
        self.robot = robot
        self._observer = robot.observer(step_s)
        self.remembered: deque[Sent] = deque(maxlen=HISTORY)  # the commands, oldest first
        self.echoes: dict[Echo, list[int]] = {}  # their numbers by echo, oldest first
        self.count = 0  # commands sent so far: the next one's number
        self._origin_s: float | None = None  # the first stamp: steps are counted from it
        self.poses = 0  # robot steps, as counted by the poses observed
        self.in_effect: int | None = None  # the number of the command in effect, if known
        self._echo = STANDING
        self._latency = RunningFloor(1.0 - CONFIDENCE, RATE)  # steps, without a queue
        self._latencies: deque[float] = deque(maxlen=3)  # of the last commands seen to act
        # steps later than the one before; the timer's steps from one tick to the next
        self._jitter = RunningQuantile(CONFIDENCE, RATE, prior=0.0)
        self._jitter_tail = RunningQuantile(APPROACH_CONFIDENCE, RATE, prior=late_prior)
        self._jitter_braking = WindowQuantile(BRAKING_WINDOW)
        self._last_tick: float | None = None
        self._follows = RunningQuantile(CONFIDENCE, RATE, prior=1.0)

    @property
    def in_flight(self) -> int:
        """Commands sent after the one in effect at the last pose."""
        if self.in_effect is None:
            return len(self.remembered)
        return min(self.count - 1 - self.in_effect, len(self.remembered))

    @property
    def last_sent(self) -> Command:
        """The command in effect when the next one takes over: the last one sent, or before
        any, the velocity the last pose reported (a magnitude, for turtlesim)."""
        return self.remembered[-1].command if self.remembered else Command(*self._echo)

    def distinct(self, command: Command) -> Command:
        """`command` as it is to be sent, so that the poses can name it (`echo.distinct`: moved
        by a few float32 steps if its echo would name another command remembered)."""
        return self._observer.distinct(command, self, self.last_sent)

    def ticked(self, now_s: float) -> None:
        """The control timer fired (node clock, seconds), with a run or without: how long
        after the last tick says how long a command may act before the next one is sent."""
        if self._origin_s is None:
            self._origin_s = now_s
        tick = self._in_steps(now_s)
        if self._last_tick is not None:
            self._follows.add(tick - self._last_tick)
        self._last_tick = tick
        # a command in flight past its lifespan was dropped on the way (the writer keeps it no
        # longer): it will never act, and nothing waits for it
        lifespan = COMMAND_LIFESPAN_S / self.step_s
        while (self.in_effect is not None and self.in_flight
               and self.remembered[-self.in_flight].stamp < tick - lifespan):
            self.in_effect += 1

    def sent(self, command: Command, now_s: float) -> None:
        """Record a command as it is published (node clock, seconds)."""
        if self._origin_s is None:
            self._origin_s = now_s
        if len(self.remembered) == self.remembered.maxlen:  # the oldest is forgotten
            oldest = self.remembered[0].echo
            numbers = self.echoes[oldest]
            del numbers[0]
            if not numbers:
                del self.echoes[oldest]
        echo = as_echoed(command)
        self.remembered.append(Sent(command, echo, self._in_steps(now_s), self.poses))
        self.echoes.setdefault(echo, []).append(self.count)
        self.count += 1

    def observe(self, linear_echo: float, angular_echo: float, pose: Pose2D | None = None) -> None:
        """A pose, and the velocities it reports: the observer says which command is in effect
        (and so how many are in flight), and when it shows, how late that one acted."""
        self.poses += 1
        self._echo = (linear_echo, angular_echo)
        seen: PoseReading | None = self._observer.see(self, self._echo, pose)
        if seen is None:
            return
        if seen.latency is not None:
            self._observe_latency(seen.latency)
        if not seen.due:
            self.in_effect = seen.in_effect
        else:  # before the latency is known, the last sent (none in flight)
            self.in_effect = (self._due() if self._latency.value is not None
                              else self.count - 1 if self.remembered else None)

    @property
    def floor(self) -> float | None:
        """The latency without a queue, in steps, once known."""
        return self._latency.value

    def _due(self) -> int:
        """The newest command due by now: sent the latency's floor ago (a measured velocity
        names no command: this is the one taken to act)."""
        floor, first = self._latency.value, self.first
        due = [first + index for index, sent in enumerate(self.remembered)
               if round(sent.stamp + floor) <= self.poses]
        return due[-1] if due else first - 1

    @property
    def at_rest(self) -> bool:
        """The last pose shows the robot at rest: its velocities within what counts as rest
        for it (zero for turtlesim's echo, what odometry resolves for a base)."""
        (linear, angular), (linear_within, angular_within) = self._echo, self.robot.rest_within
        return abs(linear) <= linear_within and abs(angular) <= angular_within

    def _observe_latency(self, latency: float) -> None:
        """A command first seen in effect `latency` steps after it was sent. The floor takes
        the median of the last three: one wrong match (an echo alike by chance) moves nothing,
        and a latency that changed shows in the second command."""
        if self._latencies:
            later = latency - self._latencies[-1]
            self._jitter.add(later)
            self._jitter_tail.add(later)
            if self._observer.exact_steps:  # a fitted latency's step either way is the fit's
                self._jitter_braking.add(later)
        self._latencies.append(latency)
        if len(self._latencies) == self._latencies.maxlen:
            self._latency.add(sorted(self._latencies)[1])

    @property
    def first(self) -> int:
        """The number of the oldest command remembered."""
        return self.count - len(self.remembered)

    @property
    def excess(self) -> int:
        """Commands overdue beyond the jitter: send none now. A command is due at the robot the
        latency's floor after it was sent; one in flight past that waits (a queue that a burst
        filled, and one sent a step keeps full) or is held up (a stalled link, whose commands
        will arrive together). Each period without a command sent lets the robot take one."""
        floor = self._latency.value
        if floor is None:
            return 0
        poses = self.poses
        overdue = sum(round(sent.stamp + floor) <= poses for sent in self._pending())
        return max(overdue - max(self._jitter.whole(), 0), 0)

    def predict(self, pose: Pose2D, now_s: float) -> Prediction:
        """Where the robot will be when the next command takes effect, and how uncertain."""
        pending = self._pending()
        x, y, theta, step_s = pose.x, pose.y, pose.theta, self.step_s
        for command, steps in self._schedule(pending, now_s):
            linear, angular = command.linear, command.angular
            for _ in range(steps):
                theta += angular * step_s
                x += linear * math.cos(theta) * step_s
                y += linear * math.sin(theta) * step_s
        late = self._late_steps(self._jitter_tail)
        last = self.last_sent  # acts until the next command is taken: maybe `late` longer
        standing = self.at_rest and all(sent.command == STOP for sent in pending)
        return Prediction(Pose2D(x, y, wrap_angle(theta)), last, late, self._overrun(last, late),
                          standing, turns_first=self.robot.turns_first,
                          braking_overrun=self._overrun(
                              last, self._late_steps(self._jitter_braking)))

    def _overrun(self, last: Command, late: int) -> tuple[float, float]:
        """How far `last` carries the robot when it acts `late` steps longer (m, rad)."""
        return abs(last.linear) * late * self.step_s, abs(last.angular) * late * self.step_s

    def _pending(self) -> list[Sent]:
        """The commands in flight, oldest first."""
        remembered, in_flight = self.remembered, self.in_flight
        return [remembered[index] for index in range(len(remembered) - in_flight,
                                                     len(remembered))]

    def _schedule(self, pending: list[Sent], now_s: float) -> list[tuple[Command, int]]:
        """The command in effect and each one in flight, with the steps each acts after the
        last pose: from the step it arrives (not before the step after the one before it) to
        the next one's; the last until the next command, sent now, arrives."""
        remembered = self.remembered
        acting = ([remembered[-1 - len(pending)].command] if len(pending) < len(remembered)
                  else [Command(*self._echo)])
        acting += [sent.command for sent in pending]
        stamps = [sent.stamp for sent in pending]
        stamps.append(self._in_steps(now_s) if self._origin_s is not None else 0.0)
        # each arrives the latency after it was sent, without a queue; until the floor is
        # known, the last latency seen, and before any command was seen to take effect, the
        # oldest on its way is taken to arrive at the next step
        latency = self._latency.value
        if latency is None:
            latency = self._latencies[-1] if self._latencies else self.poses + 1 - stamps[0]
        starts, step = [], self.poses
        for stamp in stamps:
            step = max(step + 1, round(stamp + latency))
            starts.append(step)
        begins = [self.poses + 1, *starts[:-1]]
        return [(command, end - begin)
                for command, begin, end in zip(acting, begins, starts, strict=True)]

    def _late_steps(self, tail: RunningQuantile | WindowQuantile) -> int:
        return max(tail.whole(), 0) + max(self._follows.whole(1) - 1, 0)

    def _in_steps(self, stamp_s: float) -> float:
        return (stamp_s - self._origin_s) / self.step_s

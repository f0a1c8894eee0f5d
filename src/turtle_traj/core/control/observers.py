"""What the robot is, and how its poses tell which command acts: the model's two senses. Pure.

`Robot` describes a robot for the model of it (`robot_model.RobotModel`): how its step moves
it, when it counts as at rest, and the observer its poses need. Each observer says, from a
pose, which of the commands sent is in effect, and how many steps after it was sent it began
to act (`PoseReading`):

* `EchoObserver`, turtlesim's: the pose echoes the velocities of the command in effect
  (`echo`). The command whose echo matches is in effect; commands act in order, so among equal
  echoes (a run of stops) the match is the one nearest a step on from the last, never an older
  one; an echo that matches nothing is someone else's command, and the robot is taken to have
  stepped on. Each command is nudged so its echo names it alone (`echo.distinct`).
* `DelayFitObserver`, a base's: odometry measures the velocity, which names no command. The
  latency that best explains the last poses' motion is observed (`DelayFit`), and the command
  due by now is in effect.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.delay_fit import DelayFit
from turtle_traj.core.control.echo import Echo, distinct
from turtle_traj.core.geometry.path import Pose2D


@dataclass(frozen=True)
class Sent:
    """A command as the model remembers it."""

    command: Command
    echo: Echo
    stamp: float  # when it was sent, in steps since the first command
    poses: int  # poses observed by then: it acts at a later step


class CommandLog(Protocol):
    """What an observer reads of the model: the commands remembered, and what it knows."""

    remembered: Sequence[Sent]  # the commands remembered, oldest first
    echoes: Mapping[Echo, list[int]]  # the numbers of those remembered, by echo, oldest first
    first: int  # the number of the oldest remembered
    count: int  # commands sent so far: the next one's number
    in_effect: int | None  # the number of the command in effect at the last pose, if known
    poses: int  # robot steps, as counted by the poses observed
    floor: float | None  # the latency without a queue, in steps, once known
    at_rest: bool  # the last pose shows the robot at rest


@dataclass(frozen=True)
class PoseReading:
    """What a pose tells: the command in effect, and a latency when the pose shows one."""

    in_effect: int | None = None  # the number of the command in effect
    latency: float | None = None  # steps from being sent to acting
    due: bool = False  # the command due by now (sent the latency's floor ago) is in effect


class Observer(Protocol):
    """Says from each pose which command is in effect."""

    # Its latencies are whole steps, each one a command's own: a step of jitter is a command
    # that acted late (an echo), not a fit's wavering (a delay fit)
    exact_steps: bool

    def distinct(self, command: Command, model: CommandLog, last_sent: Command) -> Command:
        """`command` as it is to be sent, so that the poses can name it."""

    def see(self, model: CommandLog, echo: Echo, pose: Pose2D | None) -> PoseReading | None:
        """What the pose with velocity `echo` tells (None: nothing new)."""


class EchoObserver:
    """turtlesim's: the pose echoes the command in effect (see the module's docstring)."""

    exact_steps = True

    def __init__(self, step_s: float) -> None:
        self.step_s = step_s

    def distinct(self, command: Command, model: CommandLog, last_sent: Command) -> Command:
        return distinct(command, model.echoes, last_sent)

    def see(self, model: CommandLog, echo: Echo, pose: Pose2D | None) -> PoseReading | None:
        # among equal echoes, the one a step on from the last (the latency's floor is the
        # earliest a command may act: as a guess it would skip a moving command still on its
        # way between two stops, and the prediction would miss its step)
        expected = model.first if model.in_effect is None else model.in_effect + 1
        matches = _matches(model, echo)
        if model.in_effect is None and model.at_rest:  # as it stood before any was taken
            matches.insert(0, model.first - 1)
        if not matches:  # someone else's command (a stale one, the 1 s timeout): a step on
            if model.in_effect is None:
                return None
            return PoseReading(min(expected, model.count - 1))
        in_effect = min(matches, key=lambda number: abs(number - expected))
        if in_effect < model.first:  # none of ours was taken yet
            return None
        if in_effect == model.in_effect or len(matches) > 1:  # nothing of the latency
            return PoseReading(in_effect)
        sent = model.remembered[in_effect - model.first]
        return PoseReading(in_effect, model.poses - sent.stamp)


def _matches(model: CommandLog, echo: Echo) -> list[int]:
    """The numbers of the commands remembered whose echo is `echo`: those no older than the
    one in effect at the last pose, as commands take effect in order; any, if none is (the
    last match was wrong)."""
    matches = list(model.echoes.get(echo, ()))
    in_order = [number for number in matches if number >= (model.in_effect or 0)]
    return in_order or matches


class DelayFitObserver:
    """A base's: its measured velocity names no command; a latency fitted to the poses does
    (see the module's docstring)."""

    exact_steps = False

    def __init__(self, step_s: float) -> None:
        self._fit = DelayFit(step_s)

    def distinct(self, command: Command, model: CommandLog, last_sent: Command) -> Command:
        return command

    def see(self, model: CommandLog, echo: Echo, pose: Pose2D | None) -> PoseReading | None:
        if pose is not None:
            self._fit.add(model.poses, pose)
        latency = None
        remembered = model.remembered
        if remembered:
            lowest = min(sent.poses + 1 - math.floor(sent.stamp) for sent in remembered)
            latency = self._fit.best([(sent.stamp, sent.command) for sent in remembered], lowest)
        return PoseReading(latency=latency, due=True)


@dataclass(frozen=True)
class Robot:
    """What a robot is, for the model of it."""

    # each step turns first and then moves along the new heading (turtlesim); False: it
    # drives arcs
    turns_first: bool
    # reported velocities (m/s, rad/s) within which it counts as at rest
    rest_within: tuple[float, float]
    observer: type  # how its poses tell which command acts: made with the step (s)


# A base whose odometry measures less than this (m/s, rad/s) stands: a few encoder ticks a
# period (an XL430's 4096 a turn on 33 mm wheels 0.16 m apart, at 62.5 Hz: 3 mm/s, 0.04 rad/s).
MEASURED_STILL = (0.01, 0.05)
TURTLESIM = Robot(turns_first=True, rest_within=(0.0, 0.0), observer=EchoObserver)
ODOMETRY_BASE = Robot(turns_first=False, rest_within=MEASURED_STILL, observer=DelayFitObserver)

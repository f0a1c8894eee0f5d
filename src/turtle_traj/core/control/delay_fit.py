"""A base's latency from its odometry: the delay that best explains its recent motion. Pure.

A base's odometry measures where it went, not which command acted. Over the last `WINDOW`
poses, each candidate latency says which command acted at each step (the newest that had
arrived, sent that many steps before); the one whose commands, integrated step by step, give
the turns and distances the poses show is the latency. It is reported only when it explains
the motion clearly better than any other (the commands varied: a base cruising on one command
fits every latency alike). Odometry's velocity is quantised (0.04 rad/s for an XL430's encoder
at 62.5 Hz); its pose integrates it, and is finer.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence

from turtle_traj.core.control.commands import Command
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Pose2D

WINDOW = 24  # poses fitted: 0.38 s of a 62.5 Hz base
SPAN = 24  # latencies tried, in steps
# What a step's turn and distance may miss by and still fit (rad, m): a few encoder ticks.
TURN_NOISE, DISTANCE_NOISE = 2e-3, 2e-4


class DelayFit:
    """Recent poses by step, and the latency that fits them (`best`)."""

    def __init__(self, step_s: float) -> None:
        self.step_s = step_s
        self._poses: deque[tuple[int, Pose2D]] = deque(maxlen=WINDOW + 1)

    def add(self, step: int, pose: Pose2D) -> None:
        """The pose of robot step `step` (steps counted by poses, one a step)."""
        self._poses.append((step, pose))

    def best(self, commands: Sequence[tuple[float, Command]], lowest: int) -> int | None:
        """The latency (steps from a command's stamp to the step it acts first, in the
        poses' count) in `lowest`, `lowest + 1`, ... that explains the window's motion, or None
        when none does clearly. `commands`: (stamp in steps, command), oldest first."""
        if len(self._poses) <= WINDOW:
            return None
        errors = sorted((self._error(commands, latency), latency)
                        for latency in range(lowest, lowest + SPAN))
        (best, latency), (second, _) = errors[0], errors[1]
        if not math.isfinite(best) or best > 0.5 * second:
            return None
        return latency

    def _error(self, commands: Sequence[tuple[float, Command]], latency: int) -> float:
        """How badly the window's motion fits commands arriving `latency` steps after their
        stamps (inf: the window reaches before the commands remembered)."""
        arrivals = [round(stamp + latency) for stamp, _ in commands]
        error, index = 0.0, -1
        previous = self._poses[0][1]
        for step, pose in list(self._poses)[1:]:
            while index + 1 < len(arrivals) and arrivals[index + 1] <= step:
                index += 1
            if index < 0:
                return math.inf
            command = commands[index][1]
            turned = wrap_angle(pose.theta - previous.theta)
            moved = math.hypot(pose.x - previous.x, pose.y - previous.y)
            error += ((turned - command.angular * self.step_s) / TURN_NOISE) ** 2
            error += ((moved - abs(command.linear) * self.step_s) / DISTANCE_NOISE) ** 2
            previous = pose
        return error

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

import numpy as np

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
        self._last: Pose2D | None = None
        # each step's turn and distance, from the pose before (by the later pose's step)
        self._motions: deque[tuple[int, float, float]] = deque(maxlen=WINDOW)

    def add(self, step: int, pose: Pose2D) -> None:
        """The pose of robot step `step` (steps counted by poses, one a step)."""
        if self._last is not None:
            self._motions.append((step, wrap_angle(pose.theta - self._last.theta),
                                  math.hypot(pose.x - self._last.x, pose.y - self._last.y)))
        self._last = pose

    def best(self, commands: Sequence[tuple[float, Command]], lowest: int) -> int | None:
        """The latency (steps from a command's stamp to the step it acts first, in the
        poses' count) in `lowest`, `lowest + 1`, ... that explains the window's motion, or None
        when none does clearly. `commands`: (stamp in steps, command), oldest first."""
        if len(self._motions) < WINDOW:
            return None
        errors = sorted(zip(self._errors(commands, lowest).tolist(),
                            range(lowest, lowest + SPAN), strict=True))
        (best, latency), (second, _) = errors[0], errors[1]
        if not math.isfinite(best) or best > 0.5 * second:
            return None
        return latency

    def _errors(self, commands: Sequence[tuple[float, Command]], lowest: int) -> np.ndarray:
        """For each latency from `lowest` (SPAN of them), how badly the window's motion fits
        commands arriving that many steps after their stamps: the sum of each step's squared
        misfits of turn and distance, in noise units, added in step order (inf: the window
        reaches before the commands remembered). All latencies at once."""
        stamps = np.array([stamp for stamp, _ in commands])
        angular = np.array([command.angular for _, command in commands]) * self.step_s
        linear = np.abs(np.array([command.linear for _, command in commands])) * self.step_s
        steps, turned, moved = (np.array(values) for values in zip(*self._motions, strict=True))
        arrivals = np.round(stamps[None, :] + np.arange(lowest, lowest + SPAN)[:, None])
        # the command in effect at each step: the last of those, in order, arrived by then
        # (-1: none yet; one arriving before another sent earlier waits for it)
        arrivals = np.maximum.accumulate(arrivals, axis=1)
        acting = (arrivals[:, None, :] <= steps[None, :, None]).sum(axis=2) - 1
        misfits = np.empty((SPAN, 2 * len(steps)))
        misfits[:, 0::2] = ((turned - angular[acting]) / TURN_NOISE) ** 2
        misfits[:, 1::2] = ((moved - linear[acting]) / DISTANCE_NOISE) ** 2
        errors = np.cumsum(misfits, axis=1)[:, -1]  # one by one, as they come
        errors[(acting < 0).any(axis=1)] = math.inf
        return errors

"""A running quantile of a stream of numbers, updated in constant time. Pure Python.

The stochastic-approximation estimate (Robbins and Monro): each observation moves the estimate
up by `rate * share` when it lies above it, and down by `rate * (1 - share)` when below, so it
settles where `share` of the observations lie below. It weighs the recent more than the old,
and a spike moves a high quantile by `rate * share` only, which the following observations take
back: one stall among many never moves it by a whole step.
"""

from __future__ import annotations

from collections import deque


class RunningQuantile:
    """The `share` quantile of what was observed lately (None before any observation).

    :param rate: the largest move one observation makes, in the observations' unit.
    :param prior: the estimate before any observation (None: the first observation).
    """

    def __init__(self, share: float, rate: float, prior: float | None = None) -> None:
        self.share = share
        self.rate = rate
        self.value: float | None = prior

    def add(self, observed: float) -> None:
        if self.value is None:
            self.value = float(observed)
        elif observed > self.value:
            self.value += self.rate * self.share
        elif observed < self.value:
            self.value -= self.rate * (1.0 - self.share)

    def whole(self, default: int = 0) -> int:
        """The estimate rounded to a whole number (`default` before any observation)."""
        return default if self.value is None else round(self.value)


class RunningFloor(RunningQuantile):
    """The least of what was observed lately: it falls to any observation below it at once,
    and rises as a `share` quantile does above it (slowly, for a small share). For a delay, the
    delay without a queue: every observation is the floor or more, and a lower one proves it."""

    def add(self, observed: float) -> None:
        if self.value is not None and observed < self.value:
            self.value = float(observed)
        else:
            super().add(observed)


class WindowQuantile:
    """A quantile too high for a running estimate: the largest of the last `window`
    observations, the `1 - 1 / window` quantile of what was observed lately (one observation
    in `window` lies above it). A running estimate of such a share steps up by almost its rate
    at every observation above it and creeps down at every one below, so on whole numbers it
    swings by its rate around the quantile; the window's largest holds still. Constant time
    per observation (the window's decreasing candidates)."""

    def __init__(self, window: int) -> None:
        self.window = window
        self._count = 0
        self._candidates: deque[tuple[int, float]] = deque()  # (index, value), decreasing

    def add(self, observed: float) -> None:
        while self._candidates and self._candidates[-1][1] <= observed:
            self._candidates.pop()
        self._candidates.append((self._count, float(observed)))
        self._count += 1
        if self._candidates[0][0] < self._count - self.window:
            self._candidates.popleft()

    @property
    def value(self) -> float | None:
        return self._candidates[0][1] if self._candidates else None

    def whole(self, default: int = 0) -> int:
        """The largest rounded to a whole number (`default` before any observation)."""
        return default if self.value is None else round(self.value)

"""A running quantile of a stream of numbers, updated in constant time. Pure Python.

The stochastic-approximation estimate (Robbins and Monro): each observation moves the estimate
up by `rate * share` when it lies above it, and down by `rate * (1 - share)` when below, so it
settles where `share` of the observations lie below. It weighs the recent more than the old,
and a spike moves a high quantile by `rate * share` only, which the following observations take
back: one stall among many never moves it by a whole step.
"""

from __future__ import annotations


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

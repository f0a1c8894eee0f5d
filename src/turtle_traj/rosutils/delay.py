"""A delay line for velocity commands, to test controllers against latency and jitter.

Off by default. Times are simulated seconds and the jitter comes from a seeded generator, so
a lock-step run with a delay repeats exactly. Commands keep their order, as on a reliable
stream: a command is never applied before one that arrived earlier.
"""

from __future__ import annotations

import random
from collections import deque
from collections.abc import Iterator
from typing import Generic, TypeVar

Message = TypeVar('Message')


class CommandDelay(Generic[Message]):
    """Holds each command for `delay_s` plus a random share of `jitter_s`."""

    def __init__(self, delay_s: float, jitter_s: float, *, seed: int = 0) -> None:
        self.delay_s = delay_s
        self.jitter_s = jitter_s
        self._random = random.Random(seed)
        self._queue: deque[tuple[float, str, Message]] = deque()

    @property
    def active(self) -> bool:
        return self.delay_s > 0.0 or self.jitter_s > 0.0

    def push(self, now_s: float, turtle: str, message: Message) -> None:
        """Queue a command that arrived at simulated time `now_s`."""
        due = now_s + self.delay_s + self._random.uniform(0.0, self.jitter_s)
        if self._queue:
            due = max(due, self._queue[-1][0])
        self._queue.append((due, turtle, message))

    def drop(self, turtle: str) -> None:
        """Forget the commands queued for `turtle` (killed or reset: its subscription is gone)."""
        self._queue = deque(entry for entry in self._queue if entry[1] != turtle)

    def due(self, now_s: float) -> Iterator[tuple[str, Message]]:
        """Take, in order, the commands due by `now_s`."""
        while self._queue and self._queue[0][0] <= now_s + 1e-9:
            _due, turtle, message = self._queue.popleft()
            yield turtle, message

"""Noticing that a node went away mid-run: its feedback falls silent, then it leaves a
parameter request unanswered (a busy node answers that at once; a killed one never does)."""

from __future__ import annotations

import time

from rcl_interfaces.srv import GetParameters
from rclpy.node import Node
from rclpy.task import Future

FEEDBACK_SILENCE_S = 2.0  # no feedback for this long: ask whether the node still answers
PROBE_TIMEOUT_S = 3.0  # no answer within this: the node is gone


class Liveness:
    """Watches the node `node_name` from our `node`; call `heard()` on each sign of life and
    `gone()` as often as convenient."""

    def __init__(self, node: Node, node_name: str) -> None:
        self._client = node.create_client(GetParameters, f'{node_name}/get_parameters')
        self.last_heard = time.monotonic()
        self._probe: tuple[Future, float] | None = None

    def heard(self) -> None:
        self.last_heard, self._probe = time.monotonic(), None

    def silence_s(self) -> float:
        return time.monotonic() - self.last_heard

    def gone(self) -> bool:
        """True once the node has been silent and then left a probe unanswered too long."""
        now = time.monotonic()
        if now - self.last_heard < FEEDBACK_SILENCE_S:
            return False
        if self._probe is None:  # silent: does the node still answer at all?
            request = GetParameters.Request(names=['turtle_name'])
            self._probe = (self._client.call_async(request), now)
        elif self._probe[0].done():
            self.heard()
        elif now - self._probe[1] > PROBE_TIMEOUT_S:
            return True
        return False

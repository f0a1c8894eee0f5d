"""Noticing that a node went away mid-run: its feedback falls silent, then it leaves parameter
requests unanswered (a busy node answers one at once; a killed one never does). The request is
sent again each second while unanswered: one can be lost (a busy program's full socket buffer
drops it), and a node that has not yet matched our reply reader cannot answer it."""

from __future__ import annotations

import time
from collections.abc import Callable

from rcl_interfaces.srv import GetParameters
from rclpy.node import Node
from rclpy.task import Future

FEEDBACK_SILENCE_S = 2.0  # no feedback for this long: ask whether the node still answers
PROBE_TIMEOUT_S = 3.0  # no answer within this: the node is gone
PROBE_RESEND_S = 1.0  # a probe not answered within this is sent again


class Liveness:
    """Watches the node `node_name` from our `node`; call `heard()` on each sign of life and
    `gone()` as often as convenient. `now` is the clock the silences are timed on (seconds;
    the steady clock by default)."""

    def __init__(self, node: Node, node_name: str,
                 now: Callable[[], float] | None = None) -> None:
        self._client = node.create_client(GetParameters, f'{node_name}/get_parameters')
        self._now = now if now is not None else time.monotonic
        self.last_heard = self._now()
        self._probes: list[Future] = []  # sent since the node was last heard
        self._first_probe_s = self._last_probe_s = 0.0

    def heard(self) -> None:
        self.last_heard = self._now()
        for probe in self._probes:  # left unanswered: the client forgets them
            self._client.remove_pending_request(probe)
        self._probes = []

    def silence_s(self) -> float:
        return self._now() - self.last_heard

    def gone(self) -> bool:
        """True once the node has been silent and then left its probes unanswered too long."""
        now = self._now()
        if now - self.last_heard < FEEDBACK_SILENCE_S:
            return False
        if any(probe.done() for probe in self._probes):
            self.heard()
            return False
        if self._probes and now - self._first_probe_s > PROBE_TIMEOUT_S:
            return True
        if not self._probes or now - self._last_probe_s > PROBE_RESEND_S:
            self._probe(now)  # silent: does the node still answer at all?
        return False

    def _probe(self, now: float) -> None:
        if not self._probes:
            self._first_probe_s = now
        self._last_probe_s = now
        self._probes.append(self._client.call_async(GetParameters.Request(names=['turtle_name'])))

"""A silent node is probed with parameter requests, each second again while none is answered: a
lost request (a busy program's full socket buffer drops it) or a reply the node could not send
yet does not make a busy node look killed; a node that answers none is gone after the timeout.
The client and the clock are stand-ins: what is checked is when requests go out and the verdict."""

from __future__ import annotations

import pytest
from rclpy.task import Future

from turtle_traj.client import liveness as module
from turtle_traj.client.liveness import (
    FEEDBACK_SILENCE_S,
    PROBE_RESEND_S,
    PROBE_TIMEOUT_S,
    Liveness,
)


class _Client:
    def __init__(self) -> None:
        self.sent: list[tuple[float, Future]] = []
        self.forgotten: list[Future] = []

    def call_async(self, _request) -> Future:
        self.sent.append((module.time.monotonic(), Future()))
        return self.sent[-1][1]

    def remove_pending_request(self, future: Future) -> None:
        self.forgotten.append(future)


class _Node:
    def __init__(self) -> None:
        self.client = _Client()

    def create_client(self, *_args):
        return self.client


@pytest.fixture
def clock(monkeypatch):
    now = [100.0]
    monkeypatch.setattr(module.time, 'monotonic', lambda: now[0])
    return now


def _watch(liveness: Liveness, clock: list[float], until_s: float,
           on_probe=lambda sent: None) -> float | None:
    """Call `gone()` every 10 ms until `until_s` after the start; when it said gone (s)."""
    start = clock[0]
    while clock[0] - start < until_s:
        if liveness.gone():
            return clock[0] - start
        on_probe(liveness._client.sent)
        clock[0] += 0.01
    return None


def test_a_node_that_answers_no_probe_is_gone_after_the_timeout_probed_each_second(clock):
    node = _Node()
    liveness = Liveness(node, '/turtle_traj')
    said_gone = _watch(liveness, clock, 20.0)
    assert said_gone == pytest.approx(FEEDBACK_SILENCE_S + PROBE_TIMEOUT_S, abs=0.03)
    times = [sent - 100.0 for sent, _ in node.client.sent]
    assert times[0] == pytest.approx(FEEDBACK_SILENCE_S, abs=0.02)
    assert [b - a for a, b in zip(times, times[1:], strict=False)] == pytest.approx(
        [PROBE_RESEND_S] * (len(times) - 1), abs=0.02)
    assert len(times) == int(PROBE_TIMEOUT_S / PROBE_RESEND_S)


def test_a_lost_probe_is_sent_again_and_the_answer_to_the_next_keeps_the_node_alive(clock):
    node = _Node()
    liveness = Liveness(node, '/turtle_traj')

    def answer_the_second(sent) -> None:  # the first request is lost
        if len(sent) == 2 and not sent[1][1].done():
            sent[1][1].set_result('answered')
    assert _watch(liveness, clock, FEEDBACK_SILENCE_S + PROBE_TIMEOUT_S + 1.0,
                  answer_the_second) is None
    # heard when the second probe's answer came, a resend after the first
    assert liveness.last_heard - 100.0 == pytest.approx(FEEDBACK_SILENCE_S + PROBE_RESEND_S,
                                                        abs=0.03)
    assert node.client.sent[0][1] in node.client.forgotten  # the lost one is let go


def test_feedback_keeps_the_node_alive_without_any_probe(clock):
    node = _Node()
    liveness = Liveness(node, '/turtle_traj')
    for _ in range(1000):  # 10 s of feedback every 0.1 s
        clock[0] += 0.01
        if round(clock[0] * 100) % 10 == 0:
            liveness.heard()
        assert not liveness.gone()
    assert node.client.sent == []

"""Awaiting a condition inside a node's coroutine, on simulated and wall time alike."""

from __future__ import annotations

import time
from collections.abc import Callable

from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.task import Future

POLL_PERIOD_S = 0.005


async def wait_until(node: Node, condition: Callable[[], bool], timeout_s: float) -> bool:
    """Await `condition()` for at most `timeout_s` of wall time; whether it came true.

    Polled on the node clock, so that on simulated time it is seen at the step it comes true,
    and on the steady clock, so that a clock that stands still (a vanished /clock source)
    still times out.
    """
    waited = Future()
    deadline = time.monotonic() + timeout_s

    def poll() -> None:
        if waited.done():
            return
        met = condition()
        if met or time.monotonic() > deadline:
            waited.set_result(met)

    steady = Clock(clock_type=ClockType.STEADY_TIME)
    timers = [node.create_timer(POLL_PERIOD_S, poll),
              node.create_timer(POLL_PERIOD_S, poll, clock=steady)]
    try:
        poll()
        return await waited
    finally:
        for timer in timers:
            node.destroy_timer(timer)

"""Awaiting inside a node's coroutines: a future a timer completes (at most for a while), or a
condition, on simulated and wall time alike, and on every executor the node may be composed in.

rclpy 7.1.6's Python executors poll a coroutine that awaits a pending future on every pass
(ros2/rclpy#1405: they re-run pending tasks instead of waiting for their futures). The
SingleThreadedExecutor survives that at some CPU cost; on the MultiThreadedExecutor each pass
also goes through the thread pool, and a run kept the executor at a whole core. There a handler
blocks its own pool thread instead, as rclpy's documentation has reentrant callbacks do on that
executor: the task counts as executing and is not polled, and the other threads run the timers
that complete it (tests/test_multithreaded.py, with the simulator a program of its own: in the
same process it starves, which docs/tutorials/action-from-python.md says). The EventsExecutor
(the programs' default) resumes a task only when woken, and stays with `await`.
"""

from __future__ import annotations

import contextlib
import threading
import time
import weakref
from collections.abc import Callable
from typing import Any

from rclpy.clock import Clock, ClockType
from rclpy.exceptions import InvalidHandle
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from rclpy.task import Future

POLL_PERIOD_S = 0.005


async def completion(node: Node, future: Future, *, timeout_s: float | None = None) -> Any:
    """The result of `future`, which another callback of `node` completes (None if
    `timeout_s` passed first on a MultiThreadedExecutor, where that is checked here)."""
    if isinstance(node.executor, MultiThreadedExecutor) and not future.done():
        completed = threading.Event()
        future.add_done_callback(lambda _: completed.set())
        if not completed.wait(timeout_s):
            return None
        return future.result()
    if not future.done():
        future.add_done_callback(lambda _: _Bell.ring(node))
    return await future


class _Bell:
    """A node's timer that fires at once when rung, so that its executor resumes the coroutines
    awaiting in `completion` now. rclpy 7.1.6's EventsExecutor resumes them only after a
    callback of a subscription, timer, service or client, never after a task's: a future
    completed by a task (a done callback, a result handed over from a thread) would leave its
    coroutine waiting for whatever callback came next, in lock-step a wall-clock timer's beat
    in one run and the next step in another."""

    _of: weakref.WeakKeyDictionary[Node, _Bell] = weakref.WeakKeyDictionary()

    def __init__(self, node: Node) -> None:
        self._timer = node.create_timer(0.0, self._quiet,  # it fires as it is made
                                        clock=Clock(clock_type=ClockType.STEADY_TIME))

    def _quiet(self) -> None:
        self._timer.cancel()

    @classmethod
    def ring(cls, node: Node) -> None:
        """Fire `node`'s bell (made on its first ring), on its executor's thread."""
        with contextlib.suppress(InvalidHandle):  # the node is gone, and its coroutines
            bell = cls._of.get(node)
            if bell is None:
                cls._of[node] = cls(node)
            else:
                bell._timer.reset()


async def result_within(node: Node, future: Future, timeout_s: float) -> Any:
    """`future`'s result, awaited as another callback completes it (on simulated time: at the
    step it does, whatever the wall clock), or None after `timeout_s` of the steady clock."""
    steady = Clock(clock_type=ClockType.STEADY_TIME)
    late = Future()
    timer = node.create_timer(timeout_s, lambda: late.done() or late.set_result(None),
                              clock=steady)
    future.add_done_callback(lambda done: late.done() or late.set_result(done.result()))
    try:
        return await completion(node, late)
    finally:
        node.destroy_timer(timer)


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
        # (the margin: a pool so busy that no timer ran by the deadline still ends the wait)
        met = await completion(node, waited, timeout_s=timeout_s + 1.0)
        return bool(met) if met is not None else condition()
    finally:
        for timer in timers:
            node.destroy_timer(timer)

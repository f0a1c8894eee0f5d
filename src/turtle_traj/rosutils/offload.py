"""Blocking work beside a node's executor: a thread computes it, the executor gets the result.

A callback that computes for seconds (a text planned with TOPP-RA) holds its executor: no
feedback, no parameter replies, no poses, and a client that hears nothing for long enough
gives the node up for dead. `Offloader.submit` runs the work on a thread of its own and
completes an rclpy Future with its result from the node's executor, so a coroutine awaits it
like any other future. The thread hands the result over with `executor.create_task`, which
every rclpy executor takes from any thread and which wakes it (Jazzy's EventsExecutor refuses
guard conditions, rclpy's usual wake-up).

Lock-step counts work in flight as work of the step (`in_flight`): the simulator does not step
while a node computes beside its executor, as it would not while a callback ran.
"""

from __future__ import annotations

import threading
import weakref
from collections.abc import Callable
from typing import Any

from rclpy.node import Node
from rclpy.task import Future

_lock = threading.Lock()
_in_flight: weakref.WeakKeyDictionary[Node, int] = weakref.WeakKeyDictionary()
_total = 0  # in flight for every node of the process: none, the usual case, is told at once


def in_flight(node: Node) -> int:
    """How many works submitted for `node` have not been handed to its executor yet."""
    if not _total:
        return 0
    with _lock:
        return _in_flight.get(node, 0)


def any_in_flight(nodes: list[Node]) -> bool:
    """Whether any of `nodes` has work computing beside its executor (checked on every
    lock-step step and watchdog beat: with none in the process, at once)."""
    return bool(_total) and any(in_flight(node) for node in nodes)


def beside(node: Node) -> bool:
    """Whether a node of `node`'s executor computes beside it now (lock-step holds the
    simulator meanwhile)."""
    if not _total:
        return False
    executor = node.executor
    return executor is not None and any_in_flight(executor.get_nodes())


def _count(node: Node, change: int) -> None:
    global _total
    with _lock:
        _in_flight[node] = _in_flight.get(node, 0) + change
        _total += change


class Offloader:
    """Runs blocking work for `node` on threads of their own, one thread per work."""

    def __init__(self, node: Node, name: str) -> None:
        self._node, self._name = node, name

    def submit(self, work: Callable[[], Any]) -> Future:
        """Start `work()` now; the future of its result (or exception), completed on the node's
        executor. Cancelling the future drops the result; the work itself runs to its end."""
        future = Future()
        _count(self._node, +1)
        threading.Thread(target=self._run, args=(work, future), name=self._name,
                         daemon=True).start()  # never holds the program's exit back
        return future

    def _run(self, work: Callable[[], Any], future: Future) -> None:
        try:
            result, error = work(), None
        except Exception as failure:  # handed to whoever awaits it
            result, error = None, failure
        try:
            self._node.executor.create_task(self._deliver, future, result, error)
        except Exception:  # no executor (None), or one shut down: nobody awaits the result
            _count(self._node, -1)

    def _deliver(self, future: Future, result: Any, error: Exception | None) -> None:
        _count(self._node, -1)
        if future.cancelled() or future.done():
            return
        if error is not None:
            future.set_exception(error)
        else:
            future.set_result(result)

"""Lock-step simulated time: the simulator steps only when everything else in the process is idle.

The simulator takes its next step only once an executor pass found nothing new to run and every
message our nodes published has been acknowledged by its subscribers: by then everything the
last step triggered has been handled (the pose delivered, every timer due at the new simulated
time fired, the commands those timers published taken by the simulator). Nothing waits on the
wall clock, so simulated time runs as fast as the CPU allows, and the same requests give the
same callbacks in the same order, hence bit-identical poses, whatever the load."""

from __future__ import annotations

import time
import weakref
from collections.abc import Iterator
from typing import TYPE_CHECKING

from rclpy.context import Context
from rclpy.duration import Duration
from rclpy.executors import (
    ConditionReachedException,
    ShutdownException,
    SingleThreadedExecutor,
    TimeoutException,
)
from rclpy.publisher import Publisher
from rclpy.task import Future, Task

if TYPE_CHECKING:
    from turtle_traj.sim.node import SimNode

_NO_WAIT = Duration()
_ACK_POLL = Duration(nanoseconds=1_000_000)
_DELIVERY_GRACE_S = 0.1


class LockstepExecutor(SingleThreadedExecutor):
    """A single-threaded executor that steps `simulator` whenever a whole pass found no new work.

    `spin_once` then never blocks: it runs one ready callback, or advances simulated time by one
    step. A coroutine callback still awaiting something (an async service handler waiting for its
    trajectory to end) is resumed on every pass, as rclpy does; resuming it is not new work.
    While the simulator is not among the executor's nodes (removed, as if it had vanished),
    nothing steps and `spin_once` waits like a plain SingleThreadedExecutor.
    """

    def __init__(self, simulator: SimNode, *, context: Context | None = None) -> None:
        super().__init__(context=context)
        self._simulator = simulator
        self._started: weakref.WeakSet[Task] = weakref.WeakSet()
        self._pass_found_work = False
        self._undelivered_since: float | None = None
        self.steps = 0

    def spin_once(self, timeout_sec: float | None = None) -> None:
        """Run one ready callback or, when the last pass found nothing new, step the simulator.

        :param timeout_sec: how long to wait for work while the simulator is not being spun;
            ignored otherwise, as lock-step never waits for the wall clock.
        """
        if self._simulator not in self.get_nodes():
            super().spin_once(timeout_sec)
            return
        try:
            handler, _entity, _node = self.wait_for_ready_callbacks(timeout_sec=0)
        except TimeoutException:  # the end of one pass over everything that was ready
            if not self._pass_found_work and self._delivered():
                self._simulator.step()
                self.steps += 1
            self._pass_found_work = False
            return
        except (ShutdownException, ConditionReachedException):
            return
        if handler not in self._started:
            self._started.add(handler)
            self._pass_found_work = True
        handler()
        if handler.exception() is not None:
            raise handler.exception()

    def _delivered(self) -> bool:
        """Every message our nodes published has reached its subscribers.

        Fast DDS usually hands a message to a subscriber of the same process before `publish()`
        returns, but not always (a subscriber matched a moment ago may get it from a resend a
        few milliseconds later): stepping then would act on a command one step late, or several.
        A subscriber that does not acknowledge (one destroyed but not yet unmatched, another
        process that hangs) holds each step back for at most `_DELIVERY_GRACE_S` of wall time.
        """
        waiting_since = self._undelivered_since
        for publisher in self._publishers():
            if not publisher.wait_for_all_acked(_NO_WAIT):
                now = time.monotonic()
                if waiting_since is None:
                    self._undelivered_since = now
                elif now - waiting_since > _DELIVERY_GRACE_S:
                    break
                publisher.wait_for_all_acked(_ACK_POLL)
                return False
        self._undelivered_since = None
        return True

    def _publishers(self) -> Iterator[Publisher]:
        for node in self.get_nodes():
            yield from node.publishers

    def spin_once_until_future_complete(self, future: Future,
                                        timeout_sec: float | None = None) -> None:
        """As `spin_once`: futures complete through callbacks, which lock-step runs in turn."""
        self.spin_once(timeout_sec)

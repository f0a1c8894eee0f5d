"""Lock-step simulated time: the simulator steps only when everything else in the process is idle.

The simulator takes its next step only once the executor's queue is empty and every message our
nodes published has been acknowledged by its subscribers: by then everything the last step
triggered has been handled (the pose delivered, every timer due at the new simulated time fired,
the commands those timers published taken by the simulator). Nothing waits on the wall clock, so
simulated time runs as fast as the CPU allows, and the same requests give the same callbacks in
the same order, hence bit-identical poses, whatever the load.

It runs on rclpy's EventsExecutor, which keeps a queue of events fed by the middleware's
listeners instead of rebuilding a wait set on every pass. What lock-step relies on of it (that
`spin_until_future_complete(future, 0)` runs until the queue is empty, including what the callbacks
it ran queued meanwhile, and that a message published in this process is queued before
`publish()` returns) is pinned by tests/test_lockstep_contract.py.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from typing import Protocol

from rclpy.context import Context
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.task import Future
from rclpy.time_source import TimeSource
from rosgraph_msgs.msg import Clock

from turtle_traj.rosutils.runtime import events_executor

_NO_WAIT = Duration()
_ACK_POLL = Duration(nanoseconds=1_000_000)
_DELIVERY_GRACE_S = 0.1


def clock_message(time_s: float) -> Clock:
    """Simulated time as /clock carries it (whole nanoseconds)."""
    stamp = Clock()
    stamp.clock.sec, nanoseconds = divmod(round(time_s * 1e9), 10**9)
    stamp.clock.nanosec = nanoseconds
    return stamp


class SteppedSimulator(Protocol):
    """A simulator node lock-step can drive: our turtlesim, the physics base."""

    def step(self) -> None:
        """Advance simulated time by one step and publish what it produced."""

    def clock_message(self) -> Clock:
        """The simulated time now, as /clock carries it."""


class LockstepExecutor:
    """An executor that steps `simulator` whenever nothing else in the process has work.

    `spin_once` never blocks: it runs every ready callback, and what those trigger in turn, then
    advances simulated time by one step. A coroutine callback still awaiting something (an async
    service handler waiting for its trajectory to end) is resumed when what it awaits is done,
    not before. While the simulator is not among the executor's nodes (removed, as if it had
    vanished), nothing steps and `spin_once` waits like a plain executor.
    """

    def __init__(self, simulator: SteppedSimulator, *, context: Context | None = None) -> None:
        self._events = events_executor(context=context)
        self._simulator = simulator
        self._nodes: list[Node] = []
        self._undelivered_since: float | None = None
        # The clocks of our nodes on simulated time, set at each step (see `add_node`).
        self._sim_time = TimeSource()
        self._sim_time.ros_time_is_active = True
        self.steps = 0

    # -- the Executor interface our code uses --------------------------------------------------

    def add_node(self, node: Node) -> bool:
        if node in self._nodes:
            return False
        self._nodes.append(node)
        if node is not self._simulator and node.get_clock().ros_time_is_active:
            self._set_clock_directly(node)
        return self._events.add_node(node)

    def _set_clock_directly(self, node: Node) -> None:
        """Drive a `use_sim_time` node's clock from the simulator at each step, not via /clock.

        A node on simulated time hears /clock through a subscription of its TimeSource, which
        in lock-step would cost a message and a callback per node per step. Its clock is set
        at each step instead, before anything the step triggered runs, so its callbacks see
        exactly the times they would have seen from /clock.
        """
        for subscription in list(node.subscriptions):
            if subscription.topic_name == '/clock':
                node.destroy_subscription(subscription)
        self._sim_time.attach_clock(node.get_clock())

    def remove_node(self, node: Node) -> None:
        if node in self._nodes:
            self._nodes.remove(node)
        self._events.remove_node(node)

    def get_nodes(self) -> list[Node]:
        return list(self._nodes)

    def create_task(self, callback, *args, **kwargs):
        return self._events.create_task(callback, *args, **kwargs)

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        return self._events.shutdown(timeout_sec)

    def spin_once(self, timeout_sec: float | None = None) -> None:
        """Run everything ready, then step the simulator once every message is delivered.

        :param timeout_sec: how long to wait for work while the simulator is not being spun;
            ignored otherwise, as lock-step never waits for the wall clock.
        """
        if self._simulator not in self._nodes:
            self._events.spin_once(timeout_sec)
            return
        self.drain()
        if self._delivered():
            self._simulator.step()
            self._sim_time.clock_callback(self._simulator.clock_message())
            self.steps += 1

    def drain(self) -> None:
        """Run callbacks until none is ready, including those the callbacks run made ready."""
        # A future nobody completes: the queue runs until it is empty, and the timeout of 0
        # never waits for more.
        self._events.spin_until_future_complete(Future(), 0.0)

    def spin_once_until_future_complete(self, future: Future,
                                        timeout_sec: float | None = None) -> None:
        """As `spin_once`: futures complete through callbacks, which lock-step runs in turn."""
        self.spin_once(timeout_sec)

    def _delivered(self) -> bool:
        """Every message our nodes published has reached its subscribers.

        Fast DDS hands a message to a subscriber of the same process before `publish()` returns,
        but not always (a subscriber matched a moment ago may get it from a resend a few
        milliseconds later): stepping then would act on a command one step late, or several.
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
        for node in self._nodes:
            yield from node.publishers

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
`publish()` returns) is pinned by tests/test_lockstep_contract.py; that setting a clock queues
its timers' update at once (so that the nodes tick in the order they were added) by
tests/test_lockstep.py; that a coroutine awaiting a future resumes after a callback of an
entity, not of a task (so that `node.waiting.completion` rings a timer to resume its coroutine
at the step its result comes) by tests/test_lockstep_awaiting.py.

Paced (`pace`), it also keeps simulated time from running ahead of the wall clock times the
pace: a program's `--time-scale` with our simulator in its process. Between steps it serves
whatever comes (other programs' calls, a window, the live view), so it runs as the simulator on
its own timer would, except that no step is ever taken before the node has answered the last:
PX4's software-in-the-loop lockstep, Gazebo's real-time factor.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from typing import Protocol

from rclpy.clock import ROSClock
from rclpy.context import Context
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.task import Future
from rclpy.time import Time
from rclpy.time_source import TimeSource
from rosgraph_msgs.msg import Clock

from turtle_traj.rosutils import offload
from turtle_traj.rosutils.runtime import events_executor

_NO_WAIT = Duration()
_ACK_POLL = Duration(nanoseconds=1_000_000)
_DELIVERY_GRACE_S = 0.1
_IN_FLIGHT_POLL_S = 0.01
# Paced, a process held up longer than this (a machine busy elsewhere) does not catch up in a
# burst: simulated time loses the lag instead, as a simulator on its own timer would.
MAX_PACE_LAG_S = 0.2


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

    @property
    def time_s(self) -> float:
        """The simulated time now, in seconds."""


class LockstepExecutor:
    """An executor that steps `simulator` whenever nothing else in the process has work.

    `spin_once` runs every ready callback, and what those trigger in turn, then advances
    simulated time by one step. It waits only while a node computes beside the executor
    (`offload`), which counts as a callback still running. A coroutine callback still awaiting
    something (an async service handler waiting for its trajectory to end) is resumed when what
    it awaits is done, not before. While the simulator is not among the executor's nodes
    (removed, as if it had vanished), nothing steps and `spin_once` waits like a plain executor.

    With `pace`, `spin_once` also waits (serving what comes meanwhile) until the wall clock
    has caught up with simulated time divided by `pace`, then steps.
    """

    def __init__(self, simulator: SteppedSimulator, *, context: Context | None = None,
                 pace: float | None = None) -> None:
        """:param pace: simulated seconds per wall-clock second, at most (a program's
            `--time-scale`); None: as fast as the CPU allows."""
        if pace is not None and not (math.isfinite(pace) and pace > 0.0):
            raise ValueError(f'pace must be a positive number, got {pace}')
        self._events = events_executor(context=context)
        self._simulator = simulator
        self._pace = pace
        self._pace_origin: tuple[float, float] | None = None  # (wall s, simulated s)
        self._nodes: list[Node] = []
        self._undelivered_since: float | None = None
        # The clocks of our nodes on simulated time, set at each step in the order their nodes
        # were added (see `add_node`); the TimeSource only turns simulated time on for them.
        self._sim_time = TimeSource()
        self._sim_time.ros_time_is_active = True
        self._clocks: list[tuple[Node, ROSClock]] = []
        self._time: Time | None = None  # of the last step
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
        exactly the times they would have seen from /clock. The clocks are set in the order
        their nodes were added, and each one's timers that fall due are queued as it is set:
        the nodes' control ticks run in that order at every step after the first, in every run
        (a TimeSource keeps its clocks in a set, whose order changes from run to run). At the
        first step they run in the order the executor takes the nodes in, which it does then.
        """
        for subscription in list(node.subscriptions):
            if subscription.topic_name == '/clock':
                node.destroy_subscription(subscription)
        clock = node.get_clock()
        self._sim_time.attach_clock(clock)
        if self._time is not None:
            clock.set_ros_time_override(self._time)
        self._clocks.append((node, clock))

    def remove_node(self, node: Node) -> None:
        if node in self._nodes:
            self._nodes.remove(node)
        self._clocks = [(other, clock) for other, clock in self._clocks if other is not node]
        self._events.remove_node(node)

    def get_nodes(self) -> list[Node]:
        return list(self._nodes)

    def create_task(self, callback, *args, **kwargs):
        return self._events.create_task(callback, *args, **kwargs)

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        return self._events.shutdown(timeout_sec)

    def spin_once(self, timeout_sec: float | None = None) -> None:
        """Run everything ready, then step the simulator once every message is delivered.

        :param timeout_sec: how long to wait for work while the simulator is not being spun
            or a node computes beside the executor; otherwise lock-step never waits for the
            wall clock, and ignores it.
        """
        if self._simulator not in self._nodes:
            self._events.spin_once(timeout_sec)
            return
        if self.steps == 0:  # simulated time begins with a step: the world is out (a pose)
            self._step()     # before anything is served, a request that came early included
        self.drain()
        if offload.any_in_flight(self._nodes):
            # A node computes beside the executor (a plan): that belongs to this step, as a
            # callback would. Serve what comes meanwhile, looking again every few milliseconds
            # (not spin_once: with a handler awaiting the work, it would never wait, and its
            # loop would take Python's lock from the work).
            wait = _IN_FLIGHT_POLL_S if timeout_sec is None else min(timeout_sec,
                                                                      _IN_FLIGHT_POLL_S)
            self._events.spin_until_future_complete(Future(), wait)
            return
        if self._pace is not None:
            self._paced_step(timeout_sec)
        elif self._delivered():
            self._step()

    def _step(self) -> None:
        self._simulator.step()
        self._time = Time.from_msg(self._simulator.clock_message().clock)
        for _node, clock in self._clocks:
            clock.set_ros_time_override(self._time)
        self.steps += 1

    def _paced_step(self, timeout_sec: float | None) -> None:
        """Step once the wall clock has caught up with simulated time, serving what comes
        until then (at most `timeout_sec`).

        Acknowledgements are not waited for: other programs' subscribers acknowledge at the
        middleware's pace, not the simulator's, and ours get each message inside `publish()`.
        """
        now = time.monotonic()
        if self._pace_origin is None:
            self._pace_origin = (now, self._simulator.time_s)
        wall_origin, sim_origin = self._pace_origin
        due = wall_origin + (self._simulator.time_s - sim_origin) / self._pace
        if now < due:
            wait = due - now if timeout_sec is None else min(due - now, timeout_sec)
            self._events.spin_until_future_complete(Future(), wait)
            return
        if now - due > MAX_PACE_LAG_S:
            self._pace_origin = (now, self._simulator.time_s)
        self._step()

    def spin_until_future_complete(self, future: Future,
                                   timeout_sec: float | None = None) -> None:
        """Spin (stepping) until `future` is done or `timeout_sec` of wall time passed, at
        least once; for a paced executor, which waits for the wall clock, and for work beside
        the executor."""
        deadline = None if timeout_sec is None else time.monotonic() + timeout_sec
        left = timeout_sec
        while True:
            self.spin_once(left)
            left = None if deadline is None else deadline - time.monotonic()
            if future.done() or (left is not None and left <= 0.0):
                return

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

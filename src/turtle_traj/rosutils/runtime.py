"""The one way our programs run ROS nodes: init, spin one executor, shut down cleanly."""

from __future__ import annotations

import contextlib
import faulthandler
import gc
import io
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path

import rclpy
from rclpy.context import Context
from rclpy.executors import Executor, ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions
from rclpy.task import Future

from turtle_traj.rosutils.fastdds_profile import use_our_fastdds_profile

# How long the executor may wait before Python gets to run a pending signal handler.
_SIGNAL_LATENCY_S = 0.1
# How long a program asked to stop waits for the answers to its last calls (`run_nodes`):
# the simulator answers set_pen within a step; one that vanished never does.
EXIT_GRACE_S = 1.0
_STOP_SIGNALS = {signal.SIGINT, signal.SIGTERM, signal.SIGHUP}  # SIGHUP: terminal closed
# How long a program's shutdown may take in all (the last calls, destroying the nodes and the
# DDS participant; 1-2 s on a loaded machine) before it ends regardless, with every thread's
# stack on stderr and exit code 1. Fast DDS 2.14 can hang destroying a participant while a
# peer leaves at the same moment: its set_listener(nullptr) waits, spinning a core, for a
# discovery callback that waits for the lock it keeps taking (seen once in a loaded suite: a
# node terminated together with its simulator spun for over 6 minutes; eProsima/Fast-DDS#6513).
# faulthandler's own thread ends it: it needs no GIL, which the hung call holds.
SHUTDOWN_DEADLINE_S = 10.0


def events_executor(context: Context | None = None) -> Executor:
    """rclpy's EventsExecutor, also where sys.stderr has no file descriptor.

    Its factory enables faulthandler on sys.stderr, which fails where that is not a real file
    (pytest's capsys, a notebook); the real standard error then takes the crash reports.
    """
    try:
        return EventsExecutor(context=context)
    except io.UnsupportedOperation:
        with contextlib.redirect_stderr(sys.__stderr__):
            return EventsExecutor(context=context)


def run_nodes(
    create_nodes: Callable[[Callable[[], None]], Sequence[Node]],
    *,
    args: Sequence[str] | None = None,
    on_exit: Callable[[], Iterable[Future | None] | None] | None = None,
    make_executor: Callable[[], Executor] = events_executor,
) -> int:
    """Create nodes, spin them in one executor until asked to stop, then tidy up.

    Ctrl-C, SIGTERM and the nodes themselves (a window being closed) all stop the program the
    same way: they call the `stop` function given to `create_nodes`, which sets a flag the spin
    loop checks. Signals are handled by us rather than by rclpy, so that `on_exit` still has a
    live context (a controller uses it to leave the turtle standing still).

    :param create_nodes: builds the nodes once rclpy is initialised; gets `stop`.
    :param args: command-line arguments for rclpy (``--ros-args`` remappings and parameters).
    :param on_exit: runs after spinning stopped and before the nodes are destroyed; the
        futures it returns (calls it made: a drawing's pen put back down) are spun for, up to
        `EXIT_GRACE_S` in all, so that its requests leave the program before its nodes go.
    :param make_executor: makes the executor once the nodes exist (they are added to it here).
        rclpy's EventsExecutor (experimental, C++) by default: it wakes only for what happened,
        where the SingleThreadedExecutor rebuilds its wait set over every endpoint on each
        pass, which cost the trajectory node a fifth of a core doing nothing
        (bench/speed_bench.py).
    :return: the process exit code: 0 after a stop, 1 when something else shut the ROS
        context down.
    """
    use_our_fastdds_profile()
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    # The handlers only set a flag the loop checks: an exception raised from a handler could
    # land inside rclpy's C++ bindings and come out as an unrelated RuntimeError.
    stop = threading.Event()
    for signum in _STOP_SIGNALS:
        signal.signal(signum, lambda *_: stop.set())
    nodes: list[Node] = []
    executor: Executor | None = None
    exit_code = 0
    try:
        nodes.extend(create_nodes(stop.set))
        executor = make_executor()
        for node in nodes:
            executor.add_node(node)
        # What start-up made (imports, rclpy, the nodes: ~48k objects) lives as long as the
        # program: once its garbage is gone, kept out of the collector, a full collection takes
        # well under a millisecond instead of 26-32 ms (two of turtlesim's steps without a
        # command: the one before acts on, past a corner if it comes there).
        gc.collect()
        gc.freeze()
        while rclpy.ok() and not stop.is_set():
            # Not spin_once: the EventsExecutor (rclpy 7.1.6) runs every task still awaiting
            # something at the start of each spin_once, so a loop of them never sleeps while a
            # service handler awaits its trajectory (a whole core; ros2/rclpy#1405, pinned by
            # tests/test_lockstep_contract.py). A future that never
            # completes (a new one each time: each call leaves a callback on it) lets it
            # run whatever comes for the whole timeout instead.
            executor.spin_until_future_complete(Future(), timeout_sec=_SIGNAL_LATENCY_S)
        if not stop.is_set():
            raise ExternalShutdownException
        # What already arrived still runs (a recorder keeps every message it was sent).
        executor.spin_until_future_complete(Future(), timeout_sec=0.0)
    except ExternalShutdownException:
        exit_code = 1
    finally:
        with _shutdown_deadline():
            try:
                if nodes and on_exit is not None and rclpy.ok():
                    _wait_for(executor, on_exit() or ())
            finally:
                if executor is not None:
                    executor.shutdown()
                for node in nodes:
                    node.destroy_node()
                rclpy.try_shutdown()
    return exit_code


def _shutdown_deadline() -> contextlib.ExitStack:
    """End the process `SHUTDOWN_DEADLINE_S` from now, with every thread's stack on stderr,
    unless the returned context has been left by then (not where stderr has no file
    descriptor)."""
    deadline = contextlib.ExitStack()
    with contextlib.suppress(AttributeError, ValueError, io.UnsupportedOperation):
        faulthandler.dump_traceback_later(SHUTDOWN_DEADLINE_S, exit=True, file=sys.__stderr__)
        deadline.callback(faulthandler.cancel_dump_traceback_later)
    return deadline


def _wait_for(executor: Executor | None, futures: Iterable[Future | None]) -> None:
    """Spin until each future is done, `EXIT_GRACE_S` at most in all (a vanished peer never
    answers)."""
    deadline = time.monotonic() + EXIT_GRACE_S
    for future in futures:
        if executor is not None and future is not None:
            executor.spin_until_future_complete(
                future, timeout_sec=max(deadline - time.monotonic(), 0.0))


def process_context() -> tuple[Context, bool]:
    """The process's one rclpy context (rclpy's default), initialised if it is not, and whether
    this call initialised it (the caller then shuts it down with `rclpy.try_shutdown()`).

    One context per process: each is a DDS participant while it has nodes, and Fast DDS can
    deadlock or crash when participants of one process come and go beside each other
    (eProsima/Fast-DDS #1016, #6193). rclpy's signal handlers are not installed: Ctrl-C stays
    the program's KeyboardInterrupt (a client cancels its goal on it), where rclpy's would shut
    the context down first.
    """
    if rclpy.ok():
        return rclpy.utilities.get_default_context(), False
    rclpy.try_shutdown()  # forgets a default context that was shut down
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    return rclpy.utilities.get_default_context(), True


def live_participants(pid: int | str = 'self') -> int:
    """The Fast DDS participants a process has now: each runs one event thread, `dds.ev.<n>`
    (Linux; for tests and benchmarks that check the one-context rule from outside)."""
    count = 0
    for task in Path(f'/proc/{pid}/task').iterdir():
        try:
            count += (task / 'comm').read_text().startswith('dds.ev.')
        except OSError:  # the thread ended meanwhile
            pass
    return count


def spin_until(executor: Executor, condition: Callable[[], bool], *,
               timeout_s: float) -> bool:
    """Spin until condition() holds or timeout_s of wall time passed; return condition().

    For scripts and tests that own their executor; never call it from a callback.
    """
    deadline = time.monotonic() + timeout_s
    while not condition():
        if time.monotonic() > deadline:
            return False
        executor.spin_once(timeout_sec=0.01)
    return True


def fail(message: str) -> int:
    """Print a one-line error to stderr and return the exit code for it."""
    print(f'error: {message}', file=sys.stderr)
    return 2

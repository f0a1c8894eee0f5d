"""A pytest plugin for bench/gil_starved_bench.py: a thread that holds the GIL in slices.

With GIL_HOG_SWITCH_S set, the test process gets a thread that computes in pure Python forever
and the interpreter's switch interval is set to that many seconds: every other thread of the
process (the executor's, its callbacks') waits up to one slice for the GIL at each hand-over.
This is what rclpy 7.1.6's MultiThreadedExecutor does to its own callbacks while a handler
awaits (its spin thread re-yields the waiting task without waiting, ros2/rclpy#1452), made
steady instead of now and then.

GIL_HOG_FROM says when the thread starts: `call` (the default) as the test's body starts, once
the simulator, the node and the executor are up; `configure` before collection, which starves
the imports as well (a run takes three times as long, and fails or passes alike).
"""

from __future__ import annotations

import os
import sys
import threading


def _compute() -> None:
    while True:
        sum(range(20_000))


def _start() -> None:
    switch = os.environ.get('GIL_HOG_SWITCH_S')
    if switch and not any(t.name == 'gil-hog' for t in threading.enumerate()):
        sys.setswitchinterval(float(switch))
        threading.Thread(target=_compute, name='gil-hog', daemon=True).start()


def pytest_configure(config) -> None:
    if os.environ.get('GIL_HOG_FROM') == 'configure':
        _start()


def pytest_runtest_call(item) -> None:
    _start()

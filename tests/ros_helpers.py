"""Helpers for driving an in-process executor in tests, without sleeps."""

import time
from collections.abc import Callable

from rclpy.executors import Executor


def spin_until(executor: Executor, condition: Callable[[], bool], *, timeout_s: float) -> bool:
    """Spin until condition() holds or timeout_s of wall time passed; return condition()."""
    deadline = time.monotonic() + timeout_s
    while not condition():
        if time.monotonic() > deadline:
            return False
        executor.spin_once(timeout_sec=0.02)
    return True

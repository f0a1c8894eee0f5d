"""One lock over a node's state, for nodes whose callbacks may run on several threads, and
what its holders say, logged once the lock is free."""

from __future__ import annotations

import threading
from collections.abc import Callable
from functools import wraps
from typing import Any, TypeVar

from rclpy.impl.rcutils_logger import RcutilsLogger

_Method = TypeVar('_Method', bound=Callable[..., Any])


class StateLock:
    """A re-entrant lock whose holders' log lines are written after the outermost holder lets
    go.

    rclpy's logger looks up its caller's source file on every line, a dozen system calls that
    each give up the GIL: on a MultiThreadedExecutor one line took 0.05-0.4 s, and every
    callback waiting for the lock waited with it (the poses among them: runs aborted for pose
    silence, tests/test_multithreaded.py).
    """

    def __init__(self, logger: RcutilsLogger) -> None:
        self._lock = threading.RLock()
        self._logger = logger
        self._depth = 0  # how many times the holder holds it
        self._said: list[tuple[bool, str]] = []  # (a warning?, line)

    def __enter__(self) -> StateLock:
        self._lock.acquire()
        self._depth += 1
        return self

    def __exit__(self, *_exception: object) -> None:
        self._depth -= 1
        if self._depth or not self._said:
            self._lock.release()
            return
        said, self._said = self._said, []
        self._lock.release()
        for warning, line in said:  # two call sites: rclpy keeps one severity per call site
            if warning:
                self._logger.warning(line)
            else:
                self._logger.info(line)

    def info(self, line: str) -> None:
        """Log `line` at INFO once the lock is free (call while holding it)."""
        self._said.append((False, line))

    def warning(self, line: str) -> None:
        """Log `line` at WARN once the lock is free (call while holding it)."""
        self._said.append((True, line))


def serialized(method: _Method) -> _Method:
    """Run `method` holding its object's `_state_lock` (a StateLock)."""
    @wraps(method)
    def locked(self: Any, *args: Any, **kwargs: Any) -> Any:
        with self._state_lock:
            return method(self, *args, **kwargs)
    return locked  # type: ignore[return-value]

"""How long a controller took to answer, less what the machine is to blame for: the node's
`walker.AnswerTimer`. A controller is not late because its thread waited for a CPU (Linux's
schedstat; nothing elsewhere) or collected garbage.
"""

from __future__ import annotations

import gc
import threading
import time

# Per thread: the collector's total time so far in it (`total`), and its last start. A
# collection holds up the thread that runs it; one run by another thread while a controller
# sleeps or computes is not the controller's excuse (counted for every thread, other threads'
# collections would be taken off a slow controller's time).
_collecting = threading.local()


def _on_collection(phase: str, _info: dict) -> None:
    now = time.perf_counter()
    if phase == 'start':
        _collecting.started = now
    else:
        _collecting.total = (getattr(_collecting, 'total', 0.0)
                             + now - getattr(_collecting, 'started', now))


gc.callbacks.append(_on_collection)


def not_the_controllers_s() -> float:
    """Time so far that no controller is to blame for: this thread waiting for a CPU and
    collecting garbage."""
    try:
        with open('/proc/thread-self/schedstat') as stats:
            waited = int(stats.read().split()[1]) * 1e-9
    except (OSError, IndexError, ValueError):
        waited = 0.0
    return waited + getattr(_collecting, 'total', 0.0)


class ProcessAnswerTimer:
    """The controller's own time: the wall clock less this thread's CPU waits and
    collections."""

    def start(self) -> tuple[float, float]:
        return time.perf_counter(), not_the_controllers_s()

    def took(self, mark: tuple[float, float]) -> float:
        started, excused = mark
        # the excuse read inside the timed span: a CPU wait as it is read (a system call is a
        # point where a busy machine preempts) is then in both, never excused alone
        excused = not_the_controllers_s() - excused
        return time.perf_counter() - started - excused

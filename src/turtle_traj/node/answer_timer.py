"""How long a controller took to answer, less what the machine is to blame for: the node's
`walker.AnswerTimer`. A controller is not late because its thread waited for a CPU (Linux's
schedstat; nothing elsewhere) or collected garbage.
"""

from __future__ import annotations

import gc
import os
import threading
import time

# Per thread: its schedstat file (`schedstat`), the collector's total time so far in it
# (`total`), and its last start. A collection holds up the thread that runs it; one run by
# another thread while a controller sleeps or computes is not the controller's excuse (counted
# for every thread, other threads' collections would be taken off a slow controller's time).
_collecting = threading.local()


def _on_collection(phase: str, _info: dict) -> None:
    now = time.perf_counter()
    if phase == 'start':
        _collecting.started = now
    else:
        _collecting.total = (getattr(_collecting, 'total', 0.0)
                             + now - getattr(_collecting, 'started', now))


gc.callbacks.append(_on_collection)


def _waited_s() -> float:
    """This thread's time so far waiting for a CPU (0 where Linux's schedstat is missing). The
    file stays open, one per thread, and is read again from its start: twice a control period,
    a read costs 1.3 us where opening it costs 13 us."""
    schedstat = getattr(_collecting, 'schedstat', None)
    if schedstat is None:
        try:
            schedstat = os.open('/proc/thread-self/schedstat', os.O_RDONLY)
        except OSError:
            schedstat = -1
        _collecting.schedstat = schedstat
    try:
        return int(os.pread(schedstat, 128, 0).split()[1]) * 1e-9
    except (OSError, IndexError, ValueError):
        return 0.0


def not_the_controllers_s() -> float:
    """Time so far that no controller is to blame for: this thread waiting for a CPU and
    collecting garbage."""
    return _waited_s() + getattr(_collecting, 'total', 0.0)


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

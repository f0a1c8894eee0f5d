"""How long a controller took to answer, less what the machine is to blame for: the node's
`walker.AnswerTimer`. A controller is not late because its thread waited for a CPU (Linux's
schedstat; nothing elsewhere) or collected garbage.

The schedstat file is read by libc's `pread` through `ctypes.PyDLL`, which keeps Python's lock
(the GIL) through the call: `os.pread` lets go of it, and the thread then waits to take it back
inside the timed span. Where another thread of the process spins (rclpy 7.1.6's
MultiThreadedExecutor yields again and again without waiting) on a busy machine, that wait can
be longer than a 16 ms period (`bench/gil_timer_bench.py`), and is no CPU wait to excuse.
"""

from __future__ import annotations

import ctypes
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


def _gil_keeping(name: str, result: type):
    """libc's function `name`, called with the GIL kept (None where there is no such libc)."""
    try:
        function = getattr(ctypes.PyDLL(None), name)
    except (OSError, AttributeError):
        return None
    function.restype = result
    return function


# The size and offset are passed made already (converting arguments by `argtypes` would double
# a read's cost). The file is opened with the GIL kept too: each of an executor's threads opens
# its own on its first answer, inside the timed span, where `os.open` would let go of it.
_PREAD = _gil_keeping('pread', ctypes.c_ssize_t)
_OPEN = _gil_keeping('open', ctypes.c_int)
_READ_BYTES = 128
_SIZE, _OFFSET = ctypes.c_size_t(_READ_BYTES), ctypes.c_long(0)
_SCHEDSTAT = ctypes.c_char_p(b'/proc/thread-self/schedstat')
_READ_ONLY = ctypes.c_int(os.O_RDONLY)


def _waited_s() -> float:
    """This thread's time so far waiting for a CPU (0 where Linux's schedstat is missing). The
    file stays open, one per thread, and is read again from its start, the GIL kept (see the
    module): twice a control period, a read costs 2 to 4 us where opening it costs 13 us."""
    schedstat = getattr(_collecting, 'schedstat', None)
    if schedstat is None:
        schedstat = _OPEN(_SCHEDSTAT, _READ_ONLY) if _OPEN is not None else -1
        _collecting.schedstat = schedstat
        _collecting.buffer = ctypes.create_string_buffer(_READ_BYTES)
    if schedstat < 0 or _PREAD is None:
        return 0.0
    buffer = _collecting.buffer
    count = _PREAD(schedstat, buffer, _SIZE, _OFFSET)
    try:
        return int(buffer.raw[:max(count, 0)].split()[1]) * 1e-9
    except (IndexError, ValueError):
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

    def took(self, mark: tuple[float, float], within_s: float) -> float:
        started, excused = mark
        wall = time.perf_counter() - started
        if wall <= within_s:  # in time, whatever it is excused (a read saved: most answers)
            return wall
        # the excuse read inside the timed span: a CPU wait as it is read (a system call is a
        # point where a busy machine preempts) is then in both, never excused alone
        excused = not_the_controllers_s() - excused
        return time.perf_counter() - started - excused

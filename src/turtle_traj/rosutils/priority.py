"""The control program's place in the CPU's queue: ahead of the machine's other work. Linux.

A control command that comes a step late leaves the robot acting on the one before (turtlesim
repeats it every step): at a corner's last approach that is drawn past the corner. Bursts of
other work (compilers, a browser, test workers) keep a process at the default priority waiting
longer than that now and then; measured here, a 62.5 Hz timer under waves of twelve processes
on two cores woke more than a step late at 0.05-0.1% of its ticks, and never at nice -10 (at
most 8 ms late). As ros2_control's controller manager raises its loop's priority, the node's
program asks for a higher one before ROS starts its threads (they inherit it); without the
permission it says why, once, and runs as it is. Not with a simulator in the same process: its
steps run in the node's thread, and a time-scaled physics base can take a whole core.

A nice value buys a larger share of the CPU, not a prompt wake-up: Linux's EEVDF scheduler
(6.6+) lets a running thread finish its slice (1.4 ms here) before a woken one runs, and a
woken thread may wait out several. So each thread also asks for a short slice
(`sched_setattr`; Linux 6.12 and later keep it for ordinary threads, older ones ignore it): a
thread with a shorter slice than the running one's preempts it as it wakes. Measured in the
two-host recipe's loop (three copies beside two busy loops), commands that acted a step late
fell from 3.4% (nice -10) to 1.7% with the slice, and to 0.6% with the simulator's program
raised as well (docs/concepts/robot-model.md).
"""

from __future__ import annotations

import argparse
import contextlib
import ctypes
import errno
import os
import platform
import struct
import threading
from dataclasses import dataclass

NICE = -10  # the node's default: ahead of ordinary work, behind the kernel's own threads
SLICE_S = 0.0002  # the scheduler slice asked for with it (Linux allows 0.1 to 100 ms)
_SCHED_SETATTR = {'x86_64': 314, 'aarch64': 274}  # the system call's number, by machine


@dataclass(frozen=True)
class Priority:
    """What the program runs at, and whether that is what it asked for."""

    nice: int
    granted: bool
    reason: str = ''  # why not, when not granted
    slice_s: float | None = None  # the scheduler slice, where the system call took it

    def __str__(self) -> str:
        if not self.granted:
            return f'scheduling priority: nice {self.nice} ({self.reason})'
        if self.slice_s is None:
            return f'scheduling priority: nice {self.nice}'
        return f'scheduling priority: nice {self.nice}, slice {self.slice_s * 1e3:g} ms'

    def report(self, logger) -> None:
        """Say it once at start-up: info when granted, a warning with the reason when not
        (each from a line of its own: rclpy ties one severity to a line that logs)."""
        if self.granted:
            logger.info(str(self))
        else:
            logger.warning(str(self))


def priority_for(asked: int | None, by_default: bool) -> Priority | None:
    """The program's priority: `--nice` as `asked`, else `NICE` when `by_default`; None when
    it runs as started (a value of 0 or more). Call it before rclpy starts its threads."""
    nice = asked if asked is not None else NICE if by_default else 0
    return raise_priority(nice) if nice < 0 else None


def raise_priority(nice: int = NICE) -> Priority:
    """Run this process's threads at `nice`, with a short scheduler slice (`SLICE_S`), and so
    the threads they start afterwards (call it before rclpy.init); a value already as high or
    higher is kept."""
    current = os.getpriority(os.PRIO_PROCESS, 0)
    if current > nice:
        try:
            os.setpriority(os.PRIO_PROCESS, 0, nice)
        except OSError as error:
            return Priority(current, False, f'nice {nice} refused: {error.strerror}; allow it '
                                            'with CAP_SYS_NICE or `ulimit -e`, or pass --nice 0')
        for thread in _others():  # Linux keeps a nice value per thread
            with contextlib.suppress(ProcessLookupError):  # one that ended meanwhile
                os.setpriority(os.PRIO_PROCESS, thread, nice)
    nice = os.getpriority(os.PRIO_PROCESS, 0)
    return Priority(nice, True, slice_s=SLICE_S if _ask_for_slice(nice) else None)


def _ask_for_slice(nice: int) -> bool:
    """Give every thread of this process the slice `SLICE_S` at `nice`; whether the system
    took it (a thread that ended meanwhile counts as served)."""
    number = _SCHED_SETATTR.get(platform.machine())
    if number is None:
        return False
    # struct sched_attr (48 bytes): size, policy (SCHED_OTHER), flags, nice, priority,
    # runtime (the slice, ns), deadline, period, util_min, util_max
    attr = ctypes.create_string_buffer(struct.pack(
        '=IIQiIQQQII', 48, 0, 0, nice, 0, round(SLICE_S * 1e9), 0, 0, 0, 0))
    libc = ctypes.CDLL(None, use_errno=True)
    for thread in [0, *_others()]:  # 0: this one
        if libc.syscall(number, thread, attr, 0) != 0 and ctypes.get_errno() != errno.ESRCH:
            return False
    return True


def _others() -> list[int]:
    """This process's other threads (those a library started at import)."""
    try:
        threads = [int(name) for name in os.listdir('/proc/self/task')]
    except OSError:  # not Linux: a nice value is the process's
        return []
    return [thread for thread in threads if thread != threading.get_native_id()]


def add_priority_option(parser: argparse.ArgumentParser, default: str = (
        'for the node alone; as started with a simulator in the process, whose steps share '
        'its thread (a time-scaled one can take a whole core)')) -> None:
    """The programs' `--nice N`; `default` says when the program takes `NICE`."""
    parser.add_argument('--nice', type=int, metavar='N',
                        help=f'run at this scheduling priority (-20 to 19; 0 or more: as '
                             f'started), with a short scheduler slice. Default: {NICE}, ahead '
                             f'of ordinary work, {default}. Negative values need CAP_SYS_NICE '
                             'or `ulimit -e`; without it the program says so and runs as it is')

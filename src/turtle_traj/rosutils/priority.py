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
"""

from __future__ import annotations

import argparse
import contextlib
import os
import threading
from dataclasses import dataclass

NICE = -10  # the node's default: ahead of ordinary work, behind the kernel's own threads


@dataclass(frozen=True)
class Priority:
    """What the program runs at, and whether that is what it asked for."""

    nice: int
    granted: bool
    reason: str = ''  # why not, when not granted

    def __str__(self) -> str:
        if self.granted:
            return f'scheduling priority: nice {self.nice}'
        return f'scheduling priority: nice {self.nice} ({self.reason})'


def raise_priority(nice: int = NICE) -> Priority:
    """Run this process's threads at `nice`, and so the threads they start afterwards (call it
    before rclpy.init); a value already as high or higher is kept."""
    current = os.getpriority(os.PRIO_PROCESS, 0)
    if current <= nice:
        return Priority(current, True)
    try:
        os.setpriority(os.PRIO_PROCESS, 0, nice)
    except OSError as error:
        return Priority(current, False, f'nice {nice} refused: {error.strerror}; allow it '
                                        'with CAP_SYS_NICE or `ulimit -e`, or pass --nice 0')
    for thread in _others():  # Linux keeps a nice value per thread
        with contextlib.suppress(ProcessLookupError):  # one that ended meanwhile
            os.setpriority(os.PRIO_PROCESS, thread, nice)
    return Priority(os.getpriority(os.PRIO_PROCESS, 0), True)


def _others() -> list[int]:
    """This process's other threads (those a library started at import)."""
    try:
        threads = [int(name) for name in os.listdir('/proc/self/task')]
    except OSError:  # not Linux: a nice value is the process's
        return []
    return [thread for thread in threads if thread != threading.get_native_id()]


def add_priority_option(parser: argparse.ArgumentParser) -> None:
    """The programs' `--nice N`."""
    parser.add_argument('--nice', type=int, metavar='N',
                        help=f'run the node at this scheduling priority (-20 to 19; 0 or more: as '
                             f'started). Default: {NICE}, ahead of ordinary work, for the node '
                             'alone; as started with a simulator in the process, whose steps '
                             'share its thread (a time-scaled one can take a whole core). '
                             'Negative values need CAP_SYS_NICE or `ulimit -e`; without it the '
                             'node says so and runs as it is')

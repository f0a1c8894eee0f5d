"""What timing a controller's answer costs when another thread of the process spins: the
schedstat file read by `os.pread` (which lets go of Python's lock, the GIL) against the node's
read through `ctypes.PyDLL` (which keeps it: `node/answer_timer.py`), side by side in one run.

    .venv/bin/python bench/gil_timer_bench.py [--spans 600] [--busy 2]

A thread spins in Python, as rclpy 7.1.6's MultiThreadedExecutor does while a handler waits
(ros2/rclpy#1452). Every 16 ms the main thread times a span of about 20 us of work as the node
times a controller's answer: the clock, the CPU wait so far, the work, the CPU wait again, the
clock; the span less the CPU wait between the two readings. `--busy` processes spin at the
same time on their own (a loaded machine, as in the suite beside two busy loops). Printed per
way: the median, the 99th percentile and the largest span, and how many exceed the 16 ms
control period.
"""

from __future__ import annotations

import argparse
import os
import threading
import time

from load import busy_loops
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.node import answer_timer

WORK_STEPS = 300  # about 20 us of Python


def _os_pread_waited() -> float:
    """The thread's CPU wait read by os.pread (the GIL let go during the call)."""
    schedstat = getattr(_os_pread_waited, 'fd', None)
    if schedstat is None:
        schedstat = _os_pread_waited.fd = os.open('/proc/thread-self/schedstat', os.O_RDONLY)
    return int(os.pread(schedstat, 128, 0).split()[1]) * 1e-9


def _spans(waited, count: int) -> list[float]:
    """`count` timed spans, one a control period, beside a spinning thread."""
    stop = threading.Event()

    def spin() -> None:
        while not stop.is_set():
            pass
    spinner = threading.Thread(target=spin, daemon=True)
    spinner.start()
    spans = []
    try:
        for _ in range(count):
            time.sleep(STEP_S)
            started, excused = time.perf_counter(), waited()
            total = 0
            for step in range(WORK_STEPS):
                total += step * step
            excused = waited() - excused
            spans.append(time.perf_counter() - started - excused)
    finally:
        stop.set()
        spinner.join()
    return sorted(spans)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--spans', type=int, default=600)
    parser.add_argument('--busy', type=int, default=2, help='busy processes beside it')
    options = parser.parse_args()
    with busy_loops(options.busy):
        print(f'{options.spans} spans of {WORK_STEPS} steps beside a spinning thread and '
              f'{options.busy} busy processes')
        print(f'{"schedstat read by":22} {"median ms":>9} {"p99 ms":>7} {"max ms":>7} '
              f'{"over 16 ms":>10}')
        for name, waited in (('os.pread (GIL let go)', _os_pread_waited),
                             ('ctypes.PyDLL (node)', answer_timer._waited_s)):
            spans = _spans(waited, options.spans)
            late = sum(span > STEP_S for span in spans)
            print(f'{name:22} {spans[len(spans) // 2] * 1e3:9.3f} '
                  f'{spans[int(0.99 * len(spans))] * 1e3:7.3f} {spans[-1] * 1e3:7.3f} '
                  f'{late:10d}')


if __name__ == '__main__':
    main()

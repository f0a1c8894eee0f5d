"""Processes' CPU shares and waiting for a running system: helpers the benchmarks share.

Imports nothing of turtle_traj, so a benchmark can use it while it measures an older tree.
"""

from __future__ import annotations

import os
import time
from pathlib import Path


def process_cpu_s(pid: int) -> float:
    """CPU time (user + system) a process has used, from /proc."""
    fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


def cpu_share(pid: int, seconds: float) -> float:
    """The share of one core the process used over the next `seconds`."""
    start_cpu, start_wall = process_cpu_s(pid), time.monotonic()
    time.sleep(seconds)
    return (process_cpu_s(pid) - start_cpu) / (time.monotonic() - start_wall)


def wait_until_connected(client, timeout_s: float = 30.0) -> None:
    """Ask the trajectory node (through a TrajClient) to reset until it succeeds: then it has
    the simulator's poses."""
    deadline = time.monotonic() + timeout_s
    while not client.call('reset').success:
        if time.monotonic() > deadline:
            raise RuntimeError('the trajectory node never got the simulator')
        time.sleep(0.2)

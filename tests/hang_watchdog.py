"""The last resort against a hung test: a process beside the test process that ends it.

pytest-timeout fails a test that runs too long by a signal handled in Python, which never runs
while a native call holds the GIL (as a Fast DDS deadlock inside a finaliser once did). This
process does not need the test process's GIL: when a test outlives its time limit plus a grace,
it prints every thread's native stack (gdb, where installed), then sends SIGABRT, whose
faulthandler (enabled by pytest) prints every thread's Python stack before the process dies.
pytest-xdist then reports the worker crashed, naming the test it was running.

The test process writes one line per test to this process's standard input: `SECONDS NODEID` to
arm, an empty line to disarm; end of input ends this process.
"""

from __future__ import annotations

import os
import select
import shutil
import signal
import subprocess
import sys
import time


class HangWatchdog:
    """The test process's side: starts the watchdog and arms it around each test."""

    def __init__(self) -> None:
        self._process = subprocess.Popen([sys.executable, __file__, str(os.getpid())],
                                         stdin=subprocess.PIPE, text=True)

    def arm(self, seconds: float, test: str) -> None:
        self._send(f'{seconds:g} {test}')

    def disarm(self) -> None:
        self._send('')

    def close(self) -> None:
        self._process.stdin.close()
        self._process.wait(timeout=10)

    def _send(self, line: str) -> None:
        self._process.stdin.write(line + '\n')
        self._process.stdin.flush()


def _say(text: str) -> None:
    sys.stderr.write(f'\n[hang watchdog] {text}\n')
    sys.stderr.flush()


def _end(pid: int, test: str, seconds: float) -> None:
    _say(f'{test} ran over {seconds:g} s and does not answer its own time limit: the native '
         f'stacks of every thread of process {pid}, then (SIGABRT) their Python stacks')
    gdb = shutil.which('gdb')
    if gdb is None:
        _say('gdb is not installed: no native stacks')
    else:
        try:
            subprocess.run([gdb, '-batch', '-nx', '-p', str(pid), '-ex', 'thread apply all bt'],
                           stdin=subprocess.DEVNULL, stdout=sys.stderr, stderr=sys.stderr,
                           timeout=120, check=False)
        except subprocess.TimeoutExpired:
            _say('gdb did not finish within 120 s')
    os.kill(pid, signal.SIGABRT)


def main(pid: int) -> None:
    deadline, test, seconds = None, '', 0.0
    buffered = ''
    while True:
        wait = None if deadline is None else max(0.0, deadline - time.monotonic())
        ready, _, _ = select.select([sys.stdin], [], [], wait)
        if not ready:
            _end(pid, test, seconds)
            return
        chunk = os.read(sys.stdin.fileno(), 65536).decode()
        if not chunk:
            return
        buffered += chunk
        *lines, buffered = buffered.split('\n')
        for line in lines:
            if line:
                limit, test = line.split(' ', 1)
                seconds = float(limit)
                deadline = time.monotonic() + seconds
            else:
                deadline = None


if __name__ == '__main__':
    main(int(sys.argv[1]))

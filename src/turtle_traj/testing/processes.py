"""Our programs as separate processes, for tests: started, read as they run, always reaped."""

from __future__ import annotations

import os
import pty
import select
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


class Program(subprocess.Popen):
    """A program whose standard error is read as it comes (a full pipe would stall it) and
    kept, so that a failing test can show what the program said."""

    def start_reading(self) -> None:
        self.lines: list[str] = []
        self._reader = threading.Thread(target=lambda: self.lines.extend(self.stderr),
                                        daemon=True)
        self._reader.start()

    def said(self) -> str:
        """Everything the program wrote to stderr after it started, so far."""
        return ''.join(self.lines)

    def wait_and_read(self) -> str:
        self.wait(timeout=15)
        self._reader.join(timeout=15)
        return self.said()


@contextmanager
def program(*args: str, cwd: Path | None = None) -> Iterator[Program]:
    """Run `python -m ARGS` until its turtle1 has spawned; always reaped afterwards."""
    process = Program([sys.executable, '-m', *args], stdout=subprocess.DEVNULL,
                      stderr=subprocess.PIPE, text=True, cwd=cwd)
    try:
        for line in process.stderr:
            if 'Spawning turtle [turtle1]' in line:
                break
        process.start_reading()
        yield process
    finally:
        process.kill()
        process.wait_and_read()


def program_nice(pid: int) -> set[int]:
    """The nice values of a running program's threads (Linux)."""
    values = set()
    for thread in Path(f'/proc/{pid}/task').iterdir():
        try:  # the 19th field of stat; the name before it, in brackets, may hold spaces
            values.add(int((thread / 'stat').read_text().rsplit(')', 1)[1].split()[16]))
        except FileNotFoundError:  # a thread that ended meanwhile
            continue
    return values


def terminate(process: subprocess.Popen) -> str:
    """Send SIGTERM, wait for the exit and return what the program wrote to stderr."""
    process.terminate()
    if isinstance(process, Program):
        return process.wait_and_read()
    return process.communicate(timeout=15)[1]


class Terminal:
    """`python -m ARGS` on a pseudo-terminal, as a person at a keyboard runs it."""

    def __init__(self, *args: str) -> None:
        self.pid, self._fd = pty.fork()
        if self.pid == 0:  # the child: become the program, Ctrl-C live as at a keyboard
            signal.signal(signal.SIGINT, signal.SIG_DFL)  # a background job's is ignored
            os.execv(sys.executable, [sys.executable, '-m', *args])
        self.output = ''
        self._seen = 0  # where the next `expect` starts looking

    def expect(self, text: str, timeout_s: float = 30.0) -> str:
        """Read until `text` is written after the previous expected text (AssertionError after
        `timeout_s`); return what came before it."""
        deadline = time.monotonic() + timeout_s
        while (found := self.output.find(text, self._seen)) < 0:
            assert time.monotonic() < deadline, f'{text!r} not seen; got:\n{self.output}'
            self._read(deadline - time.monotonic())
        before, self._seen = self.output[self._seen:found], found + len(text)
        return before

    def send(self, keys: str) -> None:
        """Type `keys` ('\\x03' is Ctrl-C: the terminal interrupts the program)."""
        os.write(self._fd, keys.encode())

    @property
    def fd(self) -> int:
        """The terminal's side of the pseudo-terminal (its modes are the program's)."""
        return self._fd

    def finish(self, timeout_s: float = 30.0, *, close: bool = True) -> int:
        """Read to the end and return the exit code (the program is killed after `timeout_s`);
        with `close` False the terminal stays open, to look at the modes it was left in."""
        deadline = time.monotonic() + timeout_s
        while self._read(deadline - time.monotonic()):
            pass
        if time.monotonic() >= deadline:
            os.kill(self.pid, signal.SIGKILL)
        status = os.waitpid(self.pid, 0)[1]
        if close:
            self.close()
        return os.waitstatus_to_exitcode(status)

    def close(self) -> None:
        os.close(self._fd)

    def _read(self, timeout_s: float) -> bool:
        """Read what is there (False at the end of the output or of the time)."""
        ready, _, _ = select.select([self._fd], [], [], max(timeout_s, 0.0))
        if not ready:
            return False
        try:
            chunk = os.read(self._fd, 4096)
        except OSError:  # the program has exited
            return False
        self.output += chunk.decode(errors='replace')
        return bool(chunk)

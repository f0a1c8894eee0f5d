"""Helpers for tests that run our programs as separate processes."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def program(*args: str, cwd: Path | None = None) -> Iterator[subprocess.Popen]:
    """Run `python -m ARGS` until its turtle1 has spawned; always reaped afterwards."""
    process = subprocess.Popen([sys.executable, '-m', *args], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, cwd=cwd)
    try:
        for line in process.stderr:
            if 'Spawning turtle [turtle1]' in line:
                break
        yield process
    finally:
        process.kill()
        process.communicate(timeout=15)


def terminate(process: subprocess.Popen) -> str:
    """Send SIGTERM, wait for the exit and return what the program wrote to stderr."""
    process.terminate()
    return process.communicate(timeout=15)[1]

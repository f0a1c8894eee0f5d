"""How many rooms run at once on this machine, whichever grader started them.

One grader runs up to `grader.default_jobs()` rooms at once. Two classes graded at the same
time (two teachers, or a test suite's workers) would run twice as many, and an open-loop
student's program, starved beside them, sleeps past its deadlines and loses points it should
have. A room therefore holds one of the machine's slots while it runs: an exclusive lock on
one of `count` files, which goes with its holder even if that is killed.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

_POLL_S = 0.05  # how often a grader waiting for a slot looks again


def slots_folder() -> Path:
    """Where the slots' files are: under /run for root (no other user can make it first),
    else in the temporary folder, one per user."""
    base = Path('/run') if os.geteuid() == 0 and Path('/run').is_dir() else Path(
        tempfile.gettempdir())
    return base / f'turtle_traj-rooms-{os.geteuid()}'


@contextlib.contextmanager
def room_slot(count: int, folder: Path | None = None) -> Iterator[int]:
    """Hold one of `count` slots (waiting for one to free) while the block runs: its index."""
    folder = folder or slots_folder()
    folder.mkdir(mode=0o700, exist_ok=True)
    while True:
        for index in range(count):
            handle = os.open(folder / f'slot-{index}', os.O_RDWR | os.O_CREAT, 0o600)
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(handle)
                continue
            try:
                yield index
            finally:
                os.close(handle)  # the lock goes with it
            return
        time.sleep(_POLL_S)

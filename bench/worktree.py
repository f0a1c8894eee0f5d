"""An older commit checked out beside this one, for benchmarks that pair the two."""

from __future__ import annotations

import contextlib
import subprocess
import tempfile
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


@contextlib.contextmanager
def old_tree(rev: str) -> Iterator[Path]:
    """`rev` in a temporary git worktree of this checkout (removed afterwards)."""
    folder = Path(tempfile.mkdtemp(prefix='turtle_traj_bench_')) / 'old'
    subprocess.run(['git', '-C', str(ROOT), 'worktree', 'add', '--detach', str(folder), rev],
                   check=True, capture_output=True)
    try:
        yield folder
    finally:
        subprocess.run(['git', '-C', str(ROOT), 'worktree', 'remove', '--force', str(folder)],
                       capture_output=True)

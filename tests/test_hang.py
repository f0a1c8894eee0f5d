"""A hung test fails fast and says where it hung, even where Python cannot run (a native call
holding the GIL, as a Fast DDS deadlock inside a finaliser once did): tests/conftest.py's time
limit and its watchdog, checked on small suites run by a pytest of their own."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.system  # runs pytest in processes: `make check` leaves it out
ROOT = Path(__file__).resolve().parents[1]
TIME_LIMIT_S, GRACE_S = 1, 2
HANGS = '''
import ctypes
import time


def test_sleeps_in_python():
    time.sleep(600)


def test_holds_the_gil_in_native_code():
    # A mutex locked twice by one thread, the GIL held: a deadlock no signal ends.
    libc, mutex = ctypes.PyDLL(None), ctypes.create_string_buffer(64)  # zeros: an unlocked one
    libc.pthread_mutex_lock(mutex)
    libc.pthread_mutex_lock(mutex)
'''


def _run(tmp_path: Path, test: str, *options: str) -> tuple[subprocess.CompletedProcess, float]:
    suite = tmp_path / 'test_hangs.py'
    suite.write_text(HANGS)
    start = time.monotonic()
    ran = subprocess.run(
        [sys.executable, '-m', 'pytest', '-p', 'tests.conftest', '-p', 'no:cacheprovider',
         f'--timeout={TIME_LIMIT_S}', f'--rootdir={tmp_path}', *options, f'{suite}::{test}'],
        cwd=ROOT, env={**os.environ, 'TURTLE_TRAJ_HANG_GRACE_S': str(GRACE_S)},
        capture_output=True, text=True, timeout=300)
    return ran, time.monotonic() - start


def test_a_test_over_its_time_limit_fails_with_every_threads_stack(tmp_path):
    ran, took_s = _run(tmp_path, 'test_sleeps_in_python')
    assert ran.returncode == 1, ran.stdout + ran.stderr
    assert f'Failed: Timeout (>{TIME_LIMIT_S:.1f}s) from pytest-timeout' in ran.stdout, ran.stdout
    assert 'time.sleep(600)' in ran.stdout  # where it hung
    assert took_s < 60


def test_a_hang_that_holds_the_gil_is_ended_with_native_and_python_stacks(tmp_path):
    ran, took_s = _run(tmp_path, 'test_holds_the_gil_in_native_code')
    said = ran.stdout + ran.stderr
    assert ran.returncode not in (0, 1), said  # killed: SIGABRT
    assert ('[hang watchdog] ' in ran.stderr and 'test_holds_the_gil_in_native_code ran over '
            f'{TIME_LIMIT_S + GRACE_S:g} s' in ran.stderr), said
    assert 'Fatal Python error: Aborted' in ran.stderr, said
    assert 'in test_holds_the_gil_in_native_code' in ran.stderr  # the Python stack
    if shutil.which('gdb') is not None:
        assert 'mutex_lock' in ran.stderr.split('[hang watchdog]')[1]  # gdb's native frames
    assert took_s < 180


def test_a_worker_killed_by_the_watchdog_names_its_test(tmp_path):
    pytest.importorskip('xdist')
    ran, _ = _run(tmp_path, 'test_holds_the_gil_in_native_code', '-n', '1')
    said = ran.stdout + ran.stderr
    assert ran.returncode != 0, said
    assert "crashed while running 'test_hangs.py::test_holds_the_gil_in_native_code'" in said, said

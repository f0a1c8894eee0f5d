"""The pytest plugin is registered for pytest (a user's test that uses it, in a folder outside
the repository, is the tutorial docs/tutorials/testing-your-node.md: tests/test_tutorials.py
runs it as written); a run ended by SIGTERM leaves nothing running, and so does the pose log."""

import contextlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest


def test_the_plugin_is_registered_for_pytest():
    from importlib.metadata import entry_points

    (entry,) = [e for e in entry_points(group='pytest11') if e.name == 'turtle_traj']
    plugin = entry.load()
    assert {'ros_domain_id', 'rclpy_context', 'turtle_sim', 'turtle_system'} <= set(vars(plugin))


# A run its user ends with SIGTERM: two xdist workers, each in a test whose fixture started a
# program. Then the run is terminated: its controller alone (as `timeout` and a CI runner do), or
# its whole process group (as `kill -- -PGID` does). The programs must not outlive the run.
_LONG_TEST = '''
import os, subprocess, sys, time
from pathlib import Path

import pytest


@pytest.fixture
def program():
    process = subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(600)'])
    yield process
    process.kill()
    process.wait()
    Path(os.environ['OUT'], f'{process.pid}.reaped').touch()


def test_a_long_one(program):
    Path(os.environ['OUT'], f'{program.pid}.started').touch()
    time.sleep(600)
'''


def _alive(pid: int) -> bool:
    """A process with that pid runs (a zombie has ended)."""
    try:
        stat = Path(f'/proc/{pid}/stat').read_text()
    except FileNotFoundError:
        return False
    return stat.rsplit(')', 1)[1].split()[0] != 'Z'


@pytest.mark.system
@pytest.mark.parametrize('whom', ['the controller', 'the process group'])
def test_a_run_ended_by_sigterm_tears_down_what_its_tests_started(tmp_path, whom):
    (tmp_path / 'test_long.py').write_text(_LONG_TEST)
    out = tmp_path / 'out'
    out.mkdir()
    run = subprocess.Popen(
        [sys.executable, '-m', 'pytest', '-q', '-n', '2', '--dist', 'each', '-p',
         'no:cacheprovider', 'test_long.py'], cwd=tmp_path, env={**os.environ, 'OUT': str(out)},
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + 60
        while len(started := list(out.glob('*.started'))) < 2:
            assert run.poll() is None, run.communicate()[0]
            assert time.monotonic() < deadline, 'the workers never began their tests'
            time.sleep(0.1)
        if whom == 'the controller':
            run.terminate()
        else:
            os.killpg(run.pid, signal.SIGTERM)
        said = run.communicate(timeout=30)[0]
        programs = [int(path.stem) for path in started]
        assert not [pid for pid in programs if _alive(pid)], said
        assert sorted(path.stem for path in out.glob('*.reaped')) == sorted(map(str, programs))
        assert 'KeyboardInterrupt: SIGTERM received' in said
    finally:  # whatever a failure left in the run's group
        with contextlib.suppress(ProcessLookupError):
            os.killpg(run.pid, signal.SIGKILL)


@pytest.mark.system
def test_the_pose_log_ends_on_sigterm_with_nothing_to_log(tmp_path, ros_domain_id):
    """With no simulator, nothing wakes its executor: a signal must (a Python handler alone
    waited for a message that never came, and the log outlived its test run)."""
    log = subprocess.Popen([sys.executable, '-m', 'turtle_traj.testing.pose_log',
                            str(tmp_path / 'poses.log')], stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 30
        while not (tmp_path / 'poses.log').exists():  # opened once its node is up
            assert log.poll() is None, log.communicate()[1]
            assert time.monotonic() < deadline, 'the pose log never started'
            time.sleep(0.05)
        log.terminate()
        assert log.wait(timeout=15) == 0, log.communicate()[1]
    finally:
        log.kill()
        log.wait()


def test_a_pose_log_read_while_it_is_written_takes_only_complete_lines(tmp_path):
    """The two-host tests read the log as the pose log appends to it (a half-written last
    line made a pose of two numbers, and the read failed: once in a quiet full suite)."""
    from turtle_traj.testing.pose_log import PoseLog

    log = tmp_path / 'poses.log'
    log.write_text('pose 1.0 5.5 5.5 0.0\nplan 1.5 5.5 5.5 6.0 5.5\npose 2.0 5.6 5.5 0.0\n'
                   'pose 3.0 5.')
    read = PoseLog.read(log)
    assert read.poses.tolist() == [[1.0, 5.5, 5.5, 0.0], [2.0, 5.6, 5.5, 0.0]]
    assert [(t, points.tolist()) for t, points in read.plans] == [(1.5, [[5.5, 5.5], [6.0, 5.5]])]

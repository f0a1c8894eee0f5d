"""One rclpy context, hence at most one DDS participant, in every program, counted from outside:
each Fast DDS participant runs one event thread, `dds.ev.<n>`."""

import subprocess
import sys
import time

import pytest

from turtle_traj.rosutils.runtime import live_participants
from turtle_traj.testing.browser import free_port
from turtle_traj.testing.processes import program, terminate

pytestmark = pytest.mark.system  # starts programs: `make check` leaves it out


def _most_participants_while_it_runs(process: subprocess.Popen, timeout_s: float, *,
                                     once_up_s: float | None = None) -> int:
    """The most participants seen in `process` until it ends or `timeout_s` passed; with
    `once_up_s`, until that long after its first (a program still starting has none)."""
    most, deadline = 0, time.monotonic() + timeout_s
    while process.poll() is None and time.monotonic() < deadline:
        try:
            seen = live_participants(process.pid)
        except OSError:  # it just ended
            break
        if once_up_s is not None and seen and not most:
            deadline = min(deadline, time.monotonic() + once_up_s)
        most = max(most, seen)
        time.sleep(0.01)
    return most


def test_each_program_has_one_participant(tmp_path):
    # The simulator, the trajectory node and the live view in one process.
    with program('turtle_traj', '--with-sim', '--web', '--web-port', str(free_port()),
                 cwd=tmp_path) as system:
        cli = [sys.executable, '-m', 'turtle_traj.cli', '--wait', '30']
        drawing = subprocess.Popen([*cli, 'move', '0.5'], stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True)
        assert _most_participants_while_it_runs(drawing, 60.0) == 1
        said = drawing.communicate(timeout=30)
        assert drawing.returncode == 0, said
        assert 'done: move done' in said[0]
        recording = subprocess.Popen([*cli, 'record', '--output', str(tmp_path / 'bag')],
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        assert _most_participants_while_it_runs(recording, 60.0, once_up_s=1.0) == 1
        terminate(recording)
        assert live_participants(system.pid) == 1

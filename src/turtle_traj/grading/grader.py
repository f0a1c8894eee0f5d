"""Grade a class: every submission in a folder run in its own room against the grader's simulator,
in parallel, and judged from what the simulator recorded (`core.grading.judge`).

Each submission (a sub-folder) gets `OUT/runs/<name>/`: its private work copy (`work/`, the
only folder it can write), what the simulator saw (`record.json`, `canvas.png`), its output
(`student.log`) and how the run ended (`outcome.json`). The submissions and `OUT` are hidden
from every run.
"""

from __future__ import annotations

import itertools
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from turtle_traj.core.grading.judge import (
    NEVER_MOVED,
    Check,
    Fit,
    Record,
    drawn_points,
    fit,
    judge,
)
from turtle_traj.core.grading.task import Task
from turtle_traj.grading.forward import UnixForwarder
from turtle_traj.grading.room import Outcome
from turtle_traj.grading.sandbox import (
    RunGroup,
    RunLimits,
    SandboxUnavailable,
    bubblewrap,
    room_command,
    simulator_first,
    student_command,
)
from turtle_traj.grading.slots import room_slot
from turtle_traj.grading.submission import NotReady, copy_submission, prepare

ROOM_GRACE_S = 30.0  # the room's start and end, beyond the student's time limit
ROOM_START_S = 20.0  # the longest the next room waits for one to start
LOG_TAIL_CHARS = 3000
RUNS_PER_CORE = 4  # runs at once: an open-loop script mostly sleeps
_NAME = re.compile(r'^[\w.-]{1,64}$')


@dataclass
class StudentResult:
    """One submission's grade."""

    name: str
    checks: list[Check]
    ended: str  # how the run ended, or why it could not run
    run_dir: Path
    log: str = ''
    peak: dict = field(default_factory=dict)
    fit: Fit | None = None
    drawn: list = field(default_factory=list)  # the pen's strokes, for the picture
    seconds: float = 0.0  # the grader's time on it (waiting for a room's slot included)
    room_s: float = 0.0  # how long its room ran, once it held a slot (0: it did not run)

    @property
    def score(self) -> float:
        return sum(check.score for check in self.checks)

    @property
    def max_score(self) -> float:
        return sum(check.max_score for check in self.checks)


def submissions_in(folder: Path) -> list[Path]:
    """The submissions: every sub-folder with a plain name, sorted."""
    return sorted(path for path in folder.iterdir()
                  if path.is_dir() and not path.is_symlink() and _NAME.match(path.name)
                  and not path.name.startswith('.'))


def default_jobs() -> int:
    return RUNS_PER_CORE * (os.cpu_count() or 1)


def grade_class(task: Task, submissions: Path, out: Path, *, jobs: int | None = None,
                on_result: Callable[[StudentResult], None] | None = None
                ) -> list[StudentResult]:
    """Every submission in `submissions`, graded; results in the folders' order.

    :raises SandboxUnavailable: this machine cannot isolate the runs.
    """
    bubblewrap()
    submissions, out = submissions.resolve(), out.resolve()  # the sandboxes bind absolute paths
    folders = submissions_in(submissions)
    runs = out / 'runs'
    runs.mkdir(parents=True, exist_ok=True)
    hidden = [submissions, out]

    def one(index_folder: tuple[int, Path]) -> StudentResult:
        index, folder = index_folder
        result = grade_one(task, folder, runs / folder.name, hidden, domain_id=1 + index % 100)
        if on_result is not None:
            on_result(result)
        return result

    with ThreadPoolExecutor(max_workers=max(1, jobs or default_jobs())) as pool:
        return list(pool.map(one, enumerate(folders)))


def watch_one(task: Task, submissions: Path, out: Path, name: str, port: int,
              on_url: Callable[[str], None]) -> StudentResult:
    """Submission `name` graded while its simulator's live view (watch only) is served on
    http://127.0.0.1:`port`/ (`on_url` hears the address before the run starts).

    :raises SandboxUnavailable: this machine cannot isolate the run.
    :raises ValueError: there is no such submission.
    :raises OSError: the port is taken.
    """
    bubblewrap()
    submissions, out = submissions.resolve(), out.resolve()
    folder = submissions / name
    if folder not in submissions_in(submissions):
        raise ValueError(f'no submission {name!r} in {submissions}')
    with tempfile.TemporaryDirectory(prefix='turtle_traj_live_') as sockets:
        socket = Path(sockets) / 'view.sock'  # short: a socket's path has 107 bytes at most
        forwarder = UnixForwarder(socket, port)
        on_url(forwarder.start())
        try:
            return grade_one(task, folder, out / 'runs' / name, [submissions, out],
                             domain_id=1, live_view=socket)
        finally:
            forwarder.stop()


def grade_one(task: Task, folder: Path, run_dir: Path, hidden: list[Path], *,
              domain_id: int, live_view: Path | None = None) -> StudentResult:
    """One submission, run in its room and judged; with `live_view`, the room serves its
    simulator's live view (watch only) on that Unix socket."""
    started = time.monotonic()
    if run_dir.exists():
        shutil.rmtree(run_dir)
    run_dir.mkdir(parents=True)
    work = run_dir / 'work'
    try:
        copy_submission(folder, work)
        ready = prepare(task, work, hidden, domain_id)
        result = _run(task, folder.name, run_dir, work, hidden, ready.argv, ready.environment,
                      domain_id, live_view)
    except NotReady as reason:
        result = _not_run(task, folder.name, run_dir, str(reason))
    except (OSError, ValueError, KeyError, TypeError) as error:  # never the class's grading
        result = _not_run(task, folder.name, run_dir,
                          f'the grader failed on it: {type(error).__name__}: {error}')
    result.seconds = time.monotonic() - started
    return result


def _run(task: Task, name: str, run_dir: Path, work: Path, hidden: list[Path],
         argv: list[str], environment: dict[str, str], domain_id: int,
         live_view: Path | None) -> StudentResult:
    limits = RunLimits(wall_s=task.time_limit_s)
    # named by this process and a count: two classes graded at once both have their 'right'
    group = (RunGroup(f'{os.getpid()}-{next(_RUNS)}-{name}', limits) if RunGroup.available()
             else None)
    try:
        command = student_command(argv, work, hidden, environment, limits,
                                  grouped=group is not None)
        spec = {'command': command, 'run_dir': str(run_dir), 'wall_s': limits.wall_s,
                'settle_s': task.settle_s, 'domain_id': domain_id,
                'live_view': str(live_view or '')}
        (run_dir / 'spec.json').write_text(json.dumps(spec))
        room_error, room_s = _run_room(room_command(sys.executable, run_dir / 'spec.json',
                                                    run_dir, group, live_view), run_dir,
                                       limits.wall_s + ROOM_GRACE_S)
        peak = group.peak() if group else {}
        tasks_hit = group is not None and group.hit_tasks_limit()
    finally:
        if group is not None:
            group.remove()
    log = _tail(run_dir / 'student.log')
    if room_error:
        return _not_run(task, name, run_dir, f'the grader failed to run it: {room_error}', log)
    outcome = Outcome(**json.loads((run_dir / 'outcome.json').read_text()))
    record = Record.from_simulator(json.loads((run_dir / 'record.json').read_text()))
    ended = outcome.describe() + ('; it was refused more processes (the limit is '
                                  f'{limits.tasks})' if tasks_hit else '')
    drawn = drawn_points(record)
    placed = (fit(task.expected, drawn) if len(drawn) >= 2 and task.expected.shape != 'none'
              else None)  # judged once, drawn in the picture and the replay
    checks = judge(task, record, placed)
    if outcome.lost_steps and any(check.message != NEVER_MOVED for check in checks):
        ended += (f'; the simulator fell {outcome.lost_steps} steps behind (the machine was too '
                  'busy): grade it again')
    return StudentResult(name, checks, ended, run_dir, log, peak, placed,
                         [stroke.tolist() for stroke in record.strokes], room_s=room_s)


_RUNS = itertools.count()
_STARTING = threading.Lock()  # one room starts at a time (see `_run_room`)
_START_POLL_S = 0.02


def _run_room(command: list[str], run_dir: Path, timeout_s: float) -> tuple[str, float]:
    """Run the room: '' when it saved its outcome, else what went wrong; and how long it ran
    (from when it held a slot).

    Rooms start one at a time: a room's start (Python, rclpy, the simulator: about a second
    of a core) runs at nice -10, and several starting together keep running simulators from
    their steps (the turtle then moves less than it was told to). Started, its simulator runs
    real-time (`simulator_first`). A room first waits for one of the machine's slots
    (`slots.room_slot`): no more rooms run at once than one grader would start."""
    with room_slot(default_jobs()), (run_dir / 'room.log').open('wb') as log:
        began = time.monotonic()
        with _STARTING:
            room = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=log,
                                    stderr=subprocess.STDOUT, start_new_session=True)
            deadline = time.monotonic() + ROOM_START_S
            while (not (run_dir / 'started').exists() and room.poll() is None
                   and time.monotonic() < deadline):
                time.sleep(_START_POLL_S)
            simulator_first(room.pid)
        try:
            room.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            os.killpg(room.pid, signal.SIGKILL)
            room.wait()
            return f'its room did not end within {timeout_s:.0f} s', time.monotonic() - began
        ran_s = time.monotonic() - began
    if room.returncode != 0 or not (run_dir / 'outcome.json').exists():
        return (f'its room ended with status {room.returncode}: '
                f'{_tail(run_dir / "room.log")}', ran_s)
    return '', ran_s


def _not_run(task: Task, name: str, run_dir: Path, reason: str, log: str = ''
             ) -> StudentResult:
    checks = [Check(check, 0.0, points, 'not run') for check, points in task.points.items()]
    return StudentResult(name, checks, reason, run_dir, log)


def _tail(path: Path) -> str:
    try:
        with path.open('rb') as file:
            file.seek(max(0, path.stat().st_size - LOG_TAIL_CHARS))
            return file.read().decode(errors='replace')
    except OSError:
        return ''


__all__ = ['SandboxUnavailable', 'StudentResult', 'grade_class', 'grade_one', 'submissions_in',
           'watch_one']

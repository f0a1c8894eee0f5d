"""The walls round a student's run: bubblewrap's namespaces, a control group's limits, and
resource limits on each process. Linux.

A run is two sandboxes, one inside the other:

- the *room* (`room_command`): a network namespace of its own (only a loopback interface, so
  DDS traffic cannot cross between runs nor leave the machine), its own process namespace,
  the system read-only and the run's folder writable. The grader's simulator runs in it
  (`grading.room`) and writes the record the run is judged from.
- the *student's* sandbox inside it (`student_command`): the room's network (the simulator is
  reachable on the loopback), a process namespace of its own (it cannot see nor signal the
  simulator), the system read-only with the submissions, the grader's output and the home
  folders hidden, and its private work folder the only writable place. Its processes join the
  run's control groups (`RunGroup`: tasks, memory, a share of a core) and carry resource
  limits (CPU seconds, file size, open files, no core dumps).

Once a room has started, its simulator runs on the real-time policy (`simulator_first`).
Nothing here starts a process: it makes the commands and the control groups.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import sys
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

CGROUP_ROOT = Path('/sys/fs/cgroup')
GROUP_PREFIX = 'turtle_traj_grading-'  # a run's control groups: this, then its name
HIDDEN = ('/root', '/home')  # empty and read-only, besides the grader's own folders
SCRATCH = ('/tmp', '/var/tmp', '/dev/shm', '/run')  # empty and the run's own
ROOM_NICE = -10  # the room's simulator steps in real time: it goes first (when root)
ROOM_REAL_TIME_PRIORITY = 10  # then real-time, below the kernel's interrupt threads (50)
# The quota's period. The kernel hands a group's quota to a core a slice at a time
# (`sched_cfs_bandwidth_slice_us`, 5 ms), and a process's nice counts only on its own core: a
# flood on one core draws slices the student's node on the other then waits for. A quarter of
# 80 ms holds four slices; two (a quarter of 40 ms) are too few: the flooding sample's node
# stalls mid-side beside a busy suite
_CPU_PERIOD_US = 80_000
# A run's weight against the machine's other work, within its quota: the kernel's weight for
# nice -10, what our own control programs run at (`rosutils.priority.NICE`): at an ordinary
# process's 1024, beside a test suite's nice -10 programs, an open-loop sample's timed sides
# run long
RUN_CPU_WEIGHT = 9548
_REMOVE_S = 10.0
ROOM_GROUPS = Path('/tmp/run-groups')  # where the room sees the student's control groups


class SandboxUnavailable(RuntimeError):
    """This machine cannot isolate a run: the message says what is missing."""


@dataclass(frozen=True)
class RunLimits:
    """What a student's run may use."""

    wall_s: float = 60.0  # from the student's start to its end
    cpu_s: int = 60  # of CPU time, each process
    memory_mb: int = 1024  # all its processes together
    tasks: int = 256  # processes and threads together (a ROS node has about 20 threads)
    file_mb: int = 16  # the largest file it may write (its log included)
    open_files: int = 256
    cpu_share: float = 0.25  # of a core, all its processes together (a ROS node takes ~0.05)


def bubblewrap() -> str:
    """bubblewrap's path.

    :raises SandboxUnavailable: it is not installed.
    """
    path = shutil.which('bwrap')
    if path is None:
        raise SandboxUnavailable('bubblewrap (bwrap) is not installed: `apt-get install '
                                 'bubblewrap` (Debian, Ubuntu)')
    return path


def room_command(python: str, spec: Path, run_dir: Path, groups: RunGroup | None,
                 live_view: Path | None = None) -> list[str]:
    """The room's command: `python -m turtle_traj.grading.room spec` in a network and process
    namespace of its own, with none of the grader's environment (its DDS settings are the
    room's own), the system read-only, `run_dir` (and the folder of the `live_view` socket)
    writable, the run's control groups at `ROOM_GROUPS/<controller>`."""
    command = [bubblewrap(), '--unshare-net', '--unshare-pid', '--unshare-ipc',
               '--unshare-uts', '--die-with-parent', '--new-session', '--clearenv',
               '--setenv', 'PATH', os.environ.get('PATH', '/usr/bin:/bin'),
               '--setenv', 'HOME', str(run_dir), '--setenv', 'LANG', 'C.UTF-8',
               '--ro-bind', '/', '/', '--dev', '/dev', '--proc', '/proc', '--tmpfs', '/tmp',
               '--bind', str(run_dir), str(run_dir)]
    for folder in _grader_folders(with_package=True):  # where the room's /tmp hid them
        if folder.is_relative_to('/tmp'):
            command += ['--ro-bind', str(folder), str(folder)]
    if live_view is not None:  # the folder of the live view's socket
        command += ['--bind', str(live_view.parent), str(live_view.parent)]
    for controller, path in (groups.paths.items() if groups else ()):
        command += ['--bind', str(path), str(ROOM_GROUPS / controller)]
    command += ['--', python, '-m', 'turtle_traj.grading.room', str(spec)]
    if os.geteuid() == 0:  # the simulator ahead of the students' programs and other work
        return ['nice', '-n', str(ROOM_NICE), *command]
    return command


def student_command(argv: Sequence[str], work: Path, hidden: Iterable[Path],
                    environment: dict[str, str], limits: RunLimits, *,
                    network: bool = True, grouped: bool = False) -> list[str]:
    """The student's command `argv`, run in `work` (its only writable folder) with nothing
    but `environment`, `hidden` folders (and the home folders, /tmp, /run) empty, in a
    process namespace of its own; without `network`, in a network namespace of its own too
    (a build). With `grouped`, it first joins the control groups the room sees at
    `ROOM_GROUPS`."""
    command = [bubblewrap(), '--unshare-pid', '--unshare-ipc', '--unshare-uts',
               '--unshare-cgroup-try', '--die-with-parent', '--new-session', '--clearenv',
               '--ro-bind', '/', '/', '--dev', '/dev', '--proc', '/proc']
    if not network:
        command.append('--unshare-net')
    hidden_folders = [Path(folder) for folder in (*SCRATCH, *HIDDEN, *hidden)
                      if Path(folder).exists()]
    for folder in hidden_folders:
        command += ['--tmpfs', str(folder)]
    for folder in _grader_folders():  # the Python the student runs with, where it was hidden
        if any(folder.is_relative_to(hidden_folder) for hidden_folder in hidden_folders):
            command += ['--ro-bind', str(folder), str(folder)]
    command += ['--bind', str(work), str(work), '--chdir', str(work)]
    for folder in hidden_folders:  # empty and read-only, but for what is bound in them
        if str(folder) not in SCRATCH:
            command += ['--remount-ro', str(folder)]
    for name, value in sorted(environment.items()):
        command += ['--setenv', name, value]
    command += ['--', 'prlimit', f'--cpu={limits.cpu_s}', f'--fsize={limits.file_mb << 20}',
                f'--nofile={limits.open_files}', '--core=0']
    if not grouped:  # the tasks limit without a control group: per user, the best there is
        command.append(f'--nproc={limits.tasks}')
    # back to the grader's own priority from the room's
    command += ['--', 'nice', '-n', str(-ROOM_NICE if os.geteuid() == 0 else 0), *argv]
    if not grouped:
        return command
    joins = ' && '.join(f'echo 0 > {ROOM_GROUPS / controller}/cgroup.procs'
                        for controller in RunGroup.CONTROLLERS)
    return ['sh', '-c', f'{joins} && exec "$@"', 'join', *command]


class RunGroup:
    """A run's control groups (cgroup v1's pids, memory and cpu controllers): how many tasks,
    how much memory and how much CPU the student's processes have together. Made by the
    grader, which must be root; `remove` kills whatever is left in them."""

    CONTROLLERS = ('pids', 'memory', 'cpu')

    def __init__(self, name: str, limits: RunLimits) -> None:
        # At the top of each hierarchy: each run has a weight of its own (`RUN_CPU_WEIGHT`)
        # and its own quota. Under one parent, all runs share one weight (a square's turn can
        # last 1.76 s instead of 1 s beside a busy test suite); a parent weighing 64 processes
        # makes the machine's other programs wait up to 0.38 s beside two classes graded at once.
        self.paths = {controller: CGROUP_ROOT / controller / f'{GROUP_PREFIX}{name}'
                      for controller in self.CONTROLLERS}
        try:
            for path in self.paths.values():
                path.mkdir(exist_ok=True)
            (self.paths['pids'] / 'pids.max').write_text(str(limits.tasks))
            (self.paths['memory'] / 'memory.limit_in_bytes').write_text(
                str(limits.memory_mb << 20))
            # a share of a core: a fork bomb's hundreds of processes, or a flood, cannot take
            # the CPU that the simulators and the other runs need (two hogs of a core each cost
            # other simulators 15-21 steps)
            (self.paths['cpu'] / 'cpu.shares').write_text(str(RUN_CPU_WEIGHT))
            (self.paths['cpu'] / 'cpu.cfs_period_us').write_text(str(_CPU_PERIOD_US))
            (self.paths['cpu'] / 'cpu.cfs_quota_us').write_text(
                str(round(limits.cpu_share * _CPU_PERIOD_US)))
        except OSError as error:
            self.remove()
            raise SandboxUnavailable(f'cannot make a control group ({error})') from None

    @classmethod
    def available(cls) -> bool:
        """Whether cgroup v1's pids, memory and cpu controllers can be written here."""
        return all(os.access(CGROUP_ROOT / controller, os.W_OK)
                   for controller in cls.CONTROLLERS)

    def peak(self) -> dict[str, float]:
        """The most tasks and memory (MB) the student's processes took at once."""
        values = {}
        with contextlib.suppress(OSError, ValueError):
            values['tasks'] = int((self.paths['pids'] / 'pids.peak').read_text())
        with contextlib.suppress(OSError, ValueError):
            values['memory_mb'] = int(
                (self.paths['memory'] / 'memory.max_usage_in_bytes').read_text()) / 2**20
        return values

    def hit_tasks_limit(self) -> bool:
        """Whether a fork or a thread was refused for the tasks limit."""
        with contextlib.suppress(OSError, ValueError, IndexError):
            return int((self.paths['pids'] / 'pids.events').read_text().split()[1]) > 0
        return False

    def remove(self) -> None:
        """Kill the processes left in the groups (none may fork any more first), then remove
        the groups. A group still busy after `_REMOVE_S` is left behind."""
        with contextlib.suppress(OSError):
            (self.paths['pids'] / 'pids.max').write_text('0')
        deadline = time.monotonic() + _REMOVE_S
        for path in self.paths.values():
            while path.exists() and time.monotonic() < deadline:
                for pid in _members(path):
                    with contextlib.suppress(ProcessLookupError):
                        os.kill(pid, signal.SIGKILL)
                try:
                    path.rmdir()
                except FileNotFoundError:
                    break
                except OSError:  # busy: its processes are still dying
                    time.sleep(0.02)


def simulator_first(root_pid: int) -> bool:
    """Put the room's simulator (the `grading.room` process under `root_pid`) on the
    real-time FIFO policy, every thread of it, once its student has started (whose processes
    it does not touch). At nice -10 among ordinary processes, a simulator beside two busy loops
    and a test suite lost up to 84 of its steps in a run, and the turtle moved less than it was
    told to. False where not permitted (not root) or not found."""
    for pid in _descendants(root_pid):
        try:
            arguments = Path(f'/proc/{pid}/cmdline').read_bytes().split(b'\0')
            if arguments[1:3] != [b'-m', b'turtle_traj.grading.room']:  # not bubblewrap's
                continue
            for thread in os.listdir(f'/proc/{pid}/task'):
                os.sched_setscheduler(int(thread), os.SCHED_FIFO,
                                      os.sched_param(ROOM_REAL_TIME_PRIORITY))
        except OSError:
            return False
        return True
    return False


def _descendants(pid: int) -> list[int]:
    """The processes under `pid`, nearest first (from every process's parent in /proc)."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir('/proc'):
        if entry.isdigit():
            with contextlib.suppress(OSError, ValueError, IndexError):
                stat = Path(f'/proc/{entry}/stat').read_text()
                parent = int(stat[stat.rindex(')') + 2:].split()[1])  # after the name
                children.setdefault(parent, []).append(int(entry))
    found, queue = [], list(children.get(pid, []))
    while queue:
        child = queue.pop(0)
        found.append(child)
        queue += children.get(child, [])
    return found


def _grader_folders(*, with_package: bool = False) -> list[Path]:
    """The folders the grader's Python lives in (the virtual environment and its base) and,
    `with_package`, our package's (an editable install's source: the room's, never a
    student's, whose view would hold the labs' sample solutions)."""
    folders = {Path(sys.prefix).resolve(), Path(sys.base_prefix).resolve()}
    if with_package:
        folders.add(Path(__file__).resolve().parents[1])
    return sorted(folders)


def _members(path: Path) -> list[int]:
    with contextlib.suppress(OSError):
        return [int(pid) for pid in (path / 'cgroup.procs').read_text().split()]
    return []

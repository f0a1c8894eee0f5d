"""A student's submission made ready to run: copied into the run's private work folder and, for a
package, built there with colcon (in a sandbox of its own, without network), its entry point
then run as `ros2 run` runs it: `install/<package>/lib/<package>/<executable>` with the
install's Python path.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from turtle_traj.core.grading.task import Task
from turtle_traj.grading.sandbox import RunLimits, student_command

BUILD_LIMITS = RunLimits(wall_s=180.0, cpu_s=120, memory_mb=2048)
MAX_SUBMISSION_MB = 50
_BUILT = frozenset({'build', 'install', 'log', '__pycache__', '.git'})
_PYTHON_DIR = f'python{sys.version_info.major}.{sys.version_info.minor}'


class NotReady(Exception):
    """The submission cannot run: the message says why, for the student."""


@dataclass(frozen=True)
class PreparedSubmission:
    """How to run a prepared submission."""

    argv: list[str]
    environment: dict[str, str] = field(default_factory=dict)
    build_log: str = ''


def base_environment(work: Path, domain_id: int) -> dict[str, str]:
    """What every student process gets: the grader's Python first on PATH, a home in its work
    folder, its ROS domain kept to its room's loopback."""
    prefix = Path(sys.prefix)
    return {'PATH': f'{prefix / "bin"}:/usr/local/bin:/usr/bin:/bin', 'HOME': str(work),
            'ROS_DOMAIN_ID': str(domain_id), 'ROS_AUTOMATIC_DISCOVERY_RANGE': 'LOCALHOST',
            'AMENT_PREFIX_PATH': str(prefix), 'PYTHONUNBUFFERED': '1', 'LANG': 'C.UTF-8'}


def copy_submission(source: Path, work: Path) -> None:
    """Copy the submission's files, at most `MAX_SUBMISSION_MB`, leaving out its symbolic
    links (the grader reads the copy, and a link could point at another student's files) and
    what a build leaves.

    :raises NotReady: it is too large.
    """
    size = sum(path.stat().st_size for path in source.rglob('*')
               if path.is_file() and not path.is_symlink())
    if size > MAX_SUBMISSION_MB << 20:
        raise NotReady(f'the submission holds {size / 2**20:.0f} MB; at most '
                       f'{MAX_SUBMISSION_MB} MB are taken')
    def left_out(folder: str, names: list[str]) -> set[str]:
        return {name for name in names if name in _BUILT or Path(folder, name).is_symlink()}

    shutil.copytree(source, work, ignore=left_out)


def prepare(task: Task, work: Path, hidden: Iterable[Path], domain_id: int) -> PreparedSubmission:
    """The command that runs the submission copied into `work`: the task's entry point where a
    package.xml names its package (built first), else its script.

    :raises NotReady: neither is there, or the build failed.
    """
    environment = base_environment(work, domain_id)
    package, _, executable = task.entry_point.partition('/')
    if not (package and any(_package_name(path) == package
                            for path in work.rglob('package.xml'))):
        script = (work / task.script).resolve() if task.script else None
        if script is None or not script.is_relative_to(work.resolve()) or not script.is_file():
            raise NotReady(f'the submission has {_wanted(task)}')
        return PreparedSubmission([sys.executable, str(script), *task.args], environment)
    log = _build(work, package, hidden, environment)
    install = work / 'install' / package
    entry = install / 'lib' / package / executable
    if not entry.is_file():
        raise NotReady(f'{package} built, but installs no executable {executable} '
                       f'(lib/{package}/ has: {_listing(entry.parent)})')
    site = install / 'lib' / _PYTHON_DIR / 'site-packages'
    environment |= {'PYTHONPATH': str(site),
                    'AMENT_PREFIX_PATH': f'{install}:{environment["AMENT_PREFIX_PATH"]}'}
    return PreparedSubmission([str(entry), *task.args], environment, log)


def _build(work: Path, package: str, hidden: Iterable[Path], environment: dict[str, str]) -> str:
    colcon = shutil.which('colcon', path=str(Path(sys.prefix) / 'bin'))
    if colcon is None:
        raise NotReady('the grader has no colcon to build packages with')
    build_environment = environment | {'CMAKE_PREFIX_PATH': str(sys.prefix)}
    folder = next(path.parent for path in work.rglob('package.xml')
                  if _package_name(path) == package)
    command = student_command(
        [colcon, '--log-base', 'log', 'build', '--base-paths', str(folder),
         '--event-handlers', 'console_direct+', '--cmake-args', '-DBUILD_TESTING=OFF'],
        work, hidden, build_environment, BUILD_LIMITS, network=False)
    try:
        built = subprocess.run(command, capture_output=True, text=True, errors='replace',
                               timeout=BUILD_LIMITS.wall_s, start_new_session=True)
    except subprocess.TimeoutExpired:
        raise NotReady(f'the build took longer than {BUILD_LIMITS.wall_s:.0f} s') from None
    log = (built.stdout + built.stderr)[-4000:]
    if built.returncode != 0:
        raise NotReady(f'the package did not build:\n{_tail(log, 12)}')
    return log


def _wanted(task: Task) -> str:
    wanted = [f"no package named {task.entry_point.split('/')[0]} (no package.xml names it)"
              if task.entry_point else '', f'no {task.script}' if task.script else '']
    return ' and '.join(filter(None, wanted))


def _package_name(path: Path) -> str:
    text = path.read_text(errors='replace')
    start = text.find('<name>')
    return text[start + 6:text.find('</name>', start)].strip() if start >= 0 else ''


def _listing(folder: Path) -> str:
    names = sorted(os.listdir(folder)) if folder.is_dir() else []
    return ', '.join(names) or 'nothing'


def _tail(text: str, lines: int) -> str:
    return '\n'.join(text.strip().splitlines()[-lines:])

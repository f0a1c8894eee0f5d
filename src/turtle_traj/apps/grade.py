"""`turtle-traj grade TASK SUBMISSIONS`: grade a class's submissions against a task file, and
write the class page, the spreadsheet, the summary and each student's picture and results.
`turtle-traj lab NAME DIR`: copy a ready-made lab (its task file and sample submissions)."""

from __future__ import annotations

import shutil
import sys
from importlib import resources
from pathlib import Path

import yaml

from turtle_traj.core.grading.task import Task, TaskError, read_task
from turtle_traj.grading.grader import StudentResult, grade_class, watch_one
from turtle_traj.grading.reports import exit_status, write_reports
from turtle_traj.grading.sandbox import SandboxUnavailable

USAGE_ERROR = 2


def load_task(path: Path) -> Task:
    """The task a YAML task file describes.

    :raises TaskError: the file cannot be read, or a field is wrong (named).
    """
    try:
        return read_task(yaml.safe_load(path.read_text(encoding='utf-8')))
    except OSError as error:
        raise TaskError(f'{path}: {error.strerror}') from None
    except yaml.YAMLError as error:
        raise TaskError(f'{path} is not YAML: {error}') from None


def run(task_file: Path, submissions: Path, out: Path, jobs: int | None = None,
        watch: str | None = None, port: int = 0) -> int:
    """Grade and report (with `watch`, that submission alone, its live view served on
    `port`); the exit status is 0 when every submission got full marks, 1 when one lost
    points, 2 when the task or the folders cannot be used."""
    try:
        task = load_task(task_file)
    except TaskError as error:
        print(f'grade: {error}', file=sys.stderr)
        return USAGE_ERROR
    if not submissions.is_dir():
        print(f'grade: {submissions} is not a folder of submissions', file=sys.stderr)
        return USAGE_ERROR

    def say(result: StudentResult) -> None:
        print(f'graded {result.name} in {result.seconds:.1f} s', flush=True)

    def show(url: str) -> None:
        print(f'live view of {watch}: {url} (watch only)', flush=True)

    try:
        if watch is not None:
            results = [watch_one(task, submissions, out, watch, port, show)]
            say(results[0])
        else:
            results = grade_class(task, submissions, out, jobs=jobs, on_result=say)
    except SandboxUnavailable as error:
        print(f'grade: cannot isolate the runs: {error}', file=sys.stderr)
        return USAGE_ERROR
    except (ValueError, OSError) as error:  # no such submission; the port is taken
        print(f'grade: {error}', file=sys.stderr)
        return USAGE_ERROR
    page = write_reports(task, results, out)
    width = max((len(result.name) for result in results), default=0)
    for result in results:
        print(f'{result.name:<{width}}  {result.score:>4g} / {result.max_score:g}  '
              f'{result.ended.splitlines()[0]}')
    print(f'{len(results)} graded: {out / page.name}')  # the folder as the user named it
    return exit_status(results)


def labs() -> list[str]:
    """The ready-made labs' names."""
    return sorted(entry.name for entry in resources.files('turtle_traj').joinpath('labs')
                  .iterdir() if entry.is_dir() and not entry.name.startswith('_'))


def copy_lab(name: str, folder: Path) -> int:
    """Copy lab `name` (task.yaml, samples/) into `folder`."""
    if name not in labs():
        print(f"lab: no lab {name!r}: choose from {', '.join(labs())}", file=sys.stderr)
        return USAGE_ERROR
    if folder.exists() and any(folder.iterdir()):
        print(f'lab: {folder} is not empty', file=sys.stderr)
        return USAGE_ERROR
    with resources.as_file(resources.files('turtle_traj').joinpath('labs', name)) as source:
        shutil.copytree(source, folder, dirs_exist_ok=True,
                        ignore=shutil.ignore_patterns('__pycache__'))
    print(f'{folder}/task.yaml and {len(list((folder / "samples").iterdir())) - 1} sample '
          f'submissions in {folder}/samples')
    return 0

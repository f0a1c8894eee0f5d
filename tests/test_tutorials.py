"""The tutorials run as written, each in a folder of its own.

In page order: a Python or YAML block whose first line is `# file: NAME` is saved as NAME;
any other Python block runs as a script; each `$ ` line of a console block runs as a shell
user would type it (`turtle-traj` and `python` from this venv), a command ending in `&` in the
background (waited for until it says it serves, and ended after the page). The lines shown
under a command are its expected output: each must match a line it printed, in order, `...`
standing for any text. A command shown without output must succeed.
"""

import os
import re
import shlex
import signal
import subprocess
import sys
from pathlib import Path

import pytest

TUTORIALS = Path(__file__).resolve().parents[1] / 'docs' / 'tutorials'
# Pages whose recipe a test of its own runs: two network namespaces need root and nftables.
RUN_ELSEWHERE = {'two-machines.md': 'tests/test_two_hosts.py'}
BLOCK = re.compile(r'```(\w+)\n(.*?)```', re.S)


def tutorial_steps(page: Path) -> list[tuple[str, str, list[str]]]:
    """('file', name, [text]) | ('python', '', [text]) | ('command', line, expected lines)."""
    steps = []
    for language, text in BLOCK.findall(page.read_text()):
        if language in ('python', 'yaml'):
            first, _, rest = text.partition('\n')
            named = re.fullmatch(r'# file: (\S+)', first)
            if named:
                steps.append(('file', named[1], [rest]))
            elif language == 'python':
                steps.append(('python', '', [text]))
        elif language == 'console':
            for line in text.splitlines():
                if line.startswith('$ '):
                    steps.append(('command', line[2:], []))
                elif line.strip():
                    steps[-1][2].append(line)
    return steps


def _matches(expected: list[str], printed: str) -> str | None:
    """The first expected line not printed (in order), or None."""
    lines, at = printed.splitlines(), 0
    for want in expected:
        pattern = re.compile('.*'.join(map(re.escape, want.strip().split('...'))))
        while at < len(lines) and not pattern.fullmatch(lines[at].strip()):
            at += 1
        if at == len(lines):
            return want
        at += 1
    return None


def _argv(command: str) -> list[str]:
    words = shlex.split(command)
    return [sys.executable, *words[1:]] if words[0] == 'python' else words


def run_page(page: Path, folder: Path) -> None:
    environment = {**os.environ, 'PATH': f"{Path(sys.executable).parent}:{os.environ['PATH']}"}
    background: list[subprocess.Popen] = []
    try:
        for kind, name, content in tutorial_steps(page):
            if kind == 'file':
                (folder / name).write_text(content[0])
                continue
            if kind == 'python':
                argv, expected, shown = [sys.executable, '-c', content[0]], [], 'a Python block'
            elif name.endswith('&'):
                background.append(_started(_argv(name[:-1]), folder, environment))
                continue
            else:
                argv, expected, shown = _argv(name), content, name
            done = subprocess.run(argv, cwd=folder, env=environment, capture_output=True,
                                  text=True, timeout=300)
            printed = done.stdout + done.stderr
            if not expected:
                assert done.returncode == 0, f'{shown} failed:\n{printed}'
            missing = _matches(expected, printed)
            assert missing is None, f'{shown}: no line like {missing!r} in\n{printed}'
    except AssertionError as failure:  # what the programs left running said, and whether
        raise AssertionError(f'{failure}{_stopped(background)}') from None  # they still ran
    finally:
        _stopped(background)


def _stopped(background: list[subprocess.Popen]) -> str:
    """Stop the programs left running (once); what each said, and how it had ended if it had."""
    said = ''
    for process in background:
        ended = process.poll()
        if ended is None:
            os.killpg(process.pid, signal.SIGINT)
        output, _ = process.communicate(timeout=30)
        state = 'still running' if ended is None else f'had ended with {ended}'
        said += f'\n--- {process.args} ({state}) said:\n{output}'
    background.clear()
    return said


def _started(argv: list[str], folder: Path, environment: dict) -> subprocess.Popen:
    """A program left running, once it says it serves (its log line) or ends."""
    process = subprocess.Popen(argv, cwd=folder, env=environment, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, start_new_session=True)
    heard = ''
    while 'serving' not in heard and process.poll() is None:
        heard += process.stdout.readline()
    assert process.poll() is None, f'{argv} ended:\n{heard}{process.stdout.read()}'
    return process


PAGES = sorted(page.name for page in TUTORIALS.glob('*.md') if page.name != 'index.md')


@pytest.mark.system
@pytest.mark.parametrize('name', PAGES)
def test_the_tutorial_runs_as_written(name, tmp_path):
    if name in RUN_ELSEWHERE:
        assert Path(__file__).parent.joinpath(Path(RUN_ELSEWHERE[name]).name).exists()
        pytest.skip(f'its recipe runs in {RUN_ELSEWHERE[name]} (network namespaces)')
    run_page(TUTORIALS / name, tmp_path)


def test_the_tutorials_have_something_to_run():
    for name in PAGES:
        if name not in RUN_ELSEWHERE:
            kinds = {kind for kind, _name, _content in tutorial_steps(TUTORIALS / name)}
            assert 'command' in kinds or 'python' in kinds, name


def test_expected_output_is_matched_in_order_with_ellipses():
    printed = 'done: square done\n  elapsed 10.61 s, path 8.00 m\n'
    assert _matches(['done: square done', 'elapsed ... s, path 8.00 m'], printed) is None
    assert _matches(['elapsed ... m', 'done: square done'], printed) == 'done: square done'
    assert _matches(['path 9.00 m'], printed) == 'path 9.00 m'


def test_the_two_machine_page_shows_the_programs_its_test_runs():
    """tests/test_two_hosts.py starts these programs on its two hosts; the page must show the
    same ones, on the same machines."""
    (recipe, *_rest) = re.findall(r'```bash\n(.*?)```', (TUTORIALS / 'two-machines.md')
                                  .read_text(), re.S)
    lines = [line.split('#') for line in recipe.splitlines()]
    shown = {command.strip().split('/')[-1]: where.strip() for command, where in lines}
    assert shown == {'export ROS_DOMAIN_ID=42': 'on both machines',
                     'python -m turtle_traj.sim': 'machine A',
                     'python -m turtle_traj': 'machine B',
                     'turtle-traj draw square': 'machine B (or any machine of the domain)'}
    test = (Path(__file__).parent / 'test_two_hosts.py').read_text()
    assert "made.run('a', 'turtle_traj.sim'" in test and "made.run('b', 'turtle_traj'" in test
    assert "self.call(*args" in test and "('draw', 'square'" in test

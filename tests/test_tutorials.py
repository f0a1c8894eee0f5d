"""The tutorials run as written: each page's Python block is saved as the file it names, and
its `$ ` commands run in that folder (a command ending in `&` in the background, ended after
the page's last command), each checked for what the page says it does."""

import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import pytest

TUTORIALS = Path(__file__).resolve().parents[1] / 'docs' / 'tutorials'


def _blocks(page: Path, language: str) -> list[str]:
    return re.findall(rf'```{language}\n(.*?)```', page.read_text(), re.S)


def _commands(page: Path) -> list[str]:
    return [line[2:] for block in _blocks(page, 'console') for line in block.splitlines()
            if line.startswith('$ ')]


def _environment(folder: Path) -> dict[str, str]:
    bin_dir = str(Path(sys.executable).parent)  # turtle-traj, as a user's venv has it
    return {**os.environ, 'PATH': f"{bin_dir}:{os.environ['PATH']}", 'PWD': str(folder)}


@pytest.mark.system
def test_write_a_controller_runs_as_written(tmp_path):
    page = TUTORIALS / 'write-a-controller.md'
    (controller,) = _blocks(page, 'python')
    (tmp_path / 'my_controller.py').write_text(controller)
    up, draw, score = _commands(page)
    assert up.endswith(' &') and draw.startswith('turtle-traj draw')
    environment = _environment(tmp_path)
    background = subprocess.Popen(up[:-2].split(), cwd=tmp_path, env=environment,
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                  start_new_session=True)
    try:
        heard = ''  # as a user does, wait for the node to say it serves
        while 'serving' not in heard and background.poll() is None:
            heard += background.stdout.readline()
        drawn = subprocess.run(draw.split(), cwd=tmp_path, env=environment,
                               capture_output=True, text=True, timeout=120)
    finally:
        os.killpg(background.pid, signal.SIGINT)
        log = heard + background.communicate(timeout=30)[0]
    assert drawn.returncode == 0, drawn.stdout + drawn.stderr + log
    # the node drove it with the tutorial's controller, which the reply names
    assert 'square done (my_controller:WaypointP: ' in drawn.stdout + log
    scored = subprocess.run(score.split(), cwd=tmp_path, env=environment, capture_output=True,
                            text=True, timeout=300)
    assert scored.returncode == 0, scored.stdout + scored.stderr
    ranking = scored.stdout.split('rank controller')[1]
    assert re.search(r'my_controller:WaypointP +3 of 3', ranking) and 'dwpp' in ranking

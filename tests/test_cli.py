"""`turtle-traj` against a running simulator and node (one subprocess), and without one.

The menu and Ctrl-C on a terminal are in test_terminal.py.
"""

import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

from turtle_traj.cli import main as cli
from turtle_traj.client.traj_client import TrajClient, seen_in_graph
from turtle_traj.testing.processes import program_nice

pytestmark = pytest.mark.system  # starts programs: `make check` leaves it out


@pytest.mark.parametrize(('argv', 'trajectory', 'fields'), [
    (['draw', 'polygon', '--sides', '5', '--size', '1.5', '--clockwise'], 'polygon',
     dict(sides=5, size=1.5, clockwise=True)),
    (['draw', 'circle', '--size', '2'], 'circle', dict(size=2.0, turns=1.0, forever=False)),
    (['draw', 'circle', '--forever'], 'circle', dict(turns=0.0, forever=True)),
    (['go-to', '8', '2', '--theta', '90'], 'go_to',
     dict(x=8.0, y=2.0, use_theta=True, theta=math.pi / 2)),
    (['move', '2', '--backward'], 'move', dict(distance=-2.0)),
    (['rotate', '90', '--clockwise'], 'rotate', dict(angle=-math.pi / 2)),
    (['follow-path', '2,3', '4,5', '--closed'], 'follow_path', dict(closed=True)),
    (['write', 'Hello ROS', '--height', '1', '--pen-color', 'red', '--pen-width', '5'], 'text',
     dict(text='Hello ROS', height=1.0, pen_color='red', pen_width=5)),
    (['draw', 'svg', 'turtle.svg', '--size', '6'], 'svg', dict(file='turtle.svg', size=6.0)),
    (['draw', 'svg', '--d', 'M 0 0 L 1 1'], 'svg', dict(path_data='M 0 0 L 1 1', file='')),
    (['draw', 'star', '--tips', '6', '--size', '1'], 'star', dict(tips=6, size=1.0)),
    (['draw', 'rose', '--petals', '8'], 'rose', dict(petals=8)),
    (['draw', 'lissajous'], 'lissajous', dict(a=3, b=2, phase=math.pi / 2)),
    (['stop'], None, None),
])
def test_arguments_become_goals(argv, trajectory, fields):
    goal = cli.to_goal(cli.build_parser().parse_args(argv))
    if trajectory is None:
        assert goal is None
        return
    assert goal.trajectory == trajectory
    for field, value in fields.items():
        if isinstance(value, str):
            assert getattr(goal, field) == value
        else:
            assert getattr(goal, field) == pytest.approx(value)


def test_bad_arguments_exit_with_usage(capsys):
    with pytest.raises(SystemExit) as exited:
        cli.main(['draw', 'blob'])
    assert exited.value.code == 2
    assert "invalid choice: 'blob'" in capsys.readouterr().err


def test_output_into_a_pipe_closed_early_ends_quietly(running_system):
    process = subprocess.Popen([sys.executable, '-m', 'turtle_traj.cli', 'params'],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    process.stdout.close()  # the reader leaves before anything is written, as `| head` may
    stderr = process.stderr.read().decode()
    assert process.wait(timeout=30) == 141
    assert stderr == ''


def test_no_node_answers_within_seconds(capsys):
    assert cli.main(['--node', '/nobody_here', '--wait', '1', 'draw', 'square']) == 2
    assert 'no trajectory node answers on /nobody_here/draw ' in capsys.readouterr().err


def test_draw_and_refusal_against_a_running_system(running_system, capsys):
    assert cli.main(['draw', 'square', '--size', '1']) == 0
    out = capsys.readouterr().out
    assert out.startswith('done: square done')
    assert 'final pose  x=5.54' in out
    assert cli.main(['draw', 'square', '--size', '9']) == 1
    assert 'the largest that fits from here' in capsys.readouterr().err
    assert cli.main(['reset']) == 0
    assert 'simulator reset' in capsys.readouterr().out
    assert cli.main(['write', 'I', '--height', '0.3']) == 0
    out = capsys.readouterr().out
    assert out.startswith('done: text done') and 'pen up 0.' in out
    assert cli.main(['write', 'Grüße']) == 1
    assert "no glyph for 'ß', 'ü'" in capsys.readouterr().err
    assert cli.main(['reset']) == 0


def _readme_python_example() -> str:
    readme = (Path(__file__).resolve().parents[1] / 'README.md').read_text()
    return readme.split('### From Python\n\n```python\n', 1)[1].split('```', 1)[0]


def test_the_readmes_python_example_runs_as_written(running_system):
    assert cli.main(['reset']) == 0
    ran = subprocess.run([sys.executable, '-c', _readme_python_example()], capture_output=True,
                         text=True, timeout=120)
    assert ran.returncode == 0, ran.stderr
    assert ran.stdout.startswith('True square done ')


def test_the_readmes_python_example_says_when_no_node_runs():
    script = _readme_python_example().replace('/turtle_traj/', '/nobody_here/').replace(
        'timeout_sec=5.0', 'timeout_sec=1.0')  # the same code, a shorter wait
    ran = subprocess.run([sys.executable, '-c', script], capture_output=True, text=True,
                         timeout=60)
    assert ran.returncode == 1
    assert ran.stderr.strip() == ('no /nobody_here/draw_square: is the node running (and '
                                  'ROS_DOMAIN_ID right)?')


# Discovery of the node's parameter services can take seconds on a loaded machine; these tests
# are about what the answers say.
WAIT = ['--wait', '30']


def test_params_reads_one_converts_to_the_declared_type_and_names_unknown_ones(
        running_system, capsys):
    assert cli.main([*WAIT, 'params']) == 0
    shown = capsys.readouterr().out
    assert 'linear_speed: 1.0' in shown and 'turtle_name: turtle1' in shown
    assert cli.main([*WAIT, 'params', 'linear_speed', '2']) == 0  # an integer literal, to a double
    assert cli.main([*WAIT, 'params', 'linear_speed']) == 0
    assert capsys.readouterr().out.endswith('linear_speed: 2.0\n')
    assert cli.main([*WAIT, 'params', 'position_tolerance', '1e-3']) == 0  # a number, not a string
    assert cli.main([*WAIT, 'params', 'linear_speed', '100']) == 1
    assert 'out of range' in capsys.readouterr().err  # the range message shows
    assert cli.main([*WAIT, 'params', 'linear_speed', 'fast']) == 1
    assert "linear_speed: expects a number, got 'fast'" in capsys.readouterr().err
    assert cli.main([*WAIT, 'params', 'blob', '3']) == 2
    assert 'has no parameter blob; it has: angular_deceleration' in capsys.readouterr().err
    assert cli.main([*WAIT, 'params', 'arena_max_x', '5.0']) == 1  # the turtle stands at x = 5.54
    assert 'outside the room this arena leaves' in capsys.readouterr().err
    with TrajClient() as client:
        assert client.parameters(['position_tolerance']) == {'position_tolerance': 0.001}
        for name, value in [('linear_speed', '1.0'), ('position_tolerance', '0.0005')]:
            assert client.set_parameter(name, value) is None


def test_no_progress_line_without_a_terminal(running_system, capsys):
    assert cli.main(['reset']) == 0
    capsys.readouterr()
    assert cli.main(['rotate', '90', '--timeout', '60']) == 0  # options after the command too
    captured = capsys.readouterr()
    assert captured.err == '' and '\r' not in captured.out
    assert captured.out.startswith('done: rotate done')
    assert 'heading error' in captured.out


def test_beside_a_simulator_the_node_runs_as_started(running_system):
    # `turtle_traj.rosutils.priority`: with a simulator in the process (its steps share the
    # node's thread; a time-scaled one takes what CPU it gets) the priority is left as started
    assert program_nice(running_system.pid) == {os.getpriority(os.PRIO_PROCESS, 0)}
    assert 'scheduling priority' not in running_system.said()


def test_a_session_answers_each_call_as_a_process_of_its_own_would(running_system):
    """`python -m turtle_traj.cli.session` (the two-host tests' calls): the same exit code and
    the same words, for an answer, a refusal and a usage error."""
    from turtle_traj.testing.two_hosts import CliSession
    session = CliSession.start()
    try:
        for args in ([*WAIT, 'params', 'turtle_name'], [*WAIT, 'params', 'blob', '3'],
                     ['draw', 'blob']):
            alone = subprocess.run([sys.executable, '-m', 'turtle_traj.cli', *args],
                                   capture_output=True, text=True, timeout=60)
            within = session.call(*args, timeout_s=60)
            assert (within.returncode, within.stdout, within.stderr) == (
                alone.returncode, alone.stdout, alone.stderr), args
        assert within.returncode == 2 and "invalid choice: 'blob'" in within.stderr
    finally:
        session.process.stdin.close()
        assert session.process.wait(timeout=30) == 0  # it ends with its input


class _Graph:
    """The ROS graph as a client's node sees it: nodes (name, namespace), and servers by node."""

    def __init__(self, nodes: list[tuple[str, str]], servers: dict | None = None) -> None:
        self.nodes, self.servers = nodes, servers or {}

    def get_name(self) -> str:
        return 'turtle_traj_cli_7_0'

    def get_node_names_and_namespaces(self) -> list[tuple[str, str]]:
        return [('turtle_traj_cli_7_0', '/'), *self.nodes]

    def get_service_names_and_types_by_node(self, name: str, namespace: str) -> list:
        return [(service, ['std_srvs/srv/Trigger'])
                for service in self.servers.get((name, namespace), [])]


@pytest.mark.parametrize(('graph', 'said'), [
    (_Graph([]), '; no other node seen'),
    (_Graph([('turtlesim', '/sim1'), ('turtle_traj', '/sim1')]),
     '; nodes seen: /sim1/turtle_traj, /sim1/turtlesim'),
    (_Graph([('turtle_traj', '/')], {('turtle_traj', '/'): ['/turtle_traj/stop']}),
     '; /turtle_traj is seen, without /turtle_traj/reset'),
    (_Graph([('turtle_traj', '/')], {('turtle_traj', '/'): ['/turtle_traj/reset']}),
     '; /turtle_traj is seen serving /turtle_traj/reset, but never matched this client'),
])
def test_a_node_not_found_is_told_with_what_the_client_sees(graph, said):
    assert seen_in_graph(graph, '/turtle_traj', '/turtle_traj/reset') == said

"""`turtle-traj menu` and Ctrl-C on a terminal, against a running simulator and node.

(A file of its own, so that the test workers share the slow command-line tests.)
"""

import math
import time

import pytest

from turtle_traj.cli import main as cli
from turtle_traj.client.traj_client import TrajClient
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M, WORLD_SIZE_M
from turtle_traj.testing.processes import Terminal

pytestmark = pytest.mark.system  # starts programs: `make check` leaves it out


def test_menu_reasks_bad_answers_runs_and_leaves_on_ctrl_d(running_system, monkeypatch,
                                                            capsys):
    import io

    answers = '\n'.join([
        'x',            # unknown choice
        '1',            # square
        'big', '-4', 'nan', '1',   # side length: letters, out of range, NaN, then 1 m
        'maybe', 'n',   # clockwise?
        '',             # speed: default
        'r',            # reset
    ]) + '\n'          # then end of input (Ctrl-D)
    monkeypatch.setattr('sys.stdin', io.StringIO(answers))
    assert cli.main(['menu']) == 0
    out = capsys.readouterr().out
    said = f'the menu said:\n{out}'
    assert "unknown choice 'x'" in out, said
    assert "'big' is not a number" in out, said
    # the range of a size ends at the largest that fits from the turtle's pose
    room = WORLD_SIZE_M - 0.3 - SPAWN_XY_M
    assert f'-4 is outside 0.01 to {math.floor(room * 100) / 100:g}' in out, said
    assert "'nan' is not a finite number" in out, said
    assert 'please answer y or n' in out, said
    assert 'done: square done' in out, said
    assert 'done: simulator reset; ready' in out, said
    assert out.rstrip().endswith('bye'), said


def test_ctrl_c_cancels_the_goal_and_the_turtle_stands(running_system):
    assert cli.main(['reset']) == 0
    terminal = Terminal('turtle_traj.cli', 'draw', 'circle', '--size', '1', '--forever')
    terminal.expect('circle lap [')  # the progress line, from the action's feedback
    terminal.send('\x03')
    assert terminal.finish() == 0  # a circle forever ends well when stopped
    assert 'cancelled (interrupted): circle stopped by request' in terminal.output
    assert 'Traceback' not in terminal.output
    with TrajClient() as client:
        assert _standing(client)
        assert client.call('stop').message == 'nothing was running; turtle stopped'


def test_ctrl_c_in_the_menu_cancels_the_run_and_asks_again(running_system):
    assert cli.main(['reset']) == 0
    terminal = Terminal('turtle_traj.cli', 'menu')
    for prompt, answer in [('choice: ', '5'), ('radius', '1'), ('clockwise', ''),
                           ('until stopped', 'y'), ('top speed', '')]:
        terminal.expect(prompt)
        terminal.send(answer + '\n')
    terminal.expect('circle lap [')
    terminal.send('\x03')
    terminal.expect('cancelled (interrupted): circle stopped by request')
    terminal.expect('choice: ')  # the menu again
    terminal.send('0\n')
    assert terminal.finish() == 0
    assert 'Traceback' not in terminal.output
    with TrajClient() as client:
        assert _standing(client)


def _standing(client: TrajClient) -> bool:
    """The turtle is where it was half a second ago."""
    before = client.turtle_pose()
    time.sleep(0.5)
    return client.turtle_pose() == before


def test_menu_enter_on_speed_keeps_the_nodes_parameter():
    from turtle_traj.api.ros_interface import make_request
    from turtle_traj.cli.menu import CHOICES, NodeSnapshot, ask_field
    from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS

    square = CHOICES['1']
    speed = next(f for f in square.fields if f.name == 'linear_speed')
    live = NodeSnapshot({'linear_speed': 1.7}, DEFAULT_SETTINGS, None)
    prompts = []
    assert ask_field(square, speed, {}, live, lambda prompt: prompts.append(prompt) or '',
                     print) is None
    assert "Enter = the node's linear_speed = 1.7" in prompts[0]
    request = make_request(square, {'size': 1.0, 'linear_speed': None})
    assert request.linear_speed == 0.0  # 0 in the request: the node uses its linear_speed


def test_menu_enter_uses_the_nodes_live_default_size(running_system, monkeypatch, capsys):
    import io

    assert cli.main(['reset']) == 0
    assert cli.main(['params', 'default_side_length', '0.75']) == 0
    try:
        monkeypatch.setattr('sys.stdin', io.StringIO('1\n\nn\n\n'))  # square, all Enter
        assert cli.main(['menu']) == 0
        out = capsys.readouterr().out
        assert "Enter = the node's default_side_length = 0.75" in out
        assert 'done: square done' in out, out
        assert 'path 3.00 m' in out  # four sides of 0.75 m: the node's value, not 2 m
    finally:
        assert cli.main(['params', 'default_side_length', '2.0']) == 0

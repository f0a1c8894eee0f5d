"""`turtle-traj teleop` on a pseudo-terminal against our simulator program: keys in, cmd_vel
and rotate_absolute goals out, the terminal restored however it ends."""

from __future__ import annotations

import os
import signal
import termios

import pytest

from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.testing.processes import Terminal, program

pytestmark = pytest.mark.system  # starts programs: `make check` leaves it out


@pytest.fixture
def turtle(rclpy_context, tmp_path):
    """Our simulator, and a node of this test recording turtle1's poses."""
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from turtlesim.msg import Pose

    from turtle_traj.rosutils.runtime import spin_until
    with program('turtle_traj.sim', cwd=tmp_path) as sim:
        node = Node('teleop_observer', context=rclpy_context)
        node.sim_said = sim.said  # what the simulator logged so far
        executor = SingleThreadedExecutor(context=rclpy_context)
        executor.add_node(node)
        node.poses = []
        node.create_subscription(Pose, 'turtle1/pose', node.poses.append, TURTLE_TOPIC_QOS)
        node.spin_until = lambda condition, timeout_s=20.0: spin_until(
            executor, condition, timeout_s=timeout_s)
        assert node.spin_until(lambda: bool(node.poses))
        try:
            yield node
        finally:
            executor.shutdown()
            node.destroy_node()


def _echoing(terminal: Terminal) -> bool:
    """The terminal is back in the mode a shell expects: canonical, echoing."""
    flags = termios.tcgetattr(terminal.fd)[3]
    return bool(flags & termios.ECHO and flags & termios.ICANON)


def _keys_drive(terminal: Terminal, turtle, keys: str, moved) -> None:
    count = len(turtle.poses)
    terminal.send(keys)
    assert turtle.spin_until(lambda: any(moved(pose) for pose in turtle.poses[count:])), keys


def test_keys_drive_as_turtle_teleop_key_and_q_restores_the_terminal(turtle):
    terminal = Terminal('turtle_traj.cli.teleop')
    terminal.expect("'q' to quit.")
    assert not _echoing(terminal)  # a key at a time, not echoed
    _keys_drive(terminal, turtle, '\x1b[A', lambda pose: pose.linear_velocity == 2.0)
    _keys_drive(terminal, turtle, '\x1b[D', lambda pose: pose.angular_velocity == 2.0)
    _keys_drive(terminal, turtle, '\x1b[B', lambda pose: pose.linear_velocity == 2.0
                and pose.angular_velocity == 0.0)  # backwards: the speed is reported
    turtle.spin_until(lambda: False, timeout_s=1.2)  # the last command times out
    _keys_drive(terminal, turtle, 'v', lambda pose: abs(pose.theta + 1.5708) < 0.03
                and pose.angular_velocity == 0.0)  # rotate_absolute to -90 degrees
    # Towards 135 degrees (2.4 s), cancelled: F cancels the goal just sent, whether or not
    # its acceptance is back yet (the keys come together, as from a quick hand). Timed from
    # the poses this test sees instead, a loaded machine once sent F 2.4 s after E.
    terminal.send('ef')
    assert turtle.spin_until(lambda: 'Rotation goal canceled' in turtle.sim_said())
    count = len(turtle.poses)
    assert turtle.spin_until(lambda: len(turtle.poses) > count + 3)  # poses after the cancel
    assert turtle.poses[-1].angular_velocity == 0.0
    assert abs(turtle.poses[-1].theta - 2.3562) > 1.0
    terminal.send('q')
    assert terminal.finish(close=False) == 0
    assert _echoing(terminal)
    terminal.close()


@pytest.mark.parametrize('ending', ['ctrl-c', 'sigterm', 'sighup'])
def test_every_way_out_restores_the_terminal(turtle, ending):
    terminal = Terminal('turtle_traj.cli.teleop')
    terminal.expect("'q' to quit.")
    assert not _echoing(terminal)
    if ending == 'ctrl-c':
        terminal.send('\x03')
    else:
        os.kill(terminal.pid, signal.SIGTERM if ending == 'sigterm' else signal.SIGHUP)
    assert terminal.finish(close=False) == 0
    assert _echoing(terminal)
    terminal.close()


def test_teleop_needs_a_terminal(tmp_path):
    import subprocess
    import sys
    done = subprocess.run([sys.executable, '-m', 'turtle_traj.cli.teleop'], stdin=subprocess.PIPE,
                          capture_output=True, text=True, timeout=30)
    assert done.returncode == 2
    assert 'teleop reads keys from a terminal' in done.stderr

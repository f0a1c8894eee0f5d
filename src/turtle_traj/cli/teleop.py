"""`turtle-traj teleop`: turtlesim's `turtle_teleop_key` in a terminal, against any turtlesim.

Arrow keys publish one cmd_vel each at +-scale_linear / +-scale_angular (parameters, 2.0 by
default, read at every press); G T R E D C V B send rotate_absolute goals, F cancels the latest
goal sent (once its acceptance is back, if it is still on its way: turtle_teleop_key instead
cancels the latest goal whose acceptance it has heard, an older one while the answer is late)
and Q quits. The terminal is put in non-canonical, no-echo mode and restored on every way out:
Q, Ctrl-C, SIGTERM, a closed terminal (SIGHUP) or an error.
"""

from __future__ import annotations

import os
import select
import signal
import sys
import termios
import tty
from collections.abc import Sequence

import rclpy
from geometry_msgs.msg import Twist
from rclpy.action import ActionClient
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions
from rclpy.task import Future
from rclpy.utilities import remove_ros_args
from turtlesim.action import RotateAbsolute

from turtle_traj.core.teleop_keys import (
    ARROW_BYTES,
    CANCEL_KEY,
    QUIT_KEY,
    ROTATIONS,
    SCALE_ANGULAR,
    SCALE_LINEAR,
    velocity,
)
from turtle_traj.rosutils.fastdds_profile import use_our_fastdds_profile
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.rosutils.runtime import events_executor, fail, spin_until

BANNER = """Reading from keyboard
---------------------------
Use arrow keys to move the turtle.
Use g|b|v|c|d|e|r|t keys to rotate to absolute orientations. 'f' to cancel a rotation.
'q' to quit.
"""
_READ_TIMEOUT_S = 0.1  # as turtle_teleop_key: one byte at a time, 0.1 s at most
_CONNECT_WAIT_S = 3.0  # for the turtle before the first key is read


class TeleopNode(Node):
    """Node `teleop_turtle`: what one key press does."""

    def __init__(self, **kwargs) -> None:
        super().__init__('teleop_turtle', **kwargs)
        self.declare_parameter('scale_linear', SCALE_LINEAR)
        self.declare_parameter('scale_angular', SCALE_ANGULAR)
        self._cmd_vel = self.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
        self._rotate = ActionClient(self, RotateAbsolute, 'turtle1/rotate_absolute')
        self._sent: Future | None = None  # the latest goal sent: its acceptance, to come
        self._cancel_when_accepted = False  # F came before that acceptance

    def destroy_node(self) -> None:
        self._rotate.destroy()  # rclpy's destroy_node leaves a node's action clients alive
        super().destroy_node()

    def connected(self) -> bool:
        """A turtle listens on cmd_vel and its rotate_absolute is there."""
        return self._cmd_vel.get_subscription_count() > 0 and self._rotate.server_is_ready()

    def press(self, key: str) -> bool:
        """Act on one key (a byte as read); False once it says quit."""
        if key in ARROW_BYTES:
            twist = Twist()
            twist.linear.x, twist.angular.z = velocity(
                ARROW_BYTES[key], self.get_parameter('scale_linear').value,
                self.get_parameter('scale_angular').value)
            self._cmd_vel.publish(twist)
        elif key in ROTATIONS:
            self._sent = self._rotate.send_goal_async(RotateAbsolute.Goal(theta=ROTATIONS[key]))
            self._cancel_when_accepted = False
            self._sent.add_done_callback(self._answered)
        elif key == CANCEL_KEY and self._sent is not None:
            if self._sent.done():
                self._cancel(self._sent)
            else:
                self._cancel_when_accepted = True
        return key != QUIT_KEY

    def _answered(self, future: Future) -> None:
        if future is self._sent and self._cancel_when_accepted:
            self._cancel(future)

    @staticmethod
    def _cancel(sent: Future) -> None:
        handle = sent.result()
        if handle is not None and handle.accepted:
            handle.cancel_goal_async()


def _hang_up(*_args) -> None:
    raise SystemExit(0)


def main(args: Sequence[str] | None = None) -> int:
    argv = list(sys.argv if args is None else ['teleop', *args])
    if len(remove_ros_args(argv)) > 1:
        return fail(f'teleop takes no arguments besides --ros-args, got '
                    f'{" ".join(remove_ros_args(argv)[1:])}')
    if not os.isatty(sys.stdin.fileno()):
        return fail('teleop reads keys from a terminal: run it in one (not through a pipe)')
    use_our_fastdds_profile()
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    node = TeleopNode()
    executor = events_executor()
    executor.add_node(node)
    stdin = sys.stdin.fileno()
    saved = termios.tcgetattr(stdin)
    for signum in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(signum, _hang_up)
    try:
        tty.setcbreak(stdin)  # no echo, a byte at a time; Ctrl-C still interrupts
        # A key pressed before the turtle is connected would be lost: wait for it a moment.
        if not spin_until(executor, node.connected, timeout_s=_CONNECT_WAIT_S):
            print(f'(no turtle answers on {node.resolve_topic_name("turtle1/cmd_vel")} yet: '
                  'is turtlesim running?)', flush=True)
        print(BANNER, end='', flush=True)
        while True:
            ready, _, _ = select.select([stdin], [], [], _READ_TIMEOUT_S)
            if ready:
                key = os.read(stdin, 1).decode(errors='replace')
                if not key or not node.press(key):  # the end of input, or q
                    break
            # What came in (goal answers included): rclpy's EventsExecutor runs the callbacks
            # of futures only while it spins until a future (one nobody completes, here).
            executor.spin_until_future_complete(Future(), timeout_sec=0.0)
    except KeyboardInterrupt:
        pass
    finally:
        try:
            termios.tcsetattr(stdin, termios.TCSADRAIN, saved)
        except termios.error:
            pass  # the terminal is gone (hung up): nothing to restore
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())

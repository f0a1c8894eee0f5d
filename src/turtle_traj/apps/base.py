"""`python -m turtle_traj.base`: the physics base as a program, in real time or scaled time,
like a robot's base driver (`cmd_vel` in, `odom` out)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence

from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.utilities import remove_ros_args

from turtle_traj.base.node import BaseNode
from turtle_traj.base.parameters import BaseConfigError
from turtle_traj.base.physics import MujocoMissing
from turtle_traj.rosutils.runtime import fail, run_nodes
from turtle_traj.sim.options import SimOptions


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog='python -m turtle_traj.base',
        description='A simulated differential-drive base (MuJoCo physics, a TurtleBot3 '
                    'Burger by default): TwistStamped on cmd_vel in, nav_msgs/Odometry on odom '
                    'and ground_truth out. ROS arguments (--ros-args -p mass:=1.2 -p '
                    'cmd_vel_type:=Twist ...) are passed through.')
    parser.add_argument('--time-scale', type=float, default=None, metavar='FACTOR',
                        help='run FACTOR times faster than real time and publish /clock (nodes '
                             'follow it with use_sim_time:=true)')
    return parser


def time_overrides(time_scale: float | None) -> list[Parameter]:
    """The base's parameters for a time scale (None: real time)."""
    if time_scale is None:
        return []
    return [Parameter('time_scale', value=time_scale), Parameter('publish_clock', value=True)]


def main(args: Sequence[str] | None = None) -> int:
    argv = list(sys.argv if args is None else ['turtle_traj.base', *args])
    options = build_parser().parse_args(remove_ros_args(argv)[1:])
    if (problem := SimOptions(time_scale=options.time_scale).problem()) is not None:
        return fail(problem)

    def create_nodes(_stop: Callable[[], None]) -> list[Node]:
        return [BaseNode(parameter_overrides=time_overrides(options.time_scale))]

    try:
        return run_nodes(create_nodes, args=argv)
    except (BaseConfigError, MujocoMissing) as error:
        return fail(str(error))

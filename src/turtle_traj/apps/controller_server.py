"""`turtle-traj controller-server` (`ros2 run turtle_traj controller_server`): the managed
controller server alone, for a Nav2 stack whose lifecycle manager brings it up, configured by a
Nav2 parameter file's `controller_server:` section. The robot (its odometry and cmd_vel) runs
elsewhere: `python -m turtle_traj.base`, a real base."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from rclpy.utilities import remove_ros_args

from turtle_traj.node.controller_server import NODE_NAME, ControllerServer
from turtle_traj.rosutils.runtime import fail, run_nodes


def build_parser(prog: str = 'turtle-traj controller-server') -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=prog,
        description=f'Run the managed controller server ({NODE_NAME}, a lifecycle node): '
                    'configure and activate it through its lifecycle services, as Nav2\'s '
                    'lifecycle manager does; it serves follow_path (nav2_msgs/action/'
                    'FollowPath). ROS arguments (--ros-args -r cmd_vel:=cmd_vel_nav) are passed '
                    'through.')
    parser.add_argument('--params-file', metavar='FILE',
                        help="a Nav2 parameter file: its controller_server section is read "
                             '(FollowPath.plugin naming one of ours: turtle_traj::ExactFollower, '
                             'turtle_traj::Dwpp, turtle_traj::PurePursuit, or module:Class)')
    return parser


def main(args: Sequence[str] | None = None) -> int:
    argv = list(sys.argv if args is None else ['turtle_traj.controller_server', *args])
    options = build_parser().parse_args(remove_ros_args(argv)[1:])
    return run(options.params_file, argv)


def run(params_file: str | None, argv: Sequence[str]) -> int:
    """Spin the server until Ctrl-C or SIGTERM; `argv` carries the ROS arguments (rclpy reads
    only those after --ros-args, so our own --params-file there is passed to it again as one)."""
    ros_args = list(argv)
    if params_file is not None:
        try:
            open(params_file, encoding='utf-8').close()
        except OSError as error:
            return fail(f'--params-file: {error.strerror}: {params_file}')
        ros_args += ['--ros-args', '--params-file', params_file]
    servers: list[ControllerServer] = []

    def create_nodes(_stop) -> list[ControllerServer]:
        servers.append(ControllerServer())
        return servers

    return run_nodes(create_nodes, args=ros_args,
                     on_exit=lambda: [server.shutdown_turtle() for server in servers])


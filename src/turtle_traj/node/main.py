"""`python -m turtle_traj`: run the trajectory node (add --with-sim for our simulator too)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.utilities import remove_ros_args

from turtle_traj.node.trajectory_node import TrajectoryNode
from turtle_traj.runtime import fail, run_nodes
from turtle_traj.sim import main as sim_main
from turtle_traj.sim.node import SimNode


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog='python -m turtle_traj',
        description='Run the turtle_traj trajectory node. ROS arguments (--ros-args -p '
                    'linear_speed:=1.5 -r __ns:=/sim1 ...) are passed through.')
    parser.add_argument('--with-sim', action='store_true',
                        help='also run our simulator in this process (no launch file needed)')
    parser.add_argument('--time-scale', type=float, default=None, metavar='FACTOR',
                        help='with --with-sim: run FACTOR times faster than real time (both '
                             'nodes then follow the simulated clock)')
    parser.add_argument('--gui', action='store_true', help='with --with-sim: live window')
    return parser


def main(args: Sequence[str] | None = None) -> int:
    argv = list(sys.argv if args is None else ['turtle_traj', *args])
    options = build_parser().parse_args(remove_ros_args(argv)[1:])
    if (options.time_scale is not None or options.gui) and not options.with_sim:
        return fail('--time-scale and --gui need --with-sim')
    if options.time_scale is not None and not 0.1 <= options.time_scale <= 1000.0:
        return fail(f'--time-scale must be within 0.1 and 1000, got {options.time_scale}')
    sim_time = options.time_scale is not None

    def create_nodes() -> list[Node]:
        nodes: list[Node] = []
        if options.with_sim:
            sim_options = sim_main.build_parser().parse_args(
                ['--time-scale', str(options.time_scale)] if sim_time else [])
            sim = SimNode(parameter_overrides=sim_main.parameter_overrides(sim_options))
            if options.gui:
                sim_main.attach_window(sim)
            nodes.append(sim)
        nodes.append(TrajectoryNode(
            parameter_overrides=[Parameter('use_sim_time', value=True)] if sim_time else []))
        return nodes

    try:
        return run_nodes(create_nodes, args=argv,
                         on_exit=lambda nodes: nodes[-1].shutdown_turtle())
    except sim_main.GuiUnavailable as error:
        return fail(f'--gui: {error}')

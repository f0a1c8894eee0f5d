"""`python -m turtle_traj.sim`: run the simulator, like `ros2 run turtlesim turtlesim_node`."""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path

from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.utilities import remove_ros_args

from turtle_traj.runtime import fail, run_nodes
from turtle_traj.sim.gui import GuiUnavailable, Window
from turtle_traj.sim.node import SimNode

GUI_FRAME_PERIOD_S = 1.0 / 30.0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog='python -m turtle_traj.sim',
        description='Pure-Python, wire-compatible stand-in for turtlesim_node. ROS arguments '
                    '(--ros-args -r __ns:=/sim1 -p background_r:=0 ...) are passed through.')
    parser.add_argument('--time-scale', type=float, default=None, metavar='FACTOR',
                        help='run FACTOR times faster than real time and publish /clock '
                             '(nodes that follow it need use_sim_time:=true)')
    parser.add_argument('--holonomic', action='store_true',
                        help='start with the holonomic parameter set')
    parser.add_argument('--gui', action='store_true', help='show a live window (pygame)')
    parser.add_argument('--snapshot', type=Path, metavar='PNG',
                        help='save the canvas to this PNG file on exit')
    parser.add_argument('--output-dir', type=Path, metavar='DIR',
                        help='folder the save_image service writes into (default: ./output)')
    return parser


def parameter_overrides(options: argparse.Namespace) -> list[Parameter]:
    """Command-line flags as parameter overrides of the simulator node."""
    overrides = []
    if options.time_scale is not None:
        overrides += [Parameter('time_scale', value=options.time_scale),
                      Parameter('publish_clock', value=True)]
    if options.holonomic:
        overrides.append(Parameter('holonomic', value=True))
    if options.output_dir is not None:
        overrides.append(Parameter('output_dir', value=str(options.output_dir)))
    return overrides


def attach_window(node: SimNode) -> Window:
    """Show the node's canvas in a live window; closing the window stops the program."""
    window = Window()

    def on_frame() -> None:
        window.show(node.render())
        if window.closed:
            raise KeyboardInterrupt

    node.create_timer(GUI_FRAME_PERIOD_S, on_frame)
    return window


def save_snapshot(nodes: Sequence[Node], path: Path | None) -> None:
    """Write the simulator canvas to `path`, if one was asked for."""
    for node in nodes:
        if path is not None and isinstance(node, SimNode):
            path.parent.mkdir(parents=True, exist_ok=True)
            node.render().save(path)
            print(f'saved {path}')


def main(args: Sequence[str] | None = None) -> int:
    import sys

    argv = list(sys.argv if args is None else ['turtle_traj.sim', *args])
    options = build_parser().parse_args(remove_ros_args(argv)[1:])
    if options.time_scale is not None and not 0.1 <= options.time_scale <= 1000.0:
        return fail(f'--time-scale must be within 0.1 and 1000, got {options.time_scale}')
    if options.snapshot is not None and options.snapshot.suffix.lower() != '.png':
        return fail(f'--snapshot must name a .png file, got {options.snapshot}')

    def create_nodes() -> list[Node]:
        node = SimNode(parameter_overrides=parameter_overrides(options))
        if options.gui:
            attach_window(node)
        return [node]

    try:
        return run_nodes(create_nodes, args=argv,
                         on_exit=lambda nodes: save_snapshot(nodes, options.snapshot))
    except GuiUnavailable as error:
        return fail(f'--gui: {error}')

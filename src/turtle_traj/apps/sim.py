"""`python -m turtle_traj.sim`: run the simulator, like `ros2 run turtlesim turtlesim_node`."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.utilities import remove_ros_args

from turtle_traj.core.turtlesim_contract import SPAWN_XY_M
from turtle_traj.rosutils.priority import add_priority_option, priority_for
from turtle_traj.rosutils.runtime import fail, run_nodes
from turtle_traj.sim.gui import GuiUnavailable, Window
from turtle_traj.sim.node import SimNode
from turtle_traj.sim.options import SimOptions, SimUnavailable, add_sim_options, options_from

GUI_FRAME_PERIOD_S = 1.0 / 30.0
FLEET_RING_M = 3.0  # the other turtles start this far round turtle1
INNER_RING_TURTLES = 7  # on that ring; the others, on a ring this far round it:
OUTER_RING_M = 4.5


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog='python -m turtle_traj.sim',
        description='Pure-Python, wire-compatible stand-in for turtlesim_node. ROS arguments '
                    '(--ros-args -r __ns:=/sim1 -p background_r:=0 ...) are passed through.')
    add_sim_options(parser)
    parser.add_argument('--holonomic', action='store_true',
                        help='start with the holonomic parameter set')
    parser.add_argument('--output-dir', type=Path, metavar='DIR',
                        help='folder the save_image service writes into (default: ./output)')
    add_priority_option(parser, 'in real time (its steps are the robot\'s: a command a step '
                                'late acts a step late); as started with --time-scale, which '
                                'can take a whole core')
    return parser


def parameter_overrides(options: SimOptions) -> list[Parameter]:
    """The options as parameter overrides of the simulator node."""
    overrides = []
    if options.time_scale is not None:
        overrides += [Parameter('time_scale', value=options.time_scale),
                      Parameter('publish_clock', value=True)]
    if options.holonomic:
        overrides.append(Parameter('holonomic', value=True))
    if options.output_dir is not None:
        overrides.append(Parameter('output_dir', value=str(options.output_dir)))
    return overrides


def create_sim(options: SimOptions, stop: Callable[[], None], *,
               lockstep: bool = False) -> list[Node]:
    """The simulator node (first), with its window when asked (closing the window calls
    `stop`) and its live view.

    :param lockstep: the simulator has no timer: a `LockstepExecutor` steps it.
    :raises SimUnavailable: the window cannot open, or the live view cannot listen.
    """
    node = SimNode(lockstep=lockstep, record=options.record is not None,
                   parameter_overrides=parameter_overrides(options))
    for name, (x, y, theta) in zip(options.turtle_names[1:], starting_places(options.turtles)[1:],
                                   strict=True):
        node.spawn_turtle(name, x, y, theta)
    nodes: list[Node] = [node]
    if options.web:  # aiohttp is loaded only when asked for
        from turtle_traj.apps.live_view import create_web
        nodes.extend(create_web(options, node))
    if options.gui:
        try:
            window = Window()
        except GuiUnavailable as error:
            for created in nodes:
                created.destroy_node()
            raise SimUnavailable(f'--gui: {error}') from None

        def on_frame() -> None:
            window.show(node.render())
            if window.closed:
                stop()

        node.create_timer(GUI_FRAME_PERIOD_S, on_frame)
    return nodes


def starting_places(count: int) -> list[tuple[float, float, float]]:
    """Where `count` turtles start: turtle1 at turtlesim's spawn point, the next
    `INNER_RING_TURTLES` evenly on a ring `FLEET_RING_M` round it, the rest evenly on a ring
    `OUTER_RING_M` round it, between the inner ones; all facing east (x, y, theta)."""
    inner = min(count - 1, INNER_RING_TURTLES)
    outer = count - 1 - inner
    rings = [(FLEET_RING_M, 2.0 * math.pi * index / max(inner, 1)) for index in range(inner)]
    rings += [(OUTER_RING_M, 2.0 * math.pi * (index + 0.5) / outer) for index in range(outer)]
    return [(SPAWN_XY_M, SPAWN_XY_M, 0.0), *(
        (SPAWN_XY_M + radius * math.cos(angle), SPAWN_XY_M + radius * math.sin(angle), 0.0)
        for radius, angle in rings)]


def save_outputs(node: SimNode, options: SimOptions) -> None:
    """Write the canvas (`--snapshot`) and what the simulator saw (`--record`), as asked."""
    for path, save in ((options.snapshot, lambda target: node.render().save(target)),
                       (options.record, node.record.save if node.record else None)):
        if path is not None and save is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            save(path)
            print(f'saved {path}')


def main(args: Sequence[str] | None = None) -> int:
    argv = list(sys.argv if args is None else ['turtle_traj.sim', *args])
    parsed = build_parser().parse_args(remove_ros_args(argv)[1:])
    options = options_from(parsed)
    if (problem := options.problem()) is not None:
        return fail(problem)
    priority = priority_for(parsed.nice, by_default=options.time_scale is None)
    nodes: list[Node] = []

    def create_nodes(stop: Callable[[], None]) -> list[Node]:
        nodes.extend(create_sim(options, stop))
        if priority is not None:
            priority.report(nodes[0].get_logger())
        return nodes

    try:
        # What the simulator relies on of the EventsExecutor (timer, subscriptions, services,
        # parameters, rotate_absolute with its awaited future and cancel, SIGTERM) is tested
        # through this program in tests/test_sim_node.py.
        return run_nodes(create_nodes, args=argv,
                         on_exit=lambda: save_outputs(nodes[0], options))
    except SimUnavailable as error:
        return fail(str(error))

"""`python -m turtle_traj`: run the trajectory node (add --with-sim for our simulator too)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from rclpy.executors import Executor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.task import Future
from rclpy.utilities import remove_ros_args

from turtle_traj.node.trajectory_node import TrajectoryNode
from turtle_traj.rosutils.lockstep import LockstepExecutor
from turtle_traj.rosutils.priority import add_priority_option, priority_for
from turtle_traj.rosutils.runtime import events_executor, fail, run_nodes
from turtle_traj.sim.options import SimOptions, SimUnavailable, add_sim_options, options_from


@dataclass(frozen=True)
class Options:
    """What to run: the node, and our simulator beside it when `sim` is given."""

    sim: SimOptions | None = None
    ros_args: Sequence[str] = field(default_factory=list)  # argv with ROS arguments, for rclpy
    base: bool = False  # the physics base instead of our turtlesim (with `sim`'s time scale)
    # the scheduling priority asked for (`rosutils.priority`); None: NICE for the node alone,
    # as started with a simulator in the process (a time-scaled one can take a whole core)
    nice: int | None = None

    def problem(self) -> str | None:
        if self.base and self.sim is not None and (
                self.sim.gui or self.sim.snapshot or self.sim.holonomic or self.sim.turtles > 1):
            return ('--base runs the physics base: --gui, --snapshot, --holonomic and --turtles '
                    "are our turtlesim's options")
        return self.sim.problem() if self.sim is not None else None


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog='python -m turtle_traj',
        description='Run the turtle_traj trajectory node. ROS arguments (--ros-args -p '
                    'linear_speed:=1.5 -r __ns:=/sim1 ...) are passed through.')
    parser.add_argument('--with-sim', action='store_true',
                        help='also run our simulator in this process (no launch file needed)')
    add_sim_options(parser, 'with --with-sim: ')
    add_priority_option(parser)
    return parser


def main(args: Sequence[str] | None = None) -> int:
    argv = list(sys.argv if args is None else ['turtle_traj', *args])
    parsed = build_parser().parse_args(remove_ros_args(argv)[1:])
    with_sim = options_from(parsed)
    if with_sim != SimOptions() and not parsed.with_sim:
        return fail('--time-scale, --gui, --web and --snapshot need --with-sim')
    return run(Options(sim=with_sim if parsed.with_sim else None, ros_args=argv,
                       nice=parsed.nice))


def run(options: Options) -> int:
    """Spin the node (and the simulator) until Ctrl-C, SIGTERM or the window closes."""
    if (problem := options.problem()) is not None:
        return fail(problem)
    sim_time = options.sim is not None and options.sim.time_scale is not None
    # the node alone (the robot elsewhere) by default; before ROS starts its threads
    priority = priority_for(options.nice, by_default=options.sim is None and not options.base)
    beside = None
    if options.sim is not None and not options.base:  # loaded only when asked for
        from turtle_traj.apps.sim_beside import SimBeside
        beside = SimBeside(options.sim)
    controllers: list[TrajectoryNode] = []
    simulators: list[Node] = []  # the one a paced lock-step executor steps

    def create_nodes(stop: Callable[[], None]) -> list[Node]:
        nodes: list[Node] = beside.create(stop, lockstep=sim_time) if beside is not None else []
        simulators.extend(nodes[:1])
        overrides = [Parameter('use_sim_time', value=True)] if sim_time else []
        if options.base:  # the base is loaded only when asked for
            from turtle_traj.apps.base_system import base_node_parameters
            base = _create_base(options.sim.time_scale if options.sim else None)
            simulators.append(base)
            nodes.append(base)
            overrides += [Parameter(name, value=value)
                          for name, value in base_node_parameters(base).items()]
            if options.sim is not None and options.sim.web:
                nodes.extend(_base_web(options.sim, base, nodes))
        try:
            controllers.extend(_trajectory_nodes(options, overrides))
        except Exception:
            for node in nodes:
                node.destroy_node()
            raise
        if priority is not None:
            priority.report(controllers[0].get_logger())
        if len(controllers) > 1:  # a fleet: its coordinator too
            from turtle_traj.fleet.coordinator import FleetCoordinator
            nodes.append(FleetCoordinator(parameter_overrides=overrides))
        return [*nodes, *controllers]

    def on_exit() -> list[Future | None]:
        ends = [controller.shutdown_turtle() for controller in controllers]
        if beside is not None:
            beside.save_outputs()
        return ends

    def make_executor() -> Executor:
        """With simulated time, the simulator steps in lock-step with the node, paced to the
        time scale: never a step before the node has answered the last (at 5x a step is 3.2
        ms of wall time, shorter than a busy machine can hold a timer up)."""
        if not sim_time:
            return events_executor()
        return LockstepExecutor(simulators[0], pace=options.sim.time_scale)

    try:
        return run_nodes(create_nodes, args=options.ros_args or None, on_exit=on_exit,
                         make_executor=make_executor)
    except SimUnavailable as error:
        return fail(str(error))


def _trajectory_nodes(options: Options, overrides: list[Parameter]) -> list[TrajectoryNode]:
    """The trajectory node; with several turtles, one for each, in the turtle's namespace
    (`/turtle2/turtle_traj` drives `/turtle2/pose` and `/turtle2/cmd_vel`), whom the fleet
    coordinator (`/fleet`) drives together."""
    names = options.sim.turtle_names if options.sim is not None else []
    if len(names) < 2:
        return [TrajectoryNode(parameter_overrides=overrides)]
    nodes: list[TrajectoryNode] = []
    try:
        for name in names:
            nodes.append(TrajectoryNode(namespace=f'/{name}', parameter_overrides=[
                *overrides, Parameter('turtle_name', value='')]))
    except Exception:
        for node in nodes:
            node.destroy_node()
        raise
    return nodes


def _base_web(options: SimOptions, base: Node, nodes: list[Node]) -> list[Node]:
    """The live view of the base's ground truth (its nodes); SimUnavailable destroys `nodes`."""
    from turtle_traj.apps.base_view import BaseScene
    from turtle_traj.apps.live_view import create_web
    try:
        return create_web(options, BaseScene(base))
    except SimUnavailable:
        for node in nodes:
            node.destroy_node()
        raise


def _create_base(time_scale: float | None) -> Node:
    """The physics base (loaded only when asked for), stepped in lock-step when `time_scale`
    is given.

    :raises SimUnavailable: its parameters are refused, or there is no MuJoCo.
    """
    from turtle_traj.apps.base import time_overrides
    from turtle_traj.base.node import BaseNode
    from turtle_traj.base.parameters import BaseConfigError
    from turtle_traj.base.physics import MujocoMissing
    try:
        return BaseNode(lockstep=time_scale is not None,
                        parameter_overrides=time_overrides(time_scale))
    except (BaseConfigError, MujocoMissing) as error:
        raise SimUnavailable(f'--base: {error}') from None

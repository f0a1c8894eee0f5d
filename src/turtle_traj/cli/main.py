"""`turtle-traj`: the command line of the trajectory node.

One subcommand per entry of the trajectory registry (`draw square`, `go-to`, ...), each with
an option or argument per request field, plus stop, reset, save, menu, params, up,
controller-server, teleop, record, play and plot. A trajectory runs as a goal of the node's
draw action.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from turtle_traj.cli.programs import LOCAL_PROGRAMS
from turtle_traj.core.fields import (
    BOOL,
    POINTS,
    STRING,
    Field,
    FieldError,
    parse_point,
    parse_points,
)
from turtle_traj.core.registry import NOT_DRAWINGS, TRAJECTORIES, TrajectoryKind
from turtle_traj.rosutils.priority import add_priority_option
from turtle_traj.sim.options import MAX_TURTLES, add_sim_options

if TYPE_CHECKING:
    from turtle_traj.client.traj_client import TrajClient

# rclpy, numpy and the client load only once a command runs: `--help` and a mistyped command
# answer at once (the registry and the parameter table are plain data).


MAX_JOBS = 64


def _parser_of(parse: Callable[[str], Any]) -> Callable[[str], Any]:
    """The registry's parser, as argparse calls it (its reason shown in the usage error)."""
    def parsed(text: str) -> Any:
        try:
            return parse(text)
        except FieldError as error:
            raise argparse.ArgumentTypeError(str(error)) from None
    return parsed


def _field_help(item: Field) -> str:
    unit = {'deg': 'degrees'}.get(item.unit, item.unit)
    text = f'{item.help} [{unit}]' if unit and item.type != POINTS else item.help
    if item.parameter:
        return f"{text}; default: the node's {item.parameter}"
    if item.default not in (None, 0.0, False, '') and not item.positional:
        return f'{text}; default: {item.default:g}'
    return text


def _add_field(parser: argparse.ArgumentParser, item: Field) -> None:
    if item.type == BOOL:
        parser.add_argument(item.option, dest=item.name, action='store_true',
                            help=_field_help(item))
    elif item.type == POINTS:
        parser.add_argument(item.name, type=_parser_of(parse_point), nargs='*', metavar='X,Y',
                            help=_field_help(item))
        parser.add_argument('--file', dest=f'{item.name}_file', type=Path, metavar='FILE',
                            help='read (more) points from FILE: one x,y (or x y) per line, '
                                 '# comments')
    elif item.positional:
        optional = {'nargs': '?'} if item.type == STRING and item.default is not None else {}
        parser.add_argument(item.name, type=_parser_of(item.parse), metavar=item.name.upper(),
                            help=_field_help(item), **optional)
    else:
        parser.add_argument(item.option, dest=item.name, metavar=item.option[2:].upper(),
                            type=_parser_of(item.parse), help=_field_help(item))
    if item.negate:
        parser.add_argument(f'--{item.negate}', action='store_true',
                            help=f'the other way (negates {item.name.upper()})')


def _add_connection_options(parser: argparse.ArgumentParser, defaults: bool = False) -> None:
    """--node, --timeout and --wait, before the command (with their defaults) or after it."""
    def default(value: object) -> object:
        return value if defaults else argparse.SUPPRESS
    parser.add_argument('--node', default=default('/turtle_traj'),
                        help='trajectory node to call, with its namespace (default: '
                             '/turtle_traj; e.g. /sim1/turtle_traj)')
    parser.add_argument('--turtle', default=default(None), metavar='NAME',
                        help="the node of turtle NAME in a fleet (`up --turtles N`): "
                             '/NAME/turtle_traj')
    parser.add_argument('--timeout', type=float, default=default(None),
                        help='cancel the trajectory if it has not ended after this many '
                             'seconds (default: no limit; Ctrl-C cancels it)')
    parser.add_argument('--wait', type=float, default=default(10.0),
                        help='seconds to wait for the node to be found (default: 10; a busy '
                             'machine can take several to discover it)')


def _add_trajectory(groups: dict[tuple[str, ...], argparse._SubParsersAction],
                    trajectory: TrajectoryKind) -> None:
    *path, word = trajectory.command
    for depth in range(1, len(path) + 1):  # intermediate words: `draw` in `draw square`
        if tuple(path[:depth]) not in groups:
            parent = groups[tuple(path[:depth - 1])]
            group = parent.add_parser(path[depth - 1], help=f'{path[depth - 1]} a shape from '
                                      'where the turtle stands')
            groups[tuple(path[:depth])] = group.add_subparsers(
                dest='shape', required=True, metavar='SHAPE')
    parser = groups[tuple(path)].add_parser(word, help=trajectory.summary,
                                            description=trajectory.summary)
    for item in trajectory.fields:
        _add_field(parser, item)
    if trajectory.name not in NOT_DRAWINGS:
        parser.add_argument('--turtles', type=_parser_of(_fleet_size), metavar='N',
                            help='draw it with turtle1 to turtleN together, through the fleet '
                                 'coordinator (/fleet, as `up --turtles N` starts it; --node '
                                 'names another), placed as turtle1 would draw it alone')
    _add_connection_options(parser)
    parser.set_defaults(trajectory=trajectory)


def _fleet_size(text: str) -> int:
    count = int(text)
    if not 1 <= count <= MAX_TURTLES:
        raise ValueError(f'--turtles must be within 1 and {MAX_TURTLES}')
    return count


def _jobs(text: str) -> int:
    count = int(text)
    if not 1 <= count <= MAX_JOBS:
        raise ValueError(f'--jobs must be within 1 and {MAX_JOBS}')
    return count


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog='turtle-traj', description='Drive a turtle along trajectories through the '
        'turtle_traj node. Sizes in metres, speeds in m/s, turn rates in rad/s, angles in '
        'degrees.')
    _add_connection_options(parser, defaults=True)
    commands = parser.add_subparsers(dest='command', required=True, metavar='COMMAND')
    groups = {(): commands}
    for trajectory in TRAJECTORIES:
        _add_trajectory(groups, trajectory)

    for name, text in [('stop', 'abort the running trajectory and stop the turtle'),
                       ('reset', 'abort, reset the simulator, ready again'),
                       ('menu', 'interactive menu of every trajectory')]:
        _add_connection_options(commands.add_parser(name, help=text))
    save = commands.add_parser('save', help="save our simulator's canvas as a PNG file")
    save.add_argument('filename', metavar='FILE.png',
                      help="file name, inside the simulator's output_dir (default: output)")
    _add_connection_options(save)
    params = commands.add_parser('params', help="show the node's parameters, one of them, or "
                                 'set one')
    _add_connection_options(params)
    params.add_argument('name', nargs='?', help='parameter to show or set')
    params.add_argument('value', nargs='?', help="new value, read as the parameter's type "
                        '(1.5, 2, 1e-9, true, turtle2)')

    up = commands.add_parser('up', help='run simulator and node together in this process')
    add_sim_options(up)
    up.add_argument('--base', action='store_true',
                    help='the physics base (MuJoCo, a TurtleBot3 Burger) instead of turtlesim: '
                         'the node drives it by odom and TwistStamped cmd_vel, within its limits')
    add_priority_option(up)
    server = commands.add_parser(
        'controller-server', help="run the managed controller server (a lifecycle node, as "
        "Nav2's controller_server) for a Nav2 stack")
    server.add_argument('--params-file', metavar='FILE',
                        help="a Nav2 parameter file, whose controller_server section it reads")
    commands.add_parser('teleop', help="drive turtle1 with the keyboard, as turtlesim's "
                        'turtle_teleop_key (arrows; g t r e d c v b turn; f cancels; q quits)')
    record = commands.add_parser('record', help='record a rosbag2 bag (MCAP) until Ctrl-C: by '
                                 "default the turtle's topics, the node's plan and draw action, "
                                 '/rosout and /clock')
    record.add_argument('topics', nargs='*', metavar='TOPIC', help='record these instead')
    record.add_argument('--output', type=Path, metavar='DIR',
                        help='the bag folder to create (default: bags/run_<date>-<time>)')
    record.add_argument('--node', default='/turtle_traj',
                        help='the trajectory node whose topics are recorded (default: '
                             '%(default)s)')
    record.add_argument('--turtles', type=_parser_of(_fleet_size), metavar='N',
                        help='record a fleet (`up --turtles N`): every turtle\'s topics, its '
                             "node's, and the fleet coordinator's draw action")
    play = commands.add_parser('play', help="publish a bag's commands (cmd_vel) at their "
                               'recorded times, as ros2 bag play does')
    play.add_argument('bag', type=Path, metavar='BAG', help='the bag folder')
    play.add_argument('--rate', type=float, default=1.0, help='speed factor (default 1)')
    play.add_argument('--topics', nargs='+', default=[], metavar='TOPIC',
                      help='play these topics instead of the command topics')
    score = commands.add_parser(
        'score', help='rank path-following controllers on the standard courses (the demo, the '
        "DWPP paper's step curves and sine, the MuJoCo base), in-process and lock-step")
    score.add_argument('--controller', action='append', default=[], metavar='NAME',
                       help='a controller to score (repeatable): exact, dwpp, pure_pursuit, an '
                            'installed entry point, or package.module:Class (default: the '
                            'three shipped)')
    score.add_argument('--course', action='append', default=[], metavar='NAME',
                       help='only this course (repeatable; default: all)')
    score.add_argument('--output', type=Path, metavar='DIR',
                       help='write score.csv, a plot per course and summary.png here (implies '
                            '--matched)')
    score.add_argument('--matched', action='store_true',
                       help="also run the exact follower with each other controller's maximum "
                            'error as its corner_tolerance, and say whether it is then no '
                            'slower within that error (about twice the time)')
    grade = commands.add_parser(
        'grade', help="grade a class's turtlesim lab: run each submission isolated against "
        'the simulator, judge its drawing, write the class page')
    grade.add_argument('task', type=Path, metavar='TASK', help='the task file (YAML)')
    grade.add_argument('submissions', type=Path, metavar='SUBMISSIONS',
                       help='a folder with a sub-folder per student: a script, or a package')
    grade.add_argument('--output', type=Path, default=Path('grades'), metavar='DIR',
                       help='where the class page, grades.csv, summary.json and each run go '
                            '(default: %(default)s)')
    grade.add_argument('--jobs', type=_jobs, metavar='N',
                       help='runs at once (default: four a core: an open-loop script sleeps)')
    grade.add_argument('--watch', metavar='NAME',
                       help="grade that student's submission alone, and serve its simulator's "
                            'live view (watch only) while it runs')
    grade.add_argument('--port', type=int, default=8090,
                       help='the live view\'s port on 127.0.0.1, with --watch (default: '
                            '%(default)s)')
    lab = commands.add_parser('lab', help="copy a ready-made lab: its task file and sample "
                              'submissions (right, wrong, hostile) to grade')
    lab.add_argument('name', metavar='NAME', help='the lab: square')
    lab.add_argument('folder', type=Path, metavar='DIR', help='where to copy it')
    plot = commands.add_parser('plot', help="PNG plots of a recorded run: path over plan, "
                               'deviation, v and omega against their limits, progress')
    plot.add_argument('bag', type=Path, nargs='?', metavar='BAG',
                      help='the bag folder (default, or --last: the newest in bags/)')
    plot.add_argument('--last', action='store_true', help='the newest bag in bags/')
    plot.add_argument('--output', type=Path, metavar='DIR',
                      help='where the PNG files go (default: BAG/plots)')
    return parser


def to_goal(options: argparse.Namespace):
    """The draw action's goal for parsed options (None for the other commands): the fleet
    coordinator's, with --turtles."""
    from turtle_traj.api.ros_interface import make_fleet_goal, make_goal
    trajectory = getattr(options, 'trajectory', None)
    if trajectory is None:
        return None
    if getattr(options, 'turtles', None):
        return make_fleet_goal(trajectory, vars(options),
                               [f'turtle{number}' for number in range(1, options.turtles + 1)])
    return make_goal(trajectory, vars(options))


def _read_points(path: Path) -> list[tuple[float, float]]:
    """Points from a file: one `x,y` or `x y` per line; blank lines and # comments skipped."""
    try:
        return parse_points(path.read_text())
    except FieldError as error:
        raise ValueError(f'{path}: {error}') from None


def main(args: Sequence[str] | None = None) -> int:
    """The command line; output piped into a reader that leaves early (`| head`) ends it
    quietly, as other command-line tools end."""
    try:
        return _main(args)
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # nothing more to say
        return 141  # 128 + SIGPIPE, what a shell reports for such a pipeline


def _main(args: Sequence[str] | None) -> int:
    parser = build_parser()
    options = parser.parse_args(args)
    if getattr(options, 'turtle', None):
        if options.node != '/turtle_traj':
            parser.error('--turtle names the node: give --turtle or --node, not both')
        options.node = f"/{options.turtle.strip('/')}/turtle_traj"
    if getattr(options, 'turtles', None) and getattr(options, 'trajectory', None):
        if options.turtle:
            parser.error('--turtles draws with turtle1 to turtleN: not with --turtle')
        if options.node == '/turtle_traj':  # not given: our fleet coordinator
            from turtle_traj.api.ros_interface import FLEET_NODE
            options.node = FLEET_NODE
    # Our programs' Fast DDS settings (fastdds.xml), for the command line's requests too: by
    # UDP, a request lost at a busy node's full socket buffer waits for the sender's next
    # heartbeat, 3 s by Fast DDS's default, a few milliseconds by ours.
    from turtle_traj.rosutils.fastdds_profile import use_our_fastdds_profile
    use_our_fastdds_profile()
    trajectory = getattr(options, 'trajectory', None)
    _add_point_files(parser, options, trajectory)
    program = LOCAL_PROGRAMS.get(options.command)
    if program is not None:
        return program(parser, options)
    # `kill` and a closed terminal stop the turtle as Ctrl-C does (the goal is cancelled).
    for ending in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(ending, signal.default_int_handler)
    if options.command in ('menu', 'params'):
        return _run_session(options)
    return _ask_the_node(options, trajectory)


def _add_point_files(parser: argparse.ArgumentParser, options: argparse.Namespace,
                     trajectory: TrajectoryKind | None) -> None:
    """Points fields: those given on the command line, then those of their --file."""
    for item in trajectory.fields if trajectory is not None else ():
        if item.type == POINTS:
            path = getattr(options, f'{item.name}_file')
            try:
                extra = _read_points(path) if path is not None else []
            except (OSError, ValueError) as error:
                parser.error(str(error))
            setattr(options, item.name, [*getattr(options, item.name), *extra] or None)


def _ask_the_node(options: argparse.Namespace, trajectory: TrajectoryKind | None) -> int:
    """save, stop, reset or a trajectory, through the node; the exit code."""
    from turtle_traj.cli.console import report
    from turtle_traj.client.traj_client import (
        GoalRejected,
        Interrupted,
        TrajClient,
        TrajClientError,
    )
    try:
        from turtle_traj.api.ros_interface import FLEET_ACTION_TYPE
        fleet = {'action_type': FLEET_ACTION_TYPE} if getattr(options, 'turtles', None) else {}
        with TrajClient(node=options.node, connect_timeout_s=options.wait, **fleet) as client:
            if options.command == 'save':
                response = client.save_canvas(options.filename)
                print(response.message, file=sys.stdout if response.success else sys.stderr)
                return 0 if response.success else 1
            if trajectory is None:  # stop, reset
                response = client.call(options.command)
                print(report(response), file=sys.stdout if response.success else sys.stderr)
                return 0 if response.success else 1
            return _draw(client, trajectory, options)
    except GoalRejected as refusal:
        print(f'refused: {refusal}', file=sys.stderr)
        return 1
    except Interrupted as interrupted:
        print(interrupted, file=sys.stderr)
        return 130
    except TrajClientError as error:
        print(f'error: {error}', file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # a second Ctrl-C, while cancelling
        print('\ninterrupted while cancelling: `turtle-traj stop` stops the turtle',
              file=sys.stderr)
        return 130


def _draw(client: TrajClient, trajectory: TrajectoryKind, options: argparse.Namespace) -> int:
    """Run one trajectory as a goal of the draw action, with a progress line; Ctrl-C cancels."""
    from turtle_traj.cli.console import ProgressLine, report
    from turtle_traj.client.traj_client import INTERRUPTED
    goal = to_goal(options)
    drawing = getattr(goal, 'drawing', goal)  # a fleet's goal carries the drawing
    line = ProgressLine(trajectory.name, endless=drawing.forever)
    try:
        outcome = client.draw(goal, on_feedback=line.show, timeout_s=options.timeout,
                              what=trajectory.name)
    finally:
        line.clear()
    result = outcome.result
    print(report(result, outcome.cancelled),
          file=sys.stdout if result.success else sys.stderr)
    if result.success:
        return 0
    return 130 if outcome.cancelled == INTERRUPTED else 1


def _run_session(options: argparse.Namespace) -> int:
    """The menu, or the params subcommand."""
    from turtle_traj.client.traj_client import TrajClient, TrajClientError
    try:
        with TrajClient(node=options.node, connect_timeout_s=options.wait) as client:
            if options.command == 'menu':
                from turtle_traj.cli.menu import run_menu  # the planner: not for params
                return run_menu(client)
            if options.value is None:  # show all, or one
                names = None if options.name is None else [options.name]
                for name, value in client.parameters(names).items():
                    print(f'{name}: {value}')
                return 0
            reason = client.set_parameter(options.name, options.value)
    except TrajClientError as error:
        print(f'error: {error}', file=sys.stderr)
        return 2
    if reason:
        print(f'refused: {reason}', file=sys.stderr)
        return 1
    print(f'set {options.name} to {options.value}')
    return 0


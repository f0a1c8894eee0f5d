"""`turtle-traj`: the command line of the trajectory node."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence

from turtle_traj_interfaces.srv import DrawShape, GoTo, Move

from turtle_traj import planning
from turtle_traj.client import TrajClient, TrajClientError, report
from turtle_traj.menu import run_menu


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog='turtle-traj', description='Drive a turtle along trajectories through the '
        'turtle_traj node. Sizes in metres, speeds in m/s, angles in degrees.')
    parser.add_argument('--node', default='/turtle_traj',
                        help='trajectory node to call, with its namespace (default: '
                             '/turtle_traj; e.g. /sim1/turtle_traj)')
    parser.add_argument('--timeout', type=float, default=300.0,
                        help='give up after this many seconds (default: 300)')
    parser.add_argument('--wait', type=float, default=10.0,
                        help='seconds to wait for the node to be found (default: 10; a busy '
                             'machine can take several to discover it)')
    commands = parser.add_subparsers(dest='command', required=True, metavar='COMMAND')

    draw = commands.add_parser('draw', help='draw a shape from where the turtle stands')
    draw.add_argument('shape', choices=planning.SHAPES)
    draw.add_argument('--size', type=float, default=0.0,
                      help='side (polygons), radius (circle), start radius (spiral), '
                           'amplitude (sine); default: the node\'s parameter')
    draw.add_argument('--sides', type=int, default=0, help='polygon: number of sides')
    draw.add_argument('--clockwise', action='store_true')
    draw.add_argument('--turns', type=float, default=0.0,
                      help='circle (0 = until stopped) or spiral turns')
    draw.add_argument('--growth', type=float, default=0.0, help='spiral: metres per turn')
    draw.add_argument('--max-radius', type=float, default=0.0, help='spiral: end radius')
    draw.add_argument('--frequency', type=float, default=0.0, help='sine: cycles per metre')
    draw.add_argument('--length', type=float, default=0.0, help='sine: length')
    draw.add_argument('--speed', type=float, default=0.0, help='top linear speed')
    draw.add_argument('--angular-speed', type=float, default=0.0, help='top turn rate, rad/s')

    go_to = commands.add_parser('go-to', help='drive to a point')
    go_to.add_argument('x', type=float)
    go_to.add_argument('y', type=float)
    go_to.add_argument('--theta', type=float, help='final heading, degrees')
    go_to.add_argument('--tolerance', type=float, default=0.0, help='arrival tolerance')
    go_to.add_argument('--speed', type=float, default=0.0)

    move = commands.add_parser('move', help='drive straight')
    move.add_argument('distance', type=float)
    move.add_argument('--backward', action='store_true')
    move.add_argument('--speed', type=float, default=0.0)

    rotate = commands.add_parser('rotate', help='turn in place (counter-clockwise by default)')
    rotate.add_argument('degrees', type=float)
    rotate.add_argument('--clockwise', action='store_true')
    rotate.add_argument('--speed', type=float, default=0.0, help='turn rate, rad/s')

    commands.add_parser('stop', help='abort the running trajectory and stop the turtle')
    commands.add_parser('reset', help='abort, reset the simulator, ready again')

    commands.add_parser('menu', help='interactive menu of every trajectory')
    params = commands.add_parser('params', help='show the node\'s parameters, or set one')
    params.add_argument('name', nargs='?', help='parameter to set')
    params.add_argument('value', nargs='?', help='new value (YAML: 1.5, true, turtle2)')

    up = commands.add_parser('up', help='run simulator and node together in this process')
    up.add_argument('--gui', action='store_true')
    up.add_argument('--time-scale', type=float)
    return parser


def to_request(options: argparse.Namespace) -> tuple[str, object]:
    """The service name and request for parsed options."""
    if options.command == 'draw':
        return f'draw_{options.shape}', DrawShape.Request(
            sides=options.sides, size=options.size, clockwise=options.clockwise,
            linear_speed=options.speed, angular_speed=options.angular_speed,
            turns=options.turns, growth=options.growth, max_radius=options.max_radius,
            frequency=options.frequency, length=options.length)
    if options.command == 'go-to':
        return 'go_to', GoTo.Request(
            x=options.x, y=options.y, use_theta=options.theta is not None,
            theta=math.radians(options.theta or 0.0), tolerance=options.tolerance,
            linear_speed=options.speed)
    if options.command == 'move':
        sign = -1.0 if options.backward else 1.0
        return 'move', Move.Request(distance=sign * options.distance, speed=options.speed)
    if options.command == 'rotate':
        sign = -1.0 if options.clockwise else 1.0
        return 'rotate', Move.Request(angle=sign * math.radians(options.degrees),
                                      speed=options.speed)
    return options.command, None


def main(args: Sequence[str] | None = None) -> int:
    options = build_parser().parse_args(args)
    if options.command == 'up':
        from turtle_traj.node.main import main as node_main
        extra = ['--gui'] if options.gui else []
        if options.time_scale is not None:
            extra += ['--time-scale', str(options.time_scale)]
        return node_main(['--with-sim', *extra])
    if options.command in ('menu', 'params'):
        return _run_session(options)
    service, request = to_request(options)
    interactive = sys.stderr.isatty()
    expected = ''

    def progress(seconds: float) -> None:
        if interactive:
            print(f'\r{service}: running {seconds:5.1f} s{expected}', end='', file=sys.stderr,
                  flush=True)

    try:
        with TrajClient(node=options.node, connect_timeout_s=options.wait) as client:
            if interactive and request is not None:
                bound = client.expected_duration(service, request)
                expected = f' of at least {bound:.1f} s' if bound is not None else ''
            response = client.call(service, request, timeout_s=options.timeout,
                                   on_progress=progress)
    except TrajClientError as error:
        print(f'\nerror: {error}' if interactive else f'error: {error}', file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print('\ninterrupted (the trajectory goes on; `turtle-traj stop` stops it)',
              file=sys.stderr)
        return 130
    if interactive:
        print('\r', end='', file=sys.stderr)
    print(report(response), file=sys.stdout if response.success else sys.stderr)
    return 0 if response.success else 1


def _run_session(options: argparse.Namespace) -> int:
    """The menu, or the params subcommand."""
    try:
        with TrajClient(node=options.node, connect_timeout_s=options.wait) as client:
            if options.command == 'menu':
                return run_menu(client)
            if options.name is None:
                for name, value in client.parameters().items():
                    print(f'{name}: {value}')
                return 0
            if options.value is None:
                print('error: params NAME needs a VALUE', file=sys.stderr)
                return 2
            reason = client.set_parameter(options.name, options.value)
    except TrajClientError as error:
        print(f'error: {error}', file=sys.stderr)
        return 2
    if reason:
        print(f'refused: {reason}', file=sys.stderr)
        return 1
    print(f'set {options.name} to {options.value}')
    return 0


if __name__ == '__main__':
    sys.exit(main())

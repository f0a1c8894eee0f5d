"""`turtle-traj menu`: an interactive menu over the trajectory services.

Every parameter is asked with its default and valid range; a bad answer is asked again, and
Ctrl-D or Ctrl-C at a prompt leaves the menu cleanly.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from std_srvs.srv import Trigger
from turtle_traj_interfaces.srv import DrawShape, GoTo, Move

from turtle_traj.client import TrajClient, TrajClientError, report
from turtle_traj.planning import MAX_SIDES


class _Leave(Exception):
    """The user closed the input (Ctrl-D) or interrupted it (Ctrl-C)."""


@dataclass(frozen=True)
class Field:
    """One question: request field, prompt, default and inclusive range.

    A field with a `parameter` defaults to 0, which the request passes on and the node reads as
    "use my parameter": Enter shows that parameter's live value and keeps it.
    """

    name: str
    prompt: str
    default: float
    low: float
    high: float
    integer: bool = False
    yes_no: bool = False
    parameter: str = ''


def _node_default(name: str, prompt: str, parameter: str, low: float, high: float) -> Field:
    return Field(name, prompt, 0.0, low, high, parameter=parameter)


@dataclass(frozen=True)
class Choice:
    label: str
    service: str
    fields: tuple[Field, ...] = ()
    build: Callable[[dict[str, float]], object] | None = None


def _shape(**fixed: float) -> Callable[[dict[str, float]], DrawShape.Request]:
    def build(answers: dict[str, float]) -> DrawShape.Request:
        values = {**fixed, **answers}
        values['clockwise'] = bool(values.get('clockwise', False))
        if 'sides' in values:
            values['sides'] = int(values['sides'])
        return DrawShape.Request(**values)
    return build


_CLOCKWISE = Field('clockwise', 'clockwise', 0, 0, 1, yes_no=True)
_SPEED = _node_default('linear_speed', 'speed in m/s', 'linear_speed', 0.01, 10.0)
_SIDE = _node_default('size', 'side length in m', 'default_side_length', 0.01, 10.0)

CHOICES = {
    '1': Choice('square', 'draw_square', (_SIDE, _CLOCKWISE, _SPEED), _shape()),
    '2': Choice('triangle', 'draw_triangle', (_SIDE, _CLOCKWISE, _SPEED), _shape()),
    '3': Choice('circle', 'draw_circle', (
        _node_default('size', 'radius in m', 'default_radius', 0.01, 5.5), _CLOCKWISE,
        Field('turns', 'turns', 1.0, 0.1, 100.0), _SPEED), _shape()),
    '4': Choice('spiral', 'draw_spiral', (
        _node_default('size', 'start radius in m', 'default_spiral_start_radius', 0.01, 5.0),
        _node_default('growth', 'growth per turn in m', 'default_spiral_growth', 0.01, 5.0),
        Field('turns', 'turns', 3.0, 0.1, 100.0), _CLOCKWISE, _SPEED), _shape()),
    '5': Choice('point to point', 'go_to', (
        Field('x', 'goal x in m', 8.0, 0.3, 10.79), Field('y', 'goal y in m', 8.0, 0.3, 10.79),
        _SPEED), lambda a: GoTo.Request(**a)),
    '6': Choice('hexagon', 'draw_hexagon', (_SIDE, _CLOCKWISE, _SPEED), _shape()),
    '7': Choice('sine wave', 'draw_sine', (
        _node_default('size', 'amplitude in m', 'default_sine_amplitude', 0.01, 5.0),
        _node_default('frequency', 'cycles per metre', 'default_sine_frequency', 0.01, 20.0),
        _node_default('length', 'length in m', 'default_sine_length', 0.01, 10.0), _SPEED),
        _shape()),
    '8': Choice('reset', 'reset', (), None),
    '9': Choice('polygon', 'draw_polygon', (
        Field('sides', 'number of sides', 5, 3, MAX_SIDES, integer=True),
        _SIDE, _CLOCKWISE, _SPEED), _shape()),
    '10': Choice('move straight', 'move', (
        Field('distance', 'distance in m (negative: backwards)', 2.0, -10.0, 10.0),),
        lambda a: Move.Request(**a)),
    '11': Choice('rotate', 'rotate', (
        Field('angle', 'angle in degrees (negative: clockwise)', 90.0, -3600.0, 3600.0),),
        lambda a: Move.Request(angle=math.radians(a['angle']))),
}


def _read(ask: Callable[[str], str], text: str) -> str:
    try:
        return ask(text).strip()
    except (EOFError, KeyboardInterrupt):
        raise _Leave from None


def ask_field(field: Field, ask: Callable[[str], str], say: Callable[[str], None],
              live: dict[str, object] | None = None) -> float:
    """Ask until the answer is valid; Enter takes the default.

    :param live: the node's current parameters, to show what Enter keeps.
    """
    if field.yes_no:
        while True:
            answer = _read(ask, f'  {field.prompt}? [y/N]: ').lower()
            if answer in ('', 'n', 'no', 'y', 'yes'):
                return float(answer in ('y', 'yes'))
            say('  please answer y or n')
    if field.parameter:
        value = (live or {}).get(field.parameter)
        shown = f"the node's {field.parameter}" + (f' = {value:g}' if value is not None else '')
    else:
        shown = f'{field.default:g}'
    while True:
        answer = _read(ask, f'  {field.prompt} ({field.low:g} to {field.high:g}, '
                            f'Enter = {shown}): ')
        if not answer:
            return field.default
        try:
            value = int(answer) if field.integer else float(answer)
        except ValueError:
            say(f'  {answer!r} is not a{"whole " if field.integer else " "}number')
            continue
        if not (math.isfinite(value) and field.low <= value <= field.high):
            say(f'  {answer} is outside {field.low:g} to {field.high:g}')
            continue
        return value


def run_menu(client: TrajClient, ask: Callable[[str], str] = input,
             say: Callable[[str], None] = print) -> int:
    """The menu loop; returns the exit code."""
    listing = '  '.join(f'{key} {choice.label}' for key, choice in CHOICES.items())
    try:
        while True:
            say(f'\n{listing}  0 exit')
            key = _read(ask, 'choice: ')
            if key == '0':
                return 0
            choice = CHOICES.get(key)
            if choice is None:
                say(f'  unknown choice {key!r}')
                continue
            live = client.parameters() if choice.fields else {}
            answers = {field.name: ask_field(field, ask, say, live) for field in choice.fields}
            request = choice.build(answers) if choice.build else Trigger.Request()
            say(f'  running {choice.label} ...')
            try:
                say(report(client.call(choice.service, request)))
            except TrajClientError as error:
                say(f'  error: {error}')
    except _Leave:
        say('\nbye')
        return 0

"""A request's fields as people enter them, and the one parser of each field type (`Field.parse`),
used by the command line, the menu and the live view's panel alike."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from turtle_traj.core.parameters.table import PARAMETER
from turtle_traj.core.planning.limits import MAX_POINTS, MAX_TEXT_CHARS

if TYPE_CHECKING:
    from turtle_traj.core.parameters.settings import Settings

FLOAT, INT, BOOL, POINTS, STRING = 'float', 'int', 'bool', 'points', 'string'


@dataclass(frozen=True)
class Field:
    """One request field as people enter it, on the command line and in the menu.

    A field backed by a node `parameter` sends 0 unless given, which the node reads as "use
    my parameter"; its range and unit are the parameter's (`parameters.table`).
    """

    name: str  # the request's field
    help: str
    unit: str = ''  # as entered; 'deg' is sent in radians
    type: str = FLOAT  # FLOAT, INT, BOOL, POINTS or STRING
    default: float | None = 0.0  # sent when not given; None: optional (see `given`)
    parameter: str = ''
    low: float | None = None
    high: float | None = None
    positional: bool = False
    fits: bool = False  # the size that scales: its upper bound is what fits from the pose
    negate: str = ''  # command-line flag that sends the value negated ('backward')
    given: str = ''  # request flag set true when this optional field is given ('use_theta')
    flag: str = ''  # command-line option, when not --<name>
    menu: bool = True  # asked in the menu (False: command line only)
    axis: str = ''  # 'x' or 'y': a coordinate, within the arena's bounds on that axis
    excludes: str = ''  # a field sent as 0, not its default, when this flag is true

    def __post_init__(self) -> None:
        if self.parameter:
            spec = PARAMETER[self.parameter]
            object.__setattr__(self, 'unit', self.unit or spec.unit)
            object.__setattr__(self, 'low', spec.low if self.low is None else self.low)
            object.__setattr__(self, 'high', spec.high if self.high is None else self.high)

    def bounds(self, settings: Settings) -> tuple[float, float]:
        """The range a person may enter (a coordinate: inside the arena, after its margin)."""
        if self.axis:
            arena = settings.arena
            low, high = getattr(arena, f'min_{self.axis}'), getattr(arena, f'max_{self.axis}')
            return low + arena.margin, high - arena.margin
        return self.low, self.high

    @property
    def option(self) -> str:
        return '--' + (self.flag or self.name).replace('_', '-')

    def to_request(self, value: Any) -> Any:
        """A value as entered, in the request's units (degrees to radians)."""
        return math.radians(value) if self.unit == 'deg' else value

    def parse(self, given: Any) -> Any:
        """A value of this field's type from what a person entered: text (the command line,
        the menu) or a JSON value (the live view). The one parser of each type; ranges are the
        node's to check, which says why in its own words.

        :raises FieldError: a value that is not of the field's type, with the reason.
        """
        if self.type == BOOL:
            if isinstance(given, bool):
                return given
            answer = str(given).strip().lower()
            if answer in _YES or answer in _NO:
                return answer in _YES
            raise FieldError(f'{self.name}: {given!r}: please answer y or n (true or false)')
        if self.type == STRING:
            if not isinstance(given, str) or len(given) > MAX_TEXT_CHARS:
                raise FieldError(f'{self.name} must be a text of at most {MAX_TEXT_CHARS} '
                                 'characters')
            return given
        if self.type == POINTS:
            points = parse_points(given) if isinstance(given, str) else given
            if not isinstance(points, list | tuple) or len(points) > MAX_POINTS:
                raise FieldError(f'{self.name} must be a list of at most {MAX_POINTS} '
                                 '[x, y] pairs')
            return [parse_point(point) for point in points]
        number = parse_number(given, self.name)
        if self.type == INT:
            if number != int(number):
                raise FieldError(f'{self.name}: {given!r} is not a whole number')
            return int(number)
        return number


class FieldError(ValueError):
    """A value that is not of its field's type; the message says why."""


_YES, _NO = ('y', 'yes', 'true', '1'), ('n', 'no', 'false', '0')


def parse_number(given: Any, name: str) -> float:
    """A finite number from a number or its text."""
    try:
        number = float(given) if not isinstance(given, bool) else math.nan
    except (TypeError, ValueError):
        raise FieldError(f'{name}: {given!r} is not a number') from None
    if not math.isfinite(number):
        raise FieldError(f'{name}: {given!r} is not a finite number')
    return number


def parse_point(given: Any) -> tuple[float, float]:
    """A point from text `x,y` (or `x y`) or a pair [x, y]."""
    parts = given.replace(',', ' ').split() if isinstance(given, str) else given
    if not isinstance(parts, list | tuple) or len(parts) != 2:
        raise FieldError(f'a point must be [x, y] or x,y (e.g. 2.5,8), got {given!r}')
    return parse_number(parts[0], 'x'), parse_number(parts[1], 'y')


def parse_points(text: str) -> list[tuple[float, float]]:
    """Points from text: `x,y` separated by spaces, or one `x,y` (or `x y`) per line; blank
    lines and # comments skipped (a file of points)."""
    points = []
    for line in text.splitlines():
        line = line.split('#', 1)[0].strip()
        if not line:
            continue
        words = line.split()
        if ',' not in line and len(words) == 2:  # `x y`: one point to a line
            points.append(parse_point(words))
        else:
            points.extend(parse_point(word) for word in line.replace(', ', ',').split())
    return points

"""The live view's messages, as JSON text: frames out, requests in, every request checked.

Pure Python (no ROS, no web server). Server to page: `hello` (the registry and the key map),
`snapshot` (the whole trail layer), `frame` (each simulator step: poses and the trail pixels
that changed), `status`, `run`, `params`, `param_result`, `error`. Page to server: `key`,
`goto`, `start`, `cancel`, `get_params`, `set_param`.
"""

from __future__ import annotations

import base64
import json
import math
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from turtle_traj.teleop_keys import ARROWS, CANCEL_KEY, ROTATIONS
from turtle_traj.trajectories import BOOL, BY_NAME, INT, POINTS, STRING, TRAJECTORIES
from turtle_traj.turtlesim_contract import CANVAS_SIZE_PX, PIXELS_PER_METER, WORLD_SIZE_M

MAX_MESSAGE_CHARS = 16_384  # a request longer than this is refused (a path of points fits)
MAX_TEXT_CHARS = 4_096  # a text, SVG path or parameter value
MAX_POINTS = 500
_NAME = re.compile(r'[A-Za-z_][A-Za-z0-9_/]{0,63}')  # a turtle or parameter name


class ProtocolError(ValueError):
    """A request the server does not understand or refuses; the message says why."""


@dataclass
class Frame:
    """What one simulator step changed, taken on the ROS side and encoded on the web side.

    :ivar patches: (row, column, RGBA pixels now) of each rectangle strokes touched.
    :ivar snapshot: the whole RGBA trail layer, when a page asked for it.
    """

    seq: int
    time_s: float  # simulated
    wall_s: float  # time.time() when taken, for the page's latency figure
    background: tuple[int, int, int]
    turtles: list[tuple[str, float, float, float]]
    cleared: bool = False
    patches: list[tuple[int, int, np.ndarray]] = field(default_factory=list)
    snapshot: np.ndarray | None = None


_COMPACT = (',', ':')


def _pixels(array: np.ndarray) -> str:
    return base64.b64encode(np.ascontiguousarray(array).tobytes()).decode('ascii')


def _turtles(frame: Frame) -> list[list]:
    return [[name, round(x, 5), round(y, 5), round(theta, 5)]
            for name, x, y, theta in frame.turtles]


def frame_text(frame: Frame) -> str:
    return json.dumps({
        'type': 'frame', 'seq': frame.seq, 't': round(frame.time_s, 4), 'wall': frame.wall_s,
        'background': frame.background, 'turtles': _turtles(frame),
        'clear': frame.cleared,
        'patches': [[row, column, int(pixels.shape[0]), int(pixels.shape[1]), _pixels(pixels)]
                    for row, column, pixels in frame.patches]}, separators=_COMPACT)


def snapshot_text(frame: Frame) -> str:
    """The whole trail layer as of `frame` (which must carry one), then its poses."""
    height, width = frame.snapshot.shape[:2]
    return json.dumps({
        'type': 'snapshot', 'seq': frame.seq, 'width': width, 'height': height,
        'background': list(frame.background), 'turtles': _turtles(frame),
        'pixels': _pixels(frame.snapshot)})


def hello_text() -> str:
    """The registry (kinds, fields, defaults, ranges) and the keys, for the page's panel."""
    kinds = [{
        'name': kind.name, 'summary': kind.summary,
        'fields': [{'name': item.name, 'help': item.help, 'unit': item.unit, 'type': item.type,
                    'default': item.default, 'parameter': item.parameter, 'low': item.low,
                    'high': item.high, 'optional': item.default is None}
                   for item in kind.fields]}
        for kind in TRAJECTORIES]
    world = {'pixels_per_meter': PIXELS_PER_METER, 'size_m': WORLD_SIZE_M,
             'canvas_px': CANVAS_SIZE_PX}
    return json.dumps({'type': 'hello', 'world': world, 'kinds': kinds, 'arrows': list(ARROWS),
                       'rotations': ROTATIONS, 'cancel_key': CANCEL_KEY})


def text(kind: str, **values: Any) -> str:
    return json.dumps({'type': kind, **values})


def error_text(message: str) -> str:
    return text('error', message=message)


# -- requests from the page -------------------------------------------------------------------

def _number(message: dict, name: str) -> float:
    value = message.get(name)
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ProtocolError(f'{name} must be a finite number, got {value!r}')
    return float(value)


def _name(message: dict, key: str) -> str:
    value = message.get(key)
    if not isinstance(value, str) or not _NAME.fullmatch(value):
        raise ProtocolError(f'{key} must be a name of letters, digits, _ and /, got {value!r}')
    return value


def _field_values(kind_name: str, given: Any) -> dict[str, Any]:
    """Values as entered for a kind's fields, each of the field's type (unknown ones refused;
    ranges are the node's to check, which says why in its own words)."""
    if not isinstance(given, dict):
        raise ProtocolError('fields must be an object of field names to values')
    fields = {item.name: item for item in BY_NAME[kind_name].fields}
    values: dict[str, Any] = {}
    for name, value in given.items():
        item = fields.get(name)
        if item is None:
            raise ProtocolError(f'{kind_name} has no field {name!r}; it has: {", ".join(fields)}')
        if value is None:
            continue
        if item.type == BOOL:
            if not isinstance(value, bool):
                raise ProtocolError(f'{name} must be true or false')
        elif item.type == STRING:
            if not isinstance(value, str) or len(value) > MAX_TEXT_CHARS:
                raise ProtocolError(f'{name} must be a text of at most {MAX_TEXT_CHARS} '
                                    'characters')
        elif item.type == POINTS:
            if not isinstance(value, list) or len(value) > MAX_POINTS:
                raise ProtocolError(f'{name} must be a list of at most {MAX_POINTS} [x, y] pairs')
            value = [_point(point) for point in value]
        else:
            value = _number({name: value}, name)
            if item.type == INT:
                if value != int(value):
                    raise ProtocolError(f'{name} must be a whole number, got {value:g}')
                value = int(value)
        values[name] = value
    return values


def _point(point: Any) -> tuple[float, float]:
    if not isinstance(point, list) or len(point) != 2:
        raise ProtocolError(f'a point must be [x, y], got {point!r}')
    return _number({'x': point[0]}, 'x'), _number({'y': point[1]}, 'y')


def parse(raw: str) -> dict[str, Any]:
    """A request from the page, checked: its `type` and its values of the right types.

    :raises ProtocolError: anything else, with the reason.
    """
    if len(raw) > MAX_MESSAGE_CHARS:
        raise ProtocolError(f'message of {len(raw)} characters refused (at most '
                            f'{MAX_MESSAGE_CHARS})')
    try:
        message = json.loads(raw)
    except (ValueError, RecursionError):
        raise ProtocolError('not JSON') from None
    if not isinstance(message, dict):
        raise ProtocolError('a message must be a JSON object with a "type"')
    kind = message.get('type')
    if kind == 'key':
        key = message.get('key')
        if key not in ARROWS and key not in ROTATIONS and key != CANCEL_KEY:
            raise ProtocolError(f'unknown key {key!r}')
        return {'type': kind, 'turtle': _name(message, 'turtle'), 'key': key}
    if kind == 'goto':
        return {'type': kind, 'x': _number(message, 'x'), 'y': _number(message, 'y')}
    if kind == 'start':
        trajectory = message.get('trajectory')
        if trajectory not in BY_NAME:
            raise ProtocolError(f'unknown trajectory {trajectory!r}')
        return {'type': kind, 'trajectory': trajectory,
                'fields': _field_values(trajectory, message.get('fields', {}))}
    if kind in ('cancel', 'get_params'):
        return {'type': kind}
    if kind == 'set_param':
        value = message.get('value')
        if not isinstance(value, str) or len(value) > MAX_TEXT_CHARS:
            raise ProtocolError('value must be a text (as `ros2 param set` takes it)')
        return {'type': kind, 'name': _name(message, 'name'), 'value': value}
    raise ProtocolError(f'unknown message type {kind!r}')

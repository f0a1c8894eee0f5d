"""The trajectory panel's part of the live view's messages: the registry in the hello, and the
requests `goto`, `start`, `cancel`, `get_params` and `set_param`. Pure Python: field values go
through the registry's one parser per field type (`Field.parse`)."""

from __future__ import annotations

from typing import Any

from turtle_traj.core.fields import FieldError
from turtle_traj.core.planning.limits import MAX_TEXT_CHARS
from turtle_traj.core.registry import BY_NAME, TRAJECTORIES
from turtle_traj.web.messages import Checker, ProtocolError, name, number


def hello() -> dict[str, Any]:
    """The registry: kinds, their fields, defaults and ranges, for the panel's form."""
    return {'kinds': [{
        'name': kind.name, 'summary': kind.summary,
        'fields': [{'name': item.name, 'help': item.help, 'unit': item.unit, 'type': item.type,
                    'default': item.default, 'parameter': item.parameter, 'low': item.low,
                    'high': item.high, 'optional': item.default is None}
                   for item in kind.fields]}
        for kind in TRAJECTORIES]}


def _field_values(kind_name: str, given: Any) -> dict[str, Any]:
    """Values as entered for a kind's fields, each parsed by its field (unknown ones refused;
    ranges are the node's to check, which says why in its own words)."""
    if not isinstance(given, dict):
        raise ProtocolError('fields must be an object of field names to values')
    fields = {item.name: item for item in BY_NAME[kind_name].fields}
    values: dict[str, Any] = {}
    for field_name, value in given.items():
        item = fields.get(field_name)
        if item is None:
            raise ProtocolError(f'{kind_name} has no field {field_name!r}; it has: '
                                f'{", ".join(fields)}')
        if value is None:
            continue
        try:
            values[field_name] = item.parse(value)
        except FieldError as error:
            raise ProtocolError(str(error)) from None
    return values


def _goto(message: dict[str, Any]) -> dict[str, Any]:
    return {'x': number(message, 'x'), 'y': number(message, 'y')}


def _start(message: dict[str, Any]) -> dict[str, Any]:
    trajectory = message.get('trajectory')
    if not isinstance(trajectory, str) or trajectory not in BY_NAME:
        raise ProtocolError(f'unknown trajectory {trajectory!r}')
    return {'trajectory': trajectory,
            'fields': _field_values(trajectory, message.get('fields', {}))}


def _set_param(message: dict[str, Any]) -> dict[str, Any]:
    value = message.get('value')
    if not isinstance(value, str) or len(value) > MAX_TEXT_CHARS:
        raise ProtocolError('value must be a text (as `ros2 param set` takes it)')
    return {'name': name(message, 'name'), 'value': value}


CHECKERS: dict[str, Checker] = {'goto': _goto, 'start': _start, 'cancel': lambda _: {},
                                'get_params': lambda _: {}, 'set_param': _set_param}

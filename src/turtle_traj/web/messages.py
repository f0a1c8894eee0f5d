"""The live view's requests and replies as JSON text, every request checked. Pure Python.

The server knows no request of its own: each part of the page (the simulator's view, the
trajectory panel) brings `checkers`, one per request type it handles, which return the request
with values of the right types or raise ProtocolError.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Callable, Mapping
from typing import Any

MAX_MESSAGE_CHARS = 16_384  # a request longer than this is refused (a path of points fits)
_NAME = re.compile(r'[A-Za-z_][A-Za-z0-9_/]{0,63}')  # a turtle or parameter name

Checker = Callable[[dict[str, Any]], dict[str, Any]]


class ProtocolError(ValueError):
    """A request the server does not understand or refuses; the message says why."""


def text(kind: str, **values: Any) -> str:
    return json.dumps({'type': kind, **values})


def error_text(message: str) -> str:
    return text('error', message=message)


def number(message: Mapping[str, Any], key: str) -> float:
    value = message.get(key)
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ProtocolError(f'{key} must be a finite number, got {value!r}')
    return float(value)


def name(message: Mapping[str, Any], key: str) -> str:
    value = message.get(key)
    if not isinstance(value, str) or not _NAME.fullmatch(value):
        raise ProtocolError(f'{key} must be a name of letters, digits, _ and /, got {value!r}')
    return value


def parse(raw: str, checkers: Mapping[str, Checker]) -> dict[str, Any]:
    """A request from a page, checked by the checker of its `type`.

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
    checker = checkers.get(kind) if isinstance(kind, str) else None
    if checker is None:
        raise ProtocolError(f'unknown message type {kind!r}')
    return {'type': kind, **checker(message)}

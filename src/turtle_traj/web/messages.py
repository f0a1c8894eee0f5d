"""The live view's requests and replies as JSON text, every request checked. Pure Python.

The server knows no request of its own: each part of the page (the simulator's view, the
trajectory panel) brings `checkers`, one per request type it handles, which return the request
with values of the right types or raise ProtocolError.
"""

from __future__ import annotations

import json
import math
import queue
import re
from collections.abc import Callable, Iterator, Mapping
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


class Inbox:
    """Checked requests handed from the web thread to the ROS thread, in order of arrival."""

    def __init__(self) -> None:
        self._queue: queue.SimpleQueue[tuple[int, dict[str, Any]]] = queue.SimpleQueue()

    def put(self, page: int, request: dict[str, Any]) -> None:
        """On the web thread: never blocks."""
        self._queue.put((page, request))

    def take(self) -> Iterator[tuple[int, dict[str, Any]]]:
        """On the ROS thread: each (page, request) that arrived, until none is left."""
        while True:
            try:
                yield self._queue.get_nowait()
            except queue.Empty:
                return


class QueuedPart:
    """A part of the page whose checked requests wait in `inbox` for the ROS thread; its
    `hello_fields` go into the page's hello."""

    checkers: Mapping[str, Checker] = {}
    hello_fields: Callable[[], dict[str, Any]] = staticmethod(dict)

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.inbox = Inbox()

    def hello(self) -> dict[str, Any]:
        return self.hello_fields()

    def request(self, page: int, request: dict[str, Any]) -> None:
        """Queue a page's request for the ROS thread (called on the web thread)."""
        self.inbox.put(page, request)

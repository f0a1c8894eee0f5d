"""The simulator's part of the live view's messages: the world and the keys in the hello, and
the `key` request (turtle_teleop_key's keys). Pure Python."""

from __future__ import annotations

from typing import Any

from turtle_traj.core.teleop_keys import ARROWS, CANCEL_KEY, ROTATIONS
from turtle_traj.core.turtlesim_contract import CANVAS_SIZE_PX, PIXELS_PER_METER, WORLD_SIZE_M
from turtle_traj.web.messages import Checker, ProtocolError, name


def hello() -> dict[str, Any]:
    """The world's size and scale, and the key map."""
    world = {'pixels_per_meter': PIXELS_PER_METER, 'size_m': WORLD_SIZE_M,
             'canvas_px': CANVAS_SIZE_PX}
    return {'world': world, 'arrows': list(ARROWS), 'rotations': ROTATIONS,
            'cancel_key': CANCEL_KEY}


def _key(message: dict[str, Any]) -> dict[str, Any]:
    key = message.get('key')
    if key not in ARROWS and key not in ROTATIONS and key != CANCEL_KEY:
        raise ProtocolError(f'unknown key {key!r}')
    return {'turtle': name(message, 'turtle'), 'key': key}


CHECKERS: dict[str, Checker] = {'key': _key}

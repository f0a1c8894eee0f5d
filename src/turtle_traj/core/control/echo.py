"""turtlesim's velocity echo: the evidence of which command acted. Pure Python.

turtlesim's Pose reports the velocities in effect at its step: the linear one as a magnitude,
both in float32. The newest command sent whose values match the echo is the one acting. On a
straight line every command is the same, and an echo would match them all; so each command is
moved by a few float32 steps (a relative 4e-6 at most, towards the command before it) until its
echo is unlike any other remembered, and the echo names the command in effect on any path.
"""

from __future__ import annotations

import struct
from collections.abc import Container

import numpy as np

from turtle_traj.core.control.commands import STOP, Command

Echo = tuple[float, float]  # (|linear|, angular) as float32 values
STANDING: Echo = (0.0, 0.0)  # a turtle that stands: a stop in effect, or no command yet
HISTORY = 32  # commands remembered: far more than any latency we can steer through
# Relative: more than `distinct` moves a command (4e-6); commands closer than this act alike.
ALIKE = 1e-5


_FLOAT32 = struct.Struct('<f')
_BITS = struct.Struct('<I')
_SIGN = 0x80000000
_LARGEST = 3.4028234663852886e38  # float32's; beyond, a value is not moved


def _float32(value: float) -> float:
    """`value` rounded to float32, as a Python float (numpy's `float32` costs 10 times more)."""
    if abs(value) > _LARGEST:
        return float(np.float32(value))
    return _FLOAT32.unpack(_FLOAT32.pack(value))[0]


def _rank(value: float) -> int:
    """A float32 value's place among all float32 values: the next one up is one more."""
    bits = _BITS.unpack(_FLOAT32.pack(value))[0]
    return bits if bits < _SIGN else -(bits & ~_SIGN)


def _at_rank(rank: int) -> float:
    return _FLOAT32.unpack(_BITS.pack(rank if rank >= 0 else -rank | _SIGN))[0]


def as_echoed(command: Command) -> Echo:
    """The (linear_velocity, angular_velocity) a turtlesim pose reports for `command`."""
    return _float32(abs(command.linear)), _float32(command.angular)


def _with(command: Command, on_linear: bool, value: float) -> Command:
    return (Command(value, command.angular) if on_linear
            else Command(command.linear, value))


def distinct(command: Command, taken: Container[Echo], previous: Command) -> Command:
    """`command` moved by the fewest float32 steps that give it an echo not in `taken`: its
    speed (its turn rate, when it has no speed), towards `previous`, then on towards zero. So
    it keeps within any limit of speed it was within, and its change from `previous` grows by a
    few float32 steps at most. A stop stays a stop; so does a command that runs out of steps.
    The steps are counted on float32's ranks (`_rank`), as integers."""
    echoed = as_echoed(command)
    if command == STOP or echoed not in taken:
        return command
    on_linear = command.linear != 0.0
    exact = command.linear if on_linear else command.angular
    last = previous.linear if on_linear else previous.angular
    if max(abs(exact), abs(last)) > _LARGEST:
        return command
    rank, towards = _rank(exact), _rank(last)
    if abs(_at_rank(rank) - last) > abs(exact - last):  # rounded away from the previous one
        rank += (towards > rank) - (towards < rank)
    value = _first_free(rank, towards, taken, on_linear, echoed[1] if on_linear else echoed[0])
    return command if value is None else _with(command, on_linear, value)


def _first_free(rank: int, towards: int, taken: Container[Echo], on_linear: bool,
                other: float) -> float | None:
    """The first float32 value from `rank` on, a rank at a time towards `towards` and then on
    towards zero, whose echo is not `taken` (the value on one side of it, `other` on the
    other; a float32's echo is itself); None within `HISTORY` + 1 steps or at zero. A
    steady command walks past the dozen ranks its forerunners took, so each rank costs one
    lookup and no call beyond `_at_rank`."""
    for _ in range(HISTORY + 1):
        value = _at_rank(rank)
        if ((abs(value), other) if on_linear else (other, value)) not in taken:
            return value
        towards = 0 if rank == towards else towards
        rank += (towards > rank) - (towards < rank)
        if rank == 0:
            break
    return None


def alike(command: Command, other: Command) -> bool:
    """Whether one command acts as the other does, to the few float32 steps `distinct` moves
    it: a step that holds `other` in place of `command` drives the robot the same."""
    return all(abs(a - b) <= ALIKE * max(abs(a), abs(b))
               for a, b in ((command.linear, other.linear), (command.angular, other.angular)))

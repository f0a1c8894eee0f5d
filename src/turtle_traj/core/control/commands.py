"""Velocity commands, as a controller sends them and turtlesim applies them."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Command:
    """A velocity command: forward speed (m/s) and turn rate (rad/s, counter-clockwise)."""

    linear: float = 0.0
    angular: float = 0.0


STOP = Command()

# How long a command may take to be delivered (s): the lifespan its publisher gives it (a command
# still undelivered then is dropped, not driven on seconds late after a cut link).
COMMAND_LIFESPAN_S = 0.2

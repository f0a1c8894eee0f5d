"""turtlesim's contract, as its users see it: the world's size, the spawn point, the time step,
the default pen and the topics' QoS numbers (turtlesim 1.8). Pure data: the simulator, the
controller and the settings all take these numbers from here."""

from __future__ import annotations

import struct
from dataclasses import dataclass

PIXELS_PER_METER = 45.0
CANVAS_SIZE_PX = 500
WORLD_SIZE_M = (CANVAS_SIZE_PX - 1) / PIXELS_PER_METER
# turtlesim keeps the height as a float (11.088889122): its canvas flips y about that value,
# which puts a line at a whole metre a hair below the pixel edge (what its pen scan shows).
CANVAS_HEIGHT_M = struct.unpack('f', struct.pack('f', WORLD_SIZE_M))[0]
SPAWN_XY_M = 5.544444561004639  # float32 of WORLD_SIZE_M / 2, as real turtlesim publishes it
STEP_S = 0.016  # the simulation step: one pose per turtle per step
COMMAND_TIMEOUT_S = 1.0  # a turtle stops this long after its last cmd_vel
TOPIC_QOS_DEPTH = 7  # pose, cmd_vel, color_sensor: reliable, keep last 7 (qos.hpp)


@dataclass(frozen=True)
class PenStyle:
    """The pen set_pen sets: colour and width in pixels (turtlesim cannot be asked for it)."""

    r: int
    g: int
    b: int
    width: int

    @property
    def hex(self) -> str:
        return f'#{self.r:02x}{self.g:02x}{self.b:02x}'


DEFAULT_PEN = PenStyle(179, 184, 255, 3)


def turtle_topic(turtle: str, name: str) -> str:
    """A turtle's topic or service, `<turtle>/<name>` (`turtle1/pose`); just `name` for a turtle
    left unnamed, whose topics are the node's namespace's own (a node in `/turtle2` drives
    `/turtle2/pose`)."""
    return f'{turtle}/{name}' if turtle else name

"""turtlesim's `turtle_teleop_key` mapping, as data: keys to velocity commands and rotate goals.

Shared by the terminal teleop (`turtle-traj teleop`) and the browser's keys. Pure Python.
"""

from __future__ import annotations

SCALE_LINEAR = 2.0  # turtle_teleop_key's parameters scale_linear and scale_angular
SCALE_ANGULAR = 2.0

# Arrow keys: (linear, angular) before scaling. The terminal sees the last byte of the arrow's
# escape sequence (ESC [ A ...), which turtle_teleop_key reads alone: capital A-D drive too.
ARROWS = {'up': (1.0, 0.0), 'down': (-1.0, 0.0), 'left': (0.0, 1.0), 'right': (0.0, -1.0)}
ARROW_BYTES = {'A': 'up', 'B': 'down', 'C': 'right', 'D': 'left'}

# The keys around F on a QWERTY keyboard: the direction from F is the heading asked for, in
# turtle_teleop_key's own rounded radians.
ROTATIONS = {'g': 0.0, 't': 0.7854, 'r': 1.5708, 'e': 2.3562, 'd': 3.1416, 'c': -2.3562,
             'v': -1.5708, 'b': -0.7854}
CANCEL_KEY = 'f'
QUIT_KEY = 'q'


def velocity(arrow: str, scale_linear: float = SCALE_LINEAR,
             scale_angular: float = SCALE_ANGULAR) -> tuple[float, float]:
    """The (linear.x, angular.z) one press of `arrow` ('up', 'down', 'left', 'right') sends."""
    linear, angular = ARROWS[arrow]
    return linear * scale_linear, angular * scale_angular

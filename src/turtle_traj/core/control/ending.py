"""Why a run ended, or why a request was refused: one reason beside its message, for clients
that act on it (the message says it in words, for people). Pure Python.

The responses and results carry it as `turtle_traj_interfaces/msg/Ending`, whose constants
are these members' names.
"""

from __future__ import annotations

from enum import Enum


class Ending(Enum):
    """The reason a run ended or a request was refused; the value is its label."""

    SUCCEEDED = 'succeeded'
    INVALID_REQUEST = 'invalid request'  # numbers that cannot be planned, an unknown name
    BUSY = 'busy'  # another request is running or being planned
    NO_SIMULATOR = 'no simulator'  # nothing hears the commands, a service of it is missing
    STOPPED = 'stopped'  # by request: ~/stop, ~/reset
    CANCELLED = 'cancelled'  # the action's goal was cancelled
    NO_PROGRESS = 'no progress'  # along the path for progress_timeout
    TIMED_OUT = 'timed out'  # the run took longer than it was given
    CONTROLLER_FAULT = 'controller fault'  # the controller raised, was slow or gave nonsense
    POSE_LOST = 'pose lost'  # no pose for pose_timeout
    POSE_JUMPED = 'pose jumped'  # teleported, reset, a second simulator
    OUT_OF_BOUNDS = 'out of bounds'  # the turtle came within the arena's margin
    REPLACED = 'replaced'  # a new path took over, the robot moving on (Nav2's FollowPath)
    SHUTTING_DOWN = 'shutting down'  # the node is going

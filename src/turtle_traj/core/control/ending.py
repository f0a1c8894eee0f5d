"""Why a run ended: one reason beside its message, for clients that act on it. Pure Python."""

from __future__ import annotations

from enum import Enum


class Ending(Enum):
    """The reason a run ended (its message says it in words)."""

    SUCCEEDED = 'succeeded'
    STOPPED = 'stopped'  # by request: ~/stop, a cancel, a stop before it started
    NO_PROGRESS = 'no progress'  # along the path for progress_timeout
    WALL = 'wall'  # the turtle came within the arena's margin
    POSE_JUMPED = 'pose jumped'  # teleported, reset, a second simulator
    CONTROLLER_FAULT = 'controller fault'  # the controller raised, was slow or gave nonsense
    ABORTED = 'aborted'  # the node's own reasons: poses lost, the pen, a shutdown

"""Where a fleet's drawing starts. Pure.

One turtle draws the next request from where it stands. A fleet's first turtle parks off the
drawing it started, so the next drawing starts where the last one did while that turtle still
stands where it parked (as if it had gone back there); once it is moved, where it stands.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from turtle_traj.core.geometry.path import Pose2D

KEPT_M = 0.05  # the first turtle stands this near where it parked: it was not moved since


@dataclass(frozen=True)
class Anchor:
    """Where the last drawing started (`start`), and where its first turtle then parked."""

    turtle: str
    start: Pose2D
    parked: Pose2D


def drawing_start(anchor: Anchor | None, turtle: str, pose: Pose2D) -> Pose2D:
    """Where a drawing whose first turtle is `turtle`, standing at `pose`, starts."""
    if (anchor is not None and anchor.turtle == turtle
            and math.dist((pose.x, pose.y), (anchor.parked.x, anchor.parked.y)) <= KEPT_M):
        return anchor.start
    return pose

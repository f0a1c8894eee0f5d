"""What the simulator saw of a run, kept for a grader: every turtle's pose after each step, the
pen's segments, and the services called that move a turtle other than by driving it or wipe
the drawing (a teleport, a clear, a reset, a kill, a spawn). A submission cannot reach it: the
simulator writes it, and the drawing is judged from it (`core.grading.judge`). Plain data; no
ROS."""

from __future__ import annotations

import json
from collections.abc import Iterable
from pathlib import Path

from turtle_traj.sim.state import Segment, Turtle


class RunRecord:
    """The simulator's record of a run (see the module)."""

    def __init__(self) -> None:
        # by turtle: (time s, x, y, theta, linear m/s, angular rad/s) after each step
        self.poses: dict[str, list[tuple[float, ...]]] = {}
        self.segments: list[tuple[float, float, float, float, float]] = []  # time, x0, y0, x1, y1
        self.calls: list[tuple[float, str, str]] = []  # time s, service, turtle ('' for all)

    def stepped(self, time_s: float, turtles: Iterable[Turtle],
                segments: Iterable[Segment]) -> None:
        """A step: the turtles where it left them, and what the pen drew in it."""
        for turtle in turtles:
            self.poses.setdefault(turtle.name, []).append(
                (time_s, turtle.x, turtle.y, turtle.theta, turtle.linear_speed, turtle.omega))
        self.segments += [(time_s, *segment.start, *segment.end) for segment in segments]

    def called(self, time_s: float, service: str, turtle: str = '') -> None:
        self.calls.append((time_s, service, turtle))

    def as_dict(self) -> dict:
        return {'poses': self.poses, 'segments': self.segments, 'calls': self.calls}

    def save(self, path: Path) -> None:
        """Write the record as JSON to `path`."""
        path.write_text(json.dumps(self.as_dict()), encoding='utf-8')

"""The request a node is planning: made beside its executor (`rosutils.offload`), one at a time,
and dropped when a stop, a cancel or a shutdown ends the request first."""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Any

from rclpy.node import Node
from rclpy.task import Future

from turtle_traj.core.control.ending import Ending
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import Settings
from turtle_traj.core.planning import planner
from turtle_traj.rosutils.offload import Offloader


@dataclass
class Planning:
    """A request being planned: its trajectory, the request, the settings it is planned with,
    the plan's future (cancelled if the request ended first), and how and why it ended then."""
    name: str
    request: Any
    settings: Settings
    plan: Future
    ended: str = ''
    reason: Ending = Ending.STOPPED


class PlanDesk:
    """Plans `node`'s requests beside its executor; `current` is the one being planned."""

    def __init__(self, node: Node) -> None:
        self._offloader = Offloader(node, 'plan')
        self.current: Planning | None = None

    def begin(self, trajectory: str, request: Any, start: Pose2D | None,
              settings: Settings, start_speed: float = 0.0) -> Planning:
        """Start planning `request` from `start` (the robot moving at `start_speed`, when the
        plan takes over from a run); it becomes `current`."""
        self.current = Planning(trajectory, request, settings, self._offloader.submit(
            partial(planner.plan, trajectory, request, start, settings,
                    start_speed=start_speed)))
        return self.current

    def done(self, planning: Planning) -> None:
        """`planning`'s plan was handed over (or failed): it is no longer current."""
        if self.current is planning:
            self.current = None

    def drop(self, ended: str, reason: Ending, request: Any = None) -> str | None:
        """End the current plan's request ('<trajectory> <ended>') for `reason`, if one is
        being planned (for `request` only, if given); its trajectory's name, or None."""
        planning = self.current
        if planning is None or (request is not None and planning.request is not request):
            return None
        self.current = None
        planning.ended, planning.reason = ended, reason
        planning.plan.cancel()
        return planning.name

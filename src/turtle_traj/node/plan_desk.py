"""The request a node is planning: made beside its executor (`rosutils.offload`), one at a time,
and dropped when a stop, a cancel or a shutdown ends the request first. The plan's message on
~/plan is made beside the executor too: a path of thousands of points takes tens of
milliseconds to turn into messages, which at the run's start would hold its first commands."""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Any

from nav_msgs.msg import Path as PathMsg
from rclpy.node import Node
from rclpy.task import Future
from std_msgs.msg import Header

from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import Settings
from turtle_traj.core.planning import planner
from turtle_traj.node.outcomes import PLAN_FRAME_ID, plan_message
from turtle_traj.rosutils.offload import Offloader


@dataclass
class Planning:
    """A request being planned: its trajectory, the request, the settings it is planned with,
    the plan's future (cancelled if the request ended first), the plan as nav_msgs/Path once
    planned (its header's stamp left to the publisher), and how and why it ended then."""
    name: str
    request: Any
    settings: Settings
    plan: Future | None = None
    message: PathMsg | None = None
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
        planning = Planning(trajectory, request, settings)
        planning.plan = self._offloader.submit(partial(
            _planned, planning, start, start_speed))
        self.current = planning
        return planning

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


def _planned(planning: Planning, start: Pose2D | None, start_speed: float) -> Plan:
    """`planning`'s plan, and its message (beside the executor: see the module)."""
    plan = planner.plan(planning.name, planning.request, start, planning.settings,
                        start_speed=start_speed)
    planning.message = plan_message(plan.path, Header(frame_id=PLAN_FRAME_ID))
    return plan

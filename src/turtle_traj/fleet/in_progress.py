"""A fleet's drawing under way, and what the coordinator reports of it: feedback and result."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from rclpy.action.server import ServerGoalHandle
from rclpy.task import Future
from turtle_traj_interfaces.action import FleetDraw

from turtle_traj.core.control.ending import Ending
from turtle_traj.core.fleet.run import FleetRun
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.turtlesim_contract import PenStyle
from turtle_traj.fleet.link import TurtleLink
from turtle_traj.node.outcomes import ending_message


@dataclass
class DrawingInProgress:
    """The drawing under way: its run, its turtles and how to report it."""

    run: FleetRun
    links: list[TurtleLink]
    pens: list[PenStyle]  # each turtle's
    linear_speed: float
    goal: ServerGoalHandle
    started_s: float  # when the goal came
    left_out: list[str]
    homes: list[Pose2D]  # where each turtle started (where a lost one is carried, if clear)
    anchor: Pose2D  # where the drawing starts, as one turtle would start it
    moving_s: float  # when the first moves could go
    finished: Future = field(default_factory=Future)
    to_carry: set[int] = field(default_factory=set)  # lost turtles to put out of the way
    carrying: set[int] = field(default_factory=set)  # lost turtles being put there
    min_distance: float = math.inf
    ended_s: float = 0.0  # when the timer found every piece drawn and every turtle parked
    ticks: int = 0
    failure: tuple[str, Ending] | None = None


def progress(drawing: DrawingInProgress, now_s: float) -> FleetDraw.Feedback:
    """The feedback: progress overall and per turtle, and the closest two turtles so far."""
    run = drawing.run
    return FleetDraw.Feedback(
        progress=run.progress(), elapsed=now_s - drawing.started_s,
        min_distance=drawing.min_distance, turtles=[link.name for link in drawing.links],
        turtle_progress=[run.turtle_progress(index) for index in range(len(drawing.links))],
        state=[_state(run, index) for index in range(len(drawing.links))])


def report(drawing: DrawingInProgress, now_s: float) -> FleetDraw.Result:
    """The result, with the goal's end status set (succeeded, cancelled or aborted)."""
    run, goal = drawing.run, drawing.goal
    success, reason, what = _verdict(drawing)
    parts = [what] + [f'{r.name} lost ({r.lost})' for r in run.turtles if r.lost]
    parts += [f'left out {why}' for why in drawing.left_out]
    sharing = run.first_sharing
    result = FleetDraw.Result(
        success=success, message='; '.join(parts), ending=ending_message(reason),
        makespan=(drawing.ended_s or now_s) - drawing.started_s,
        start_delay=drawing.moving_s - drawing.started_s,
        planned_makespan=run.planned_makespan_s,
        lower_bound=sharing.lower_bound_s if sharing else 0.0,
        min_distance=drawing.min_distance if math.isfinite(drawing.min_distance) else 0.0,
        turtles=[r.name for r in run.turtles], pieces=[r.pieces for r in run.turtles],
        max_deviation=[r.max_deviation for r in run.turtles],
        lost=[r.lost for r in run.turtles], left_out=drawing.left_out)
    if goal.is_cancel_requested:
        goal.canceled()
    elif success:
        goal.succeed()
    else:
        goal.abort()
    return result


def _verdict(drawing: DrawingInProgress) -> tuple[bool, Ending, str]:
    run = drawing.run
    if drawing.failure is not None:
        return False, drawing.failure[1], drawing.failure[0]
    if not run.done:
        return False, Ending.NO_PROGRESS, 'every turtle was lost'
    if run.blocked:
        numbers = ', '.join(str(index + 1) for index in sorted(run.blocked))
        return False, Ending.NO_PROGRESS, (
            f'{len(run.blocked)} of {len(run.pieces)} pieces left undrawn (pieces {numbers}, '
            'in drawing order): they pass within the clearance of a turtle that stands where '
            'it was lost')
    return True, Ending.SUCCEEDED, 'drawn'


def _state(run: FleetRun, index: int) -> str:
    if run.turtles[index].lost:
        return 'lost'
    if run.driving(index):
        return 'driving'
    return 'done' if run.turtle_progress(index) >= 1.0 else 'waiting'


def refusal(message: str, reason: Ending) -> FleetDraw.Result:
    """The result of a goal refused before any turtle moved."""
    return FleetDraw.Result(success=False, message=message, ending=ending_message(reason))

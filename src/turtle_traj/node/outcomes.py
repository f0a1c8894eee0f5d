"""How a run is reported: a refusal, and an Outcome copied into our responses and results."""

from __future__ import annotations

import math

from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path as PathMsg
from turtle_traj_interfaces.msg import Ending as EndingMsg

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.control.supervisor import Outcome
from turtle_traj.core.geometry.path import Path, Pose2D

PLAN_FRAME_ID = 'world'
PLAN_POINTS = 20_000  # most points published on ~/plan


class RunRefused(Exception):
    """A request that cannot run now: the message says why (busy, bad numbers, no simulator),
    and `reason` is that why as an `Ending`."""

    def __init__(self, message: str, reason: Ending) -> None:
        super().__init__(message)
        self.reason = reason

    def outcome(self, pose: Pose2D | None) -> Outcome:
        """The refusal as the outcome of a run that never started, the turtle at `pose`."""
        return Outcome(False, str(self), self.reason, pose)


def ending_message(reason: Ending) -> EndingMsg:
    """`reason` as the responses carry it: the constant of the same name, and its label."""
    return EndingMsg(code=getattr(EndingMsg, reason.name), label=reason.value)


def fill_response(response, outcome: Outcome):
    """Copy an outcome into any of our service responses or the Draw result (they share these
    fields)."""
    response.success = outcome.success
    response.message = outcome.message
    response.ending = ending_message(outcome.reason)
    if outcome.pose is not None:
        response.final_x, response.final_y = outcome.pose.x, outcome.pose.y
        response.final_theta = outcome.pose.theta
    response.elapsed = outcome.elapsed_s
    response.path_length = outcome.path_length
    response.driven_length = outcome.driven_length
    response.max_deviation = outcome.max_deviation
    response.final_error = outcome.final_error
    response.final_heading_error = outcome.final_heading_error
    if hasattr(response, 'pen_up_length'):  # drawings (text, svg) and the draw action
        response.pen_up_length = outcome.pen_up_length
        response.pen_up_unordered = outcome.pen_up_unordered
    return response


def plan_message(path: Path, header) -> PathMsg:
    """The planned path as nav_msgs/Path: every point up to PLAN_POINTS (a Lissajous curve has
    12 000); beyond, evenly thinned, its last point kept."""
    msg = PathMsg()
    msg.header = header
    points = path.points()
    stride = math.ceil(len(points) / PLAN_POINTS)
    for index in [*range(0, len(points) - 1, stride), len(points) - 1]:
        stamped = PoseStamped()
        stamped.header = header
        stamped.pose.position.x, stamped.pose.position.y = (float(v) for v in points[index])
        msg.poses.append(stamped)
    return msg


def summary(outcome: Outcome) -> str:
    """The outcome in one log line, with its figures."""
    return (f'{outcome.message} (elapsed {outcome.elapsed_s:.2f} s, max deviation '
            f'{outcome.max_deviation:.4f} m, final error {outcome.final_error:.4f} m, '
            f'heading error {outcome.final_heading_error:.4f} rad)')


def describe(plan: Plan, control: ControlConfig) -> str:
    """A plan in one log line: its length, its turns in place, its least duration."""
    path = plan.path
    return (f'{path.length:.2f} m of path, {math.degrees(path.turning):.0f} deg of turns in '
            f'place, at least {plan.least_time_s(control):.1f} s')

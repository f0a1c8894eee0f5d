"""The rules that end a trajectory run, and how it is reported. Pure Python.

A `RunSupervisor` wraps the follower of one plan. It aborts when the pose jumps (a teleport,
a reset, a second simulator), stops a turtle heading into a wall it did not start next to,
ends a run that makes no progress along its path for `progress_timeout_s` (a base slower
than its configured limits hunting around a corner), lets the turtle settle once the path is
done, and assembles the `Outcome` the services report.
The node feeds it poses, the control tick and requests; times are the node clock's seconds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from turtle_traj.core.control.commands import STOP, Command
from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.control.prediction import Prediction
from turtle_traj.core.control.walker import ControllerFault, PlanWalker
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.projection import PathDeviation
from turtle_traj.core.geometry.shapes import Arena
from turtle_traj.core.turtlesim_contract import STEP_S

SETTLE_PERIODS = 10  # control periods to wait for the turtle to report rest
# Three times the farthest a turtle at 10 m/s moves in one 16 ms step: longer is a jump.
MAX_POSE_JUMP_M = 0.5
PROGRESS_STEP = 1e-3  # of a leg: less is no progress (a hunt back and forth makes none)


@dataclass
class Outcome:
    """How a trajectory ended, as the service response reports it."""

    success: bool
    message: str
    reason: Ending
    pose: Pose2D | None = None
    elapsed_s: float = 0.0
    path_length: float = 0.0
    max_deviation: float = 0.0
    final_error: float = 0.0
    final_heading_error: float = 0.0
    pen_up_length: float = 0.0
    pen_up_unordered: float = 0.0
    clamped_percent: float = 0.0  # the controller's commands the node clamped to the limits
    driven_length: float = 0.0  # how far along the path the robot got, in order [m]


def wall_clearance(arena: Arena, pose: Pose2D) -> float:
    """Distance from the pose to the nearest edge of the arena (before its margin)."""
    return min(pose.x - arena.min_x, arena.max_x - pose.x,
               pose.y - arena.min_y, arena.max_y - pose.y)


class RunSupervisor:
    """One plan being driven: its follower, and the verdict once the run is over.

    `ending` is None while the run goes on, then (success, message), with `reason` why; after
    that `command` returns STOP only. Single-threaded by design: the node calls it from one
    executor thread.
    """

    def __init__(self, plan: Plan, follower: PlanWalker, *, start: Pose2D, arena: Arena,
                 started_s: float) -> None:
        """:param follower: the plan's walker, with the run's controller."""
        self.plan = plan
        self.started_s = started_s
        self.ending: tuple[bool, str] | None = None
        self.reason: Ending | None = None
        self.follower = follower
        self._start_clearance = wall_clearance(arena, start)
        self._settled_periods = 0
        self._pose = start
        self._path_done_s: float | None = None  # when the follower reached the path's end
        # when the first command was asked for: the clock read as the run starts can be behind
        # (a simulated clock whose messages waited in the executor's queue)
        self._first_command_s: float | None = None
        self._deviation = PathDeviation(plan.drawn_points())  # every pose's, as it comes
        self.distance = 0.0  # driven so far, pose to pose
        self._config: tuple[ControlConfig, ControlConfig] | None = None  # node's, this run's
        self._best_mark = (0, 0.0)  # the furthest the follower got, and when
        self._best_mark_s = started_s

    @property
    def name(self) -> str:
        return self.plan.trajectory

    def end(self, success: bool, message: str, reason: Ending) -> None:
        """Decide the verdict and why (the first decision stands)."""
        if self.ending is None:
            self.ending = (success, message)
            self.reason = reason

    def request_stop(self, reason: Ending = Ending.STOPPED) -> None:
        """A stop request (`reason`: a stop, or a cancel): success for an endless trajectory
        (it ends only this way)."""
        self.end(self.plan.path.endless, f'{self.name} stopped by request', reason)

    @property
    def pen_wanted(self) -> bool | None:
        """The pen state (True: down) the run waits for before it moves on; None: none."""
        return self.follower.pen_wanted

    def pen_is(self, down: bool) -> None:
        """The simulator confirmed this pen state."""
        self.follower.pen_down = down

    def progress(self, config: ControlConfig) -> float:
        """How much of the plan is driven, 0 to 1 (see `PlanWalker.progress`)."""
        return self.follower.progress(self.plan.control(config))

    def distance_from_path(self, pose: Pose2D) -> float:
        """Distance from the planned path as drawn (every leg; a turn is its point)."""
        return self._deviation.distance(pose.x, pose.y)

    @property
    def deviation(self) -> float:
        """Distance from the path as drawn, at the last pose."""
        return self._deviation.last

    @property
    def max_deviation(self) -> float:
        """The largest distance from the path as drawn, over every pose so far."""
        return self._deviation.largest

    def observe(self, pose: Pose2D, silent_s: float = 0.0) -> None:
        """A new pose, `silent_s` after the one before (0: the next step's): measured against
        the path; a jump from the last one aborts the run. A jump is farther than
        `MAX_POSE_JUMP_M` a step: poses lost on the way (a link cut for a moment) leave a gap
        the turtle drove on through, not a jump."""
        jump = math.dist((self._pose.x, self._pose.y), (pose.x, pose.y))
        self._pose = pose
        if jump <= MAX_POSE_JUMP_M * max(silent_s / STEP_S, 1.0):
            self.distance += jump
            self._deviation.add(pose.x, pose.y)
        else:
            self.end(False, f'{self.name} aborted: the turtle jumped {jump:.2f} m between two '
                            'poses (teleported, reset, respawned, a second simulator in this '
                            'ROS domain, or this node fell behind the simulator)',
                     Ending.POSE_JUMPED)

    def command(self, pose: Pose2D, at_rest: bool, config: ControlConfig, arena: Arena,
                now_s: float, prediction: Prediction | None = None) -> Command:
        """The command for this control period; may decide the verdict.

        :param at_rest: the last pose shows the robot at rest (`RobotModel.at_rest`).
        :param prediction: the model's prediction for this period (`RobotModel.predict`).
        :param config: the node's control settings (the plan's speeds override them).
        :param now_s: the node clock, seconds.
        """
        if self._first_command_s is None:
            self._first_command_s = now_s
        if self.ending is not None:
            return STOP
        if self.follower.done:
            return self._settle(at_rest, now_s)
        if self._config is None or self._config[0] is not config:
            self._config = (config, self.plan.control(config))  # once per settings change
        hazard = self._hazard(pose, config, arena, now_s)
        if hazard is not None:
            self.end(False, *hazard)
            return STOP
        try:
            return self.follower.update(pose, self._config[1], prediction)
        except ControllerFault as fault:
            self.end(False, f'{self.name} aborted: {fault}', Ending.CONTROLLER_FAULT)
            return STOP

    def watch(self, pose: Pose2D, config: ControlConfig, arena: Arena, now_s: float) -> None:
        """A period with no command sent (commands wait at the robot): end the run if it must
        end all the same (a wall ahead, no progress for too long)."""
        if self.ending is None and not self.follower.done:
            hazard = self._hazard(pose, config, arena, now_s)
            if hazard is not None:
                self.end(False, *hazard)

    def _settle(self, at_rest: bool, now_s: float) -> Command:
        """The path is done: wait for the turtle to report rest (or enough periods)."""
        if self._path_done_s is None:
            self._path_done_s = now_s
        self._settled_periods += 1
        if at_rest or self._settled_periods > SETTLE_PERIODS:
            self.end(True, f'{self.name} done{self.follower.report()}', Ending.SUCCEEDED)
        return STOP

    def _hazard(self, pose: Pose2D, config: ControlConfig, arena: Arena,
                now_s: float) -> tuple[str, Ending] | None:
        """Why the run must end now (a wall ahead, no progress), or None."""
        clearance = wall_clearance(arena, pose)
        if clearance < arena.margin / 2 and clearance < self._start_clearance:
            return (f'{self.name} stopped: the turtle came within {clearance:.3f} m of the wall '
                    f'at ({pose.x:.2f}, {pose.y:.2f})', Ending.OUT_OF_BOUNDS)
        if not self._stalled(now_s, config.progress_timeout_s):
            return None
        why = ('the base does not follow the commands as fast as max_linear_accel and '
               'max_angular_accel say (lower them)' if config.limited else
               'a base that cannot change speed at once needs max_linear_accel and '
               'max_angular_accel set')
        return (f'{self.name} aborted: no progress along the path for '
                f'{config.progress_timeout_s:g} s, {self.distance_from_path(pose):.3f} m from '
                f'it: {why}, or something holds it', Ending.NO_PROGRESS)

    def _stalled(self, now_s: float, timeout_s: float) -> bool:
        """No progress since `timeout_s` ago. A new leg, a new lap of an endless loop or a
        wait for the pen counts as progress."""
        leg, fraction = self.follower.mark
        best_leg, best_fraction = self._best_mark
        if (leg > best_leg or fraction >= best_fraction + PROGRESS_STEP
                or fraction < best_fraction - 0.5 or self.follower.pen_wanted is not None):
            self._best_mark, self._best_mark_s = (leg, fraction), now_s
        return now_s - self._best_mark_s > timeout_s

    def outcome(self, pose: Pose2D | None, now_s: float) -> Outcome:
        """The report of the run once `ending` is decided.

        Elapsed time runs from the first command to the path's end (not the settling after it)
        or to the stop. A run that reached its end reports the miss of its end point and end
        heading; one ended early reports its distance from the path, and no heading error. One
        reported before it ended is reported as out of time.
        """
        success, message = self.ending or (False, f'{self.name} still running')
        reason = self.reason or Ending.TIMED_OUT
        path = self.plan.path
        ended_s = self._path_done_s if self._path_done_s is not None else now_s
        began_s = self.started_s if self._first_command_s is None else self._first_command_s
        outcome = Outcome(
            success, message, reason, pose, elapsed_s=max(ended_s - began_s, 0.0),
            path_length=self.distance if path.endless else path.length,
            max_deviation=self.max_deviation, final_error=math.nan,
            pen_up_length=path.pen_up_length, pen_up_unordered=self.plan.pen_up_unordered,
            clamped_percent=self.follower.clamped_percent,
            driven_length=self.follower.driven_m)
        if pose is None:
            return outcome
        if self.follower.done:
            outcome.final_error = math.dist((pose.x, pose.y), path.end)
            outcome.final_heading_error = wrap_angle(pose.theta - path.end_heading)
        else:
            outcome.final_error = self.distance_from_path(pose)
        return outcome

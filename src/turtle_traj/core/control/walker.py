"""A plan driven by any `Controller`, the node's exact follower included. Pure Python.

`PlanWalker` walks the plan's steps: strokes, which the controller drives, and turns in place,
which the node makes (`trackers.TurnTracker`). A controller that `turns_at_corners` (the
exact follower) gets each stretch between two corners as a stroke; any other gets polylines
with the same pen joined across the corners between them, up to `MAX_CORNER_RAD`. The walker
keeps the pen as each stroke needs it, measures progress itself (the same for every
controller), starts the laps of an endless stroke, and sets the controller's tuning as each
stroke starts. A stroke driven backwards is shown to the controller as a forward one (the
pose turned round, its speeds mirrored). The walker, not the controller, judges that a
stroke's end (or an endless stroke's lap) is reached, as Nav2's goal checker does: a None from
the controller is accepted only once the stroke is driven in order to its end. Every command
is clamped to the limits and counted; an end claimed early, an exception, a non-finite
command, a wrong type or, with an `AnswerTimer`, `LATE_ANSWERS` answers in a row later than
the control period raise `ControllerFault`, which ends the run.
"""

from __future__ import annotations

import math
from bisect import bisect_left
from collections.abc import Callable, Mapping
from dataclasses import replace
from itertools import chain
from typing import Protocol

import numpy as np

from turtle_traj.core.control.commands import STOP, Command
from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.controller import ARRIVED_M, Controller, State, Stroke
from turtle_traj.core.control.drift import Tube
from turtle_traj.core.control.dynamics import within_reach
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.control.prediction import Prediction
from turtle_traj.core.control.trackers import TurnTracker
from turtle_traj.core.control.tuning import tune
from turtle_traj.core.geometry.path import Path, Polyline, Pose2D, Turn

_JOIN_M = 1e-6  # polylines whose ends meet this closely join into one stroke
# Answers later than the control period in a row that end the run. One late answer can be the
# process's: another of its threads holding Python's lock (a test runner's report, a logger)
# delays whoever waits for it; a controller that is slow is slow every time.
LATE_ANSWERS = 3
# A corner sharper than this (a path that doubles back on itself) ends a stroke: no
# look-ahead controller follows a reversal; the node turns there in place.
MAX_CORNER_RAD = math.radians(160.0)


class ControllerFault(Exception):
    """The controller did something the node will not drive: the message says what."""


def _joins(before: Polyline, after: Polyline) -> bool:
    return (before.pen == after.pen and before.reverse == after.reverse
            and not before.repeat and not after.repeat
            and math.dist(before.points[-1], after.points[0]) <= _JOIN_M)


def _inside_a_stroke(turn: Turn, before: object, after: object) -> bool:
    """A turn at a corner that the controller drives round: between two polylines that join,
    no sharper than `MAX_CORNER_RAD`."""
    return (isinstance(before, Polyline) and isinstance(after, Polyline)
            and _joins(before, after) and abs(turn.sweep_rad) <= MAX_CORNER_RAD)


def strokes_of(path: Path) -> list[Polyline | Turn]:
    """The path's steps: strokes (polylines joined across the corners between them, up to
    `MAX_CORNER_RAD`) and the turns in place that are not such corners."""
    steps: list[Polyline | Turn] = []
    legs = path.legs
    for index, leg in enumerate(legs):
        previous = steps[-1] if steps else None
        if isinstance(leg, Turn):
            after = legs[index + 1] if index + 1 < len(legs) else None
            if not _inside_a_stroke(leg, previous, after):
                steps.append(leg)
        elif isinstance(previous, Polyline) and _joins(previous, leg):
            steps[-1] = Polyline(np.vstack([previous.points, leg.points[1:]]),
                                 reverse=leg.reverse, pen=leg.pen)
        else:
            steps.append(leg)
    return steps


class AnswerTimer(Protocol):
    """Times a controller's answers: `start` just before one is asked for, `took` just after
    it came: the seconds the controller is to blame for (the node's own timer leaves out the
    machine's, `node.answer_timer`); an answer within `within_s` of wall time may be given as
    its wall time (nothing left out could make it later than that)."""

    def start(self) -> object: ...

    def took(self, mark: object, within_s: float) -> float: ...


class _Along:
    """How far along a stroke a pose is (0 to 1 of a lap): the closest point from a little
    behind the last match to a little ahead of it (further than a robot drives in a period, or
    than the nearest point leaps where a controller cuts a sharp corner, too short to jump to a
    later part of the stroke that passes close by). On an endless stroke the window runs on
    round its start, into the next lap."""

    BEHIND_M, AHEAD_M = 0.05, 0.25

    def __init__(self, stroke: Polyline) -> None:
        self.segments = stroke.segments
        self.cumulative = stroke.cumulative_length.tolist()
        self.endless = stroke.repeat
        self.arc = 0.0
        self.last = 0.0  # the fraction last found

    def nearest(self, pose: Pose2D) -> tuple[int, float]:
        """The segment nearest `pose` and the fraction along it; `last` becomes its place."""
        index, along, _ = self._project(pose)
        cumulative = self.cumulative
        self.arc = cumulative[index] + along * (cumulative[index + 1] - cumulative[index])
        self.last = self.arc / max(cumulative[-1], 1e-12)
        return index, along

    def left_at(self, pose: Pose2D) -> float:
        """The arc from `pose`, found in the window of the last match, to the stroke's end;
        below zero past the end of an endless stroke's lap. `arc` stays as it is."""
        index, along, _ = self._project(pose)
        cumulative = self.cumulative
        arc = cumulative[index] + along * (cumulative[index + 1] - cumulative[index])
        if self.endless and arc < self.arc - self.BEHIND_M:  # round the start, into the next lap
            arc += cumulative[-1]
        return cumulative[-1] - arc

    def _project(self, pose: Pose2D) -> tuple[int, float, float]:
        cumulative, count = self.cumulative, self.segments.count
        total, ahead = cumulative[-1], self.arc + self.AHEAD_M
        first = max(bisect_left(cumulative, self.arc - self.BEHIND_M) - 1, 0)
        candidates = range(first, min(bisect_left(cumulative, ahead) + 1, count))
        if self.endless and ahead > total:  # round the start, into the next lap
            candidates = chain(candidates, range(min(bisect_left(cumulative, ahead - total) + 1,
                                                     count)))
        return self.segments.project(pose.x, pose.y, candidates)


class PlanWalker:
    """Drives `plan` with `controller`, a stroke at a time (see the module's docstring).

    With `manage_pen`, a stroke starts only once the pen is as it needs (`Polyline.pen`):
    until the caller reports that state in `pen_down`, the walker holds the robot with STOP and
    names the state it waits for in `pen_wanted` (unknown, None, at first).

    :param name: the controller's name, for the messages.
    :param tuning: the controller's tuning now, by name (the node's `<controller>.<name>`
        parameters); None: its `Tunable`s' defaults.
    """

    def __init__(self, plan: Plan, controller: Controller, name: str, *,
                 manage_pen: bool = False, timer: AnswerTimer | None = None,
                 tuning: Callable[[], Mapping[str, float]] | None = None) -> None:
        self.plan, self.controller, self.name = plan, controller, name
        self.tuning = tuning
        self.timer = timer  # None: untimed; else LATE_ANSWERS late answers end the run
        self.manage_pen = manage_pen
        self.pen_down: bool | None = None
        self.pen_wanted: bool | None = None
        corners = getattr(controller, 'turns_at_corners', False)
        self.steps = list(plan.path.legs) if corners else strokes_of(plan.path)
        # each step's speed profile, where a step is one leg of the plan, planned with it
        self._profiles = plan.profiles if corners else ()
        self._tube = Tube(plan.drawn_points(), plan.tolerance) if plan.tolerance > 0.0 else None
        self.step_index = 0
        self.commands = 0  # commands the controller gave
        self.clamped = 0  # of them, changed to stay within the limits
        self._turn: TurnTracker | None = None
        self._along: _Along | None = None
        self._lap = 0
        self._periods = 0  # commands asked for in this stroke
        self._late = 0  # answers in a row later than the period
        self._last_command = STOP  # for a caller without a model of the robot
        self._reach = ARRIVED_M  # the stroke's: how near its end counts as arrived
        self._driven_before = 0.0  # m of the strokes (and laps) finished

    @property
    def done(self) -> bool:
        return self.step_index >= len(self.steps)

    @property
    def mark(self) -> tuple[int, float]:
        """Where the walker is: its step, and how much of it is driven (0 to 1)."""
        if self._turn is not None:
            return self.step_index, self._turn.fraction
        return self.step_index, self._along.last if self._along else 0.0

    def progress(self, config: ControlConfig) -> float:
        """How much of the plan is driven, 0 to 1, each step weighted by its time at top
        speed (so turns in place count); an endless stroke shows its current lap's."""
        costs = [step.length / config.linear_speed if isinstance(step, Polyline)
                 else abs(step.sweep_rad) / config.angular_speed for step in self.steps]
        done = sum(costs[:self.step_index])
        if not self.done:
            done += self.mark[1] * costs[self.step_index]
        return min(done / max(sum(costs), 1e-12), 1.0)

    @property
    def driven_m(self) -> float:
        """How much of the path is driven, in order: the strokes (and laps) finished, and the
        arc along the stroke under way."""
        return self._driven_before + (self._along.arc if self._along is not None else 0.0)

    @property
    def clamped_percent(self) -> float:
        return 100.0 * self.clamped / max(self.commands, 1)

    def report(self) -> str:
        """How many of the controller's commands were clamped to the limits, if any were."""
        if not self.clamped:
            return ''
        return f' ({self.name}: {self.clamped} of {self.commands} commands clamped to the limits)'

    def update(self, pose: Pose2D, config: ControlConfig,
               prediction: Prediction | None = None) -> Command:
        """This period's command, steered from where the commands on their way will take the
        robot (`prediction`, from `RobotModel.predict`; without it each command is taken to
        act at once); STOP once done, or while the pen is not as it needs.

        :raises ControllerFault: the controller raised, answered late or out of type.
        """
        if prediction is None:
            prediction = Prediction.immediate(pose, self._last_command)
        self._last_command = command = self._next_command(pose, config, prediction)
        return command

    def _next_command(self, pose: Pose2D, config: ControlConfig,
                      prediction: Prediction) -> Command:
        while not self.done:
            step = self.steps[self.step_index]
            if isinstance(step, Turn):
                command = self._turn_in_place(step, pose, config, prediction)
            else:
                if self.manage_pen and step.pen != self.pen_down:
                    self.pen_wanted = step.pen
                    return STOP
                self.pen_wanted = None
                command = self._stroke(step, pose, config, prediction)
            if command is not None:
                return command
            self.step_index += 1
            self._turn, self._along, self._lap = None, None, 0
        return STOP

    def _turn_in_place(self, turn: Turn, pose: Pose2D, config: ControlConfig,
                       prediction: Prediction) -> Command | None:
        if self._turn is None:
            self._turn = TurnTracker(turn, pose)
        command = self._turn.update(pose, prediction, config)
        return None if command is None else within_reach(command, prediction.velocity,
                                                         config.limits)

    def _stroke(self, stroke: Polyline, pose: Pose2D, config: ControlConfig,
                prediction: Prediction) -> Command | None:
        flip = math.pi if stroke.reverse else 0.0
        if self._along is None:
            self._start(stroke, config)
        nearest = self._along.nearest(pose)
        seen, measured = prediction, pose
        if flip:  # the pose turned round, the speeds mirrored
            velocity = prediction.velocity
            seen = replace(prediction, pose=Pose2D(
                prediction.pose.x, prediction.pose.y, prediction.pose.theta + flip),
                velocity=Command(-velocity.linear, velocity.angular))
            measured = Pose2D(pose.x, pose.y, pose.theta + flip)
        state = State(seen, measured, self._periods * config.period_s, config.limits,
                      nearest)
        self._periods += 1
        answer = self._call('command', state, period_s=config.period_s)
        if answer is None:
            self._check_arrival(stroke, prediction.pose)
            self._driven_before += stroke.length
            if not stroke.repeat:
                return None
            self._lap += 1  # an endless stroke: the next lap starts next period
            self._along = None
            return STOP
        command = self._checked(answer)
        if flip:
            command = Command(-command.linear, command.angular)
        return self._clamped(command, prediction.velocity, config)

    def _start(self, stroke: Polyline, config: ControlConfig) -> None:
        """The controller's tuning set, and the stroke handed to it."""
        self._along, self._periods = _Along(stroke), 0
        if self.tuning is not None:
            tune(self.controller, self.tuning())
        last = self.step_index == len(self.steps) - 1
        tolerance = (self.plan.end_tolerance if last and self.plan.end_tolerance is not None
                     else config.position_tolerance)
        profile = self._profiles[self.step_index] if self._profiles else None
        self._reach = max(tolerance, ARRIVED_M)
        self._call('start', Stroke(stroke.points, self._lap, stroke.repeat, tolerance, profile,
                                   stroke, self._tube), config.limits)

    def _check_arrival(self, stroke: Polyline, pose: Pose2D) -> None:
        """The controller answered None: accept that the stroke's end (or an endless stroke's
        lap) is reached only where the predicted pose has come along the stroke, in order, to
        within `_reach` of its end and stands that close to its last point.

        :raises ControllerFault: a claim made before then.
        """
        left = self._along.left_at(pose)
        miss = math.dist((pose.x, pose.y), stroke.points[-1])
        if left <= self._reach and miss <= self._reach:
            return
        raise ControllerFault(
            f"controller '{self.name}' claimed the end after {self.driven_m:.2f} m of "
            f'{self.plan.path.length:.2f} m: {left:.3f} m of the stroke left, {miss:.3f} m '
            f'from its end (arrived is within {self._reach:.3f} m of it, along the stroke and '
            'straight)')

    def _call(self, method: str, *args, period_s: float | None = None):
        """The controller's answer; timed against `period_s` when one is given and the
        walker has a timer."""
        timer = self.timer if period_s is not None else None
        mark = timer.start() if timer is not None else None
        try:
            answer = getattr(self.controller, method)(*args)
        except Exception as error:  # the controller's fault, whatever it is
            raise ControllerFault(f"controller '{self.name}' raised {type(error).__name__} in "
                                  f'{method}(): {error}') from error
        if timer is not None:
            took = timer.took(mark, period_s)
            self._late = self._late + 1 if took > period_s else 0
            if self._late >= LATE_ANSWERS:
                raise ControllerFault(
                    f"controller '{self.name}' answered later than the control period "
                    f'({period_s:.3f} s) {self._late} times in a row, the last after {took:.3f} s')
        return answer

    def _checked(self, answer: object) -> Command:
        try:
            command = Command(float(answer.linear), float(answer.angular))
        except (AttributeError, TypeError, ValueError):
            raise ControllerFault(f"controller '{self.name}' returned {answer!r}, not a Command "
                                  '(linear, angular) or None') from None
        if not (math.isfinite(command.linear) and math.isfinite(command.angular)):
            raise ControllerFault(f"controller '{self.name}' returned a non-finite command "
                                  f'({command.linear} m/s, {command.angular} rad/s)')
        return command

    def _clamped(self, command: Command, previous: Command, config: ControlConfig) -> Command:
        self.commands += 1
        limited = within_reach(Command(
            max(-config.linear_speed, min(config.linear_speed, command.linear)),
            max(-config.angular_speed, min(config.angular_speed, command.angular))),
            previous, config.limits)
        if (abs(limited.linear - command.linear) > 1e-9
                or abs(limited.angular - command.angular) > 1e-9):
            self.clamped += 1
        return limited

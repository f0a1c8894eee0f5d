"""One path follower for every trajectory, leg by leg: in-place turns and polylines. Pure Python.

`PathFollower.update(pose, config, prediction)` returns the next velocity command, from the leg's
tracker (`trackers`). On a base with acceleration limits (`ControlConfig.limited`) every command
stays within reach of the one before (`dynamics`).

**A leg's tail.** turtlesim repeats the last command it took until the next one comes; a node
that falls behind for a few steps as a leg ends (a busy machine) would leave it repeating an
approach command past the end. So once the rest of a leg fits in the robot's queue
(`Prediction.room`, turtlesim's keep-last 7), the follower sends it at once, with the next
leg's first command behind it (`tail`): each acts one step, in order, whenever the node runs.
It does so only where the prediction is exact (turtlesim, no acceleration limits, a control
period of one step) and no command is expected late (`late_steps` 0): the tail is what the
follower would send step by step on the predicted poses, which lateness makes uncertain (and a
command held up on a link would hold back those behind it). Until the robot has taken the
tail, there is nothing to send; then the leg ends, unless one of its commands was dropped on the
way (`Prediction.dropped`).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Sequence

from turtle_traj.core.control.commands import STOP, Command
from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.dynamics import within_reach
from turtle_traj.core.control.prediction import Prediction
from turtle_traj.core.control.profile import SpeedProfile
from turtle_traj.core.control.trackers import UNPLANNED, PolylineTracker, TurnTracker, exact
from turtle_traj.core.geometry.path import Path, Polyline, Pose2D, Turn

# `distinct`: a command moved so its echo is unlike those already sent and those before it
Distinct = Callable[[Command, Sequence[Command]], Command]


class PathFollower:
    """Drives a Path leg by leg; `done` once the last leg is finished.

    With `manage_pen`, a polyline starts only once the pen is as it needs (`Polyline.pen`):
    until the caller reports that state in `pen_down`, the follower holds the turtle with STOP
    and names the state it waits for in `pen_wanted`. The pen's state is unknown (None) at
    first.
    """

    def __init__(self, path: Path, *, end_tolerance: float | None = None,
                 manage_pen: bool = False,
                 profiles: tuple[SpeedProfile | None, ...] = ()) -> None:
        """:param profiles: each leg's speed profile for a base with acceleration limits, planned
            with the request (`Plan.profiles`); without them a leg plans its own as it starts.
        """
        self.path = path
        self._profiles = profiles
        self.manage_pen = manage_pen
        self.pen_down: bool | None = None
        self.pen_wanted: bool | None = None
        self.leg_index = 0
        self._end_tolerance = end_tolerance
        self._tracker: TurnTracker | PolylineTracker | None = None
        self._last_command = STOP  # for a caller without a model of the robot
        self._tail_sent = False  # the rest of this leg, and the next one's start, are sent
        self._dropped_before_tail = 0  # commands dropped on the way before it (`Prediction`)

    @property
    def done(self) -> bool:
        return self.leg_index >= len(self.path.legs)

    @property
    def mark(self) -> tuple[int, float]:
        """Where the follower is: its leg, and how much of that leg is driven (0 to 1)."""
        return self.leg_index, self._tracker.fraction if self._tracker is not None else 0.0

    def progress(self, config: ControlConfig) -> float:
        """How much of the path is driven, 0 to 1, each leg weighted by its time at top speed
        (so turns in place count); an endless path shows the progress of its current lap."""
        costs = [leg.length / config.linear_speed if isinstance(leg, Polyline)
                 else abs(leg.sweep_rad) / config.angular_speed for leg in self.path.legs]
        done = sum(costs[:self.leg_index])
        if self._tracker is not None and not self.done:
            done += self._tracker.fraction * costs[self.leg_index]
        return min(done / max(sum(costs), 1e-12), 1.0)

    def update(self, pose: Pose2D, config: ControlConfig,
               prediction: Prediction | None = None) -> Command | None:
        """The command for this control period, steered from where the commands still on their
        way will take the turtle (`prediction`, from `RobotModel.predict`; without it each
        command is taken to act at once); STOP once done; None while a leg's tail is on its
        way (`tail`): nothing to send."""
        if prediction is None:
            prediction = Prediction.immediate(pose, self._last_command)
        if self._tail_sent:
            if prediction.in_flight > 1:  # more than the next leg's first command
                return None
            self._tail_sent = False
            # the leg ends with its tail taken; one dropped on the way (a link lost it past its
            # lifespan) left the turtle short, and the leg goes on
            if prediction.dropped == self._dropped_before_tail:
                self._next_leg()
                if prediction.queued:  # the next leg's first command (or a stop) is on its way
                    if not self.done:
                        self._start_leg(pose, config)  # a pen to change is asked for at once
                    return None
        command = within_reach(self._next_command(pose, prediction, config),
                               prediction.velocity, config)
        self._last_command = command
        return command

    def tail(self, pose: Pose2D, prediction: Prediction, config: ControlConfig,
             distinct: Distinct = lambda command, _: command) -> tuple[Command, ...]:
        """The commands to send this period instead of `update`'s: the rest of this leg and the
        next leg's first command, when the leg ends within the robot's queue as predicted; ()
        otherwise. `distinct` moves each as the robot model needs (`RobotModel.distinct`)."""
        if not self._may_tail(prediction, config):
            return ()
        trial = copy.copy(self)
        trial._tracker = copy.copy(self._tracker)
        commands: list[Command] = []
        for _ in range(prediction.room):
            leg = trial.leg_index
            commands.append(distinct(trial.update(pose, config, prediction), commands))
            if trial.leg_index != leg:  # ended: the last is the next leg's first (or a stop)
                if len(commands) < 2:
                    return ()
                self._tail_sent, self._dropped_before_tail = True, prediction.dropped
                return tuple(commands)
            prediction = prediction.then(commands[-1])
            pose = prediction.pose  # as predicted from here on
        return ()

    def _may_tail(self, prediction: Prediction, config: ControlConfig) -> bool:
        """The prediction is exact to the step, the queue has room for two commands or more,
        and the leg may end within it (`steps_left`, a guess: braking takes longer)."""
        return (not self.done and self._tracker is not None and prediction.room >= 2
                and exact(prediction, config) and prediction.late_steps == 0
                and math.isclose(config.period_s, prediction.step_s)
                and self._tracker.steps_left <= prediction.room)

    def _next_leg(self) -> None:
        self.leg_index += 1
        self._tracker = None

    def _next_command(self, pose: Pose2D, prediction: Prediction,
                      config: ControlConfig) -> Command:
        while not self.done:
            if self._tracker is None and not self._start_leg(pose, config):
                return STOP  # waiting for the pen
            command = self._tracker.update(pose, prediction, config)
            if command is not None:
                return command
            self._next_leg()
        return STOP

    def _start_leg(self, pose: Pose2D, config: ControlConfig) -> bool:
        """Track the current leg from `pose`; False while the pen is not yet as it needs."""
        leg = self.path.legs[self.leg_index]
        if self.manage_pen and isinstance(leg, Polyline) and leg.pen != self.pen_down:
            self.pen_wanted = leg.pen
            return False
        self.pen_wanted = None
        if isinstance(leg, Turn):
            self._tracker = TurnTracker(leg, pose)
            return True
        last = self.leg_index == len(self.path.legs) - 1
        tolerance = (self._end_tolerance if last and self._end_tolerance is not None
                     else config.position_tolerance)
        profile = self._profiles[self.leg_index] if self._profiles else UNPLANNED
        self._tracker = PolylineTracker(leg, tolerance, profile)
        return True

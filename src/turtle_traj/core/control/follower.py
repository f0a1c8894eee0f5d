"""One path follower for every trajectory, leg by leg: in-place turns and polylines. Pure Python.

`PathFollower.update(pose, config, prediction)` returns the next velocity command, from the leg's
tracker (`trackers`), steered from the pose predicted for the moment it takes effect
(`robot_model`). On a base with acceleration limits (`ControlConfig.limited`) every command
stays within reach of the one before (`dynamics`).
"""

from __future__ import annotations

from turtle_traj.core.control.commands import STOP, Command
from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.dynamics import within_reach
from turtle_traj.core.control.prediction import Prediction
from turtle_traj.core.control.profile import SpeedProfile
from turtle_traj.core.control.trackers import UNPLANNED, PolylineTracker, TurnTracker
from turtle_traj.core.geometry.path import Path, Polyline, Pose2D, Turn


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

    @property
    def clamped_percent(self) -> float:
        """None of its commands is clamped: it plans within the limits."""
        return 0.0

    def report(self) -> str:
        return ''

    def update(self, pose: Pose2D, config: ControlConfig,
               prediction: Prediction | None = None) -> Command:
        """The command for this control period, steered from where the commands still on their
        way will take the turtle (`prediction`, from `RobotModel.predict`; without it each
        command is taken to act at once); STOP once done."""
        if prediction is None:
            prediction = Prediction.immediate(pose, self._last_command)
        command = within_reach(self._next_command(pose, prediction, config),
                               prediction.velocity, config)
        self._last_command = command
        return command

    def _next_command(self, pose: Pose2D, prediction: Prediction,
                      config: ControlConfig) -> Command:
        while not self.done:
            if self._tracker is None and not self._start_leg(pose, config):
                return STOP  # waiting for the pen
            command = self._tracker.update(pose, prediction, config)
            if command is not None:
                return command
            self.leg_index += 1
            self._tracker = None
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

"""The node's exact follower, as a `Controller` like any other. Pure Python.

It drives one stroke between two corners (`turns_at_corners`: the node turns in place at each,
so corners are exact) with `trackers.PolylineTracker`: curvature feed-forward, a heading
set-point that steers back onto the path, speed capped by the curvature, the base's speed
profile and a braking that lands on the end point. It steers from the state the model of the
robot predicts, and allows for its uncertainty as the model answers it to every controller
(`State.robot`: `late_steps`, `overrun`, `braking_overrun`, `standing`). It asks only for
what the base can reach in one period (`dynamics.within_reach`), so the node clamps none of its
commands.

Its four gains (`exact_tuning`) are the node's own parameters of the same names
(`heading_gain`, ...): the walker sets them from the node's settings as each stroke starts.
"""

from __future__ import annotations

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.controller import Limits, State, Stroke
from turtle_traj.core.control.controllers.exact_tuning import ExactTuning
from turtle_traj.core.control.dynamics import within_reach
from turtle_traj.core.control.trackers import UNPLANNED, PolylineTracker
from turtle_traj.core.geometry.path import Polyline


class ExactFollower(ExactTuning):
    """Follows each stroke exactly, within the base's limits (see the module's docstring)."""

    turns_at_corners = True

    def __init__(self) -> None:
        self._tracker: PolylineTracker | None = None
        self._tolerance = 0.0
        self._limits: Limits | None = None
        self._config: ControlConfig | None = None  # the tracker's, for `_limits`

    def start(self, stroke: Stroke, limits: Limits) -> None:
        self._tolerance = stroke.tolerance
        self._configure(limits)
        profile = stroke.profile if stroke.profile is not None else UNPLANNED
        polyline = stroke.polyline or Polyline(stroke.points, repeat=stroke.endless)
        self._tracker = PolylineTracker(polyline, stroke.tolerance, profile)

    def command(self, state: State) -> Command | None:
        if state.limits is not self._limits:
            self._configure(state.limits)  # the node's parameters changed them
        nearest = state.nearest if state.nearest is not None else self._tracker.locate(
            state.measured)
        command = self._tracker.update(state.measured, state.robot, self._config, nearest)
        return None if command is None else within_reach(command, state.velocity, self._config)

    def _configure(self, limits: Limits) -> None:
        self._limits = limits
        self._config = ControlConfig(
            linear_speed=limits.linear_speed, angular_speed=limits.angular_speed,
            heading_gain=self.heading_gain, cross_track_gain=self.cross_track_gain,
            deceleration=self.deceleration, angular_deceleration=0.0,
            position_tolerance=self._tolerance, heading_tolerance=0.0,
            turn_first_angle=self.turn_first_angle, period_s=limits.period_s,
            max_linear_accel=limits.linear_accel, max_linear_decel=limits.linear_decel,
            max_angular_accel=limits.angular_accel)

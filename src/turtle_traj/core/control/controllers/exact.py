"""The node's exact follower, as a `Controller` like any other. Pure Python.

It drives one stroke between two corners (`turns_at_corners`: the node turns in place at each,
so corners are exact) with `trackers.PolylineTracker` (a motion planned in time with
`timed_tracker.TimedTracker`, on its clock): speed capped by the curvature, the
base's speed profile and a braking that lands on the end point; on turtlesim each step lands on
the curve (`curve_step`), on a base with inertia curvature feed-forward and a heading set-point
steer back onto the path. It steers from the state the model of the robot predicts, and
allows for its uncertainty as the model answers it to every controller
(`State.robot`: `late_steps`, `overrun`, `braking_overrun`, `standing`). It asks only for
what the base can reach in one period (`dynamics.within_reach`), so the node clamps none of its
commands.

Its four gains are `Tunable`s like any controller's, served by the node as
`exact.heading_gain`, `exact.cross_track_gain`, `exact.deceleration` and
`exact.turn_first_angle`.
"""

from __future__ import annotations

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.controller import Limits, State, Stroke
from turtle_traj.core.control.dynamics import within_reach
from turtle_traj.core.control.profile import SpeedProfile
from turtle_traj.core.control.timed_tracker import TimedTracker
from turtle_traj.core.control.trackers import UNPLANNED, PolylineTracker
from turtle_traj.core.control.tuning import Tunable
from turtle_traj.core.geometry.path import Polyline


class ExactFollower:
    """Follows each stroke exactly, within the base's limits (see the module's docstring)."""

    turns_at_corners = True
    heading_gain = Tunable(8.0, 'Turn rate per radian of heading error', '1/s', 0.1, 50.0)
    cross_track_gain = Tunable(2.5, 'How hard curves pull back onto the path, on a base with '
                               'acceleration limits (on turtlesim each step lands on the curve)',
                               '1/m', 0.0, 50.0)
    deceleration = Tunable(20.0, 'Braking towards the end of a curve, on a base without '
                           'acceleration limits (with them, max_linear_decel or '
                           'max_linear_accel brakes)', 'm/s^2', 0.1, 100.0)
    turn_first_angle = Tunable(0.6, 'Heading error beyond which the turtle turns before '
                               'driving', 'rad', 0.05, 3.14159)

    def __init__(self) -> None:
        self._tracker: PolylineTracker | None = None

    def start(self, stroke: Stroke, limits: Limits) -> None:
        profile = stroke.profile if stroke.profile is not None else UNPLANNED
        polyline = stroke.polyline or Polyline(stroke.points, repeat=stroke.endless)
        if (isinstance(profile, SpeedProfile) and profile.times is not None
                and limits.limited):  # a motion planned in time: kept to its clock
            self._tracker = TimedTracker(polyline, stroke.tolerance, profile)
        else:
            self._tracker = PolylineTracker(polyline, stroke.tolerance, profile, stroke.tube)

    def command(self, state: State) -> Command | None:
        nearest = state.nearest if state.nearest is not None else self._tracker.locate(
            state.measured)
        command = self._tracker.update(state.measured, state.robot, state.limits, self,
                                       nearest)
        # the profile keeps the path's turn within reach: only the steering is clamped; a
        # motion planned in time at the limits slows down instead, on the curve it asks for
        timed = isinstance(self._tracker, TimedTracker)
        return None if command is None else within_reach(command, state.velocity, state.limits,
                                                         keep_curvature=timed)

"""Property tests of the control for bases with acceleration limits, pure Python: the window of
commands, braking, the time-optimal profile and rounded corners, each against its limits."""

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.dynamics import stopping_speed, within_reach
from turtle_traj.core.control.profile import SpeedProfile
from turtle_traj.core.geometry.corners import rounded_corner
from turtle_traj.core.geometry.path import Polyline
from turtle_traj.core.geometry.projection import NearestOnPolyline

PERIOD = 0.016
speeds = st.floats(-2.0, 2.0, allow_nan=False)
accels = st.floats(0.05, 5.0, allow_nan=False)


def _config(accel: float, turn_accel: float, decel: float = 0.0, **speeds) -> ControlConfig:
    return ControlConfig(
        linear_speed=speeds.get('linear', 0.5), angular_speed=speeds.get('angular', 1.0),
        angular_deceleration=50.0, position_tolerance=5e-4, heading_tolerance=5e-4,
        period_s=PERIOD, max_linear_accel=accel, max_linear_decel=decel,
        max_angular_accel=turn_accel)


@given(speeds, speeds, speeds, speeds, accels, accels, accels)
def test_a_command_stays_within_reach_of_the_one_before(v0, w0, v1, w1, accel, decel, alpha):
    config = _config(accel, alpha, decel)
    result = within_reach(Command(v1, w1), Command(v0, w0), config.limits)
    assert abs(result.linear - v0) <= max(accel, decel) * PERIOD
    assert abs(result.angular - w0) <= alpha * PERIOD
    reach = 0.999 * PERIOD
    if abs(w1 - w0) <= alpha * reach and abs(v1 - v0) <= min(accel, decel) * reach:
        assert result == Command(v1, w1)  # a command in reach is sent as it is


@given(st.floats(0.0, 5.0), accels)
def test_braking_from_the_stopping_speed_stops_within_the_distance(distance, decel):
    speed, covered = stopping_speed(distance, decel, PERIOD), 0.0
    while speed > 0.0:
        covered += speed * PERIOD
        speed -= decel * PERIOD
    assert covered <= distance + 1e-9


@settings(max_examples=25, deadline=None)
@given(st.floats(0.2, 3.0), st.floats(0.3, 2.0), st.floats(0.1, 2.0), st.floats(0.2, 2.0))
def test_the_profile_on_an_arc_keeps_every_limit(radius, sweep, accel, alpha):
    angles = np.linspace(0.0, sweep, max(int(radius * sweep / 0.005), 8) + 1)
    arc = Polyline(np.stack([radius * np.sin(angles), radius * (1.0 - np.cos(angles))], axis=1))
    config = _config(accel, alpha)
    profile = SpeedProfile.plan(arc, config.limits)
    v = profile.speed
    assert v[0] == 0.0 and v[-1] < 1e-6  # rest to rest
    assert np.all(v <= config.linear_speed + 1e-6)
    assert np.all(v / radius <= config.angular_speed + 1e-6)  # omega = v k
    # constant acceleration between grid points: a = d(v²)/(2 ds); alpha = a k on an arc
    a = np.diff(v ** 2) / (2.0 * np.diff(profile.arc))
    assert np.all(np.abs(a) <= accel * (1 + 1e-3) + 1e-9)
    assert np.all(np.abs(a) / radius <= alpha * (1 + 1e-3) + 1e-9)
    lower = arc.length / config.linear_speed  # never faster than the top speed allows
    assert profile.duration_s >= lower


@given(st.floats(0.05, math.radians(170)), st.sampled_from([-1.0, 1.0]),
       st.floats(0.001, 0.5), st.floats(0.0, 2 * math.pi), st.sampled_from([math.inf, 1.05]))
def test_a_rounded_corner_keeps_within_its_tolerance_and_meets_both_legs(
        deflection, side, tolerance, heading, shape):
    corner = np.array([3.0, 4.0])
    heading_out = heading + side * deflection
    points = rounded_corner(corner, heading, heading_out, tolerance, room=2.0, shape=shape)
    leg_in = corner - 2.0 * np.array([math.cos(heading), math.sin(heading)])
    leg_out = corner + 2.0 * np.array([math.cos(heading_out), math.sin(heading_out)])
    drawn = NearestOnPolyline(np.array([leg_in, corner, leg_out]))
    assert drawn.distances(points).max() <= tolerance * (1 + 1e-6)
    assert drawn.distances(points[[0, -1]]).max() < 1e-9  # it starts and ends on the legs
    directions = np.arctan2(*np.diff(points, axis=0).T[::-1])
    turns = np.angle(np.exp(1j * np.diff(directions)))
    assert np.all(np.abs(turns) < 0.1)  # smooth: no kink a base would have to stop for
    assert math.isclose(np.sum(turns) + np.angle(np.exp(1j * (directions[0] - heading)))
                        + np.angle(np.exp(1j * (heading_out - directions[-1]))),
                        side * deflection, abs_tol=1e-6)

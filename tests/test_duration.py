"""The least time of a run (pure): each ramp against its own integration, and the whole estimate
against the time the control loop takes on the simulator's physics, with and without
acceleration limits."""

import math
from dataclasses import replace

import pytest

from turtle_traj.core.control.duration import ramp_s
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.testing.pure_loop import Loop, shape


def _integrated(distance: float, top: float, up: float, down: float) -> float:
    """Time to cover `distance` from rest to rest, integrated over distance: the speed at each
    point is the least of the top, of speeding up from the start and of braking to the end."""
    import numpy as np
    s = (np.arange(200_000) + 0.5) * distance / 200_000
    speed = np.minimum(top, np.minimum(np.sqrt(2 * up * s), np.sqrt(2 * down * (distance - s))))
    return float(np.sum(distance / 200_000 / speed))


@pytest.mark.parametrize(('distance', 'top', 'up', 'down'), [
    (1.0, 0.5, 0.5, 0.5), (0.1, 0.5, 0.5, 0.5), (2.0, 1.0, 2.5, 1.0), (0.05, 0.22, 2.5, 2.5)])
def test_a_ramp_takes_as_long_as_its_integration(distance, top, up, down):
    assert ramp_s(distance, top, up, down) == pytest.approx(_integrated(distance, top, up, down),
                                                            rel=1e-3)


def test_a_ramp_without_limits_is_distance_over_speed():
    assert ramp_s(2.0, 0.5, 0.0, 0.0) == pytest.approx(4.0)
    assert ramp_s(0.0, 0.5, 1.0, 1.0) == 0.0


LIMITED = replace(DEFAULT_SETTINGS, control=replace(
    DEFAULT_SETTINGS.control, linear_speed=0.5, angular_speed=1.0, max_linear_accel=0.5,
    max_angular_accel=1.0))


@pytest.mark.parametrize('settings', [DEFAULT_SETTINGS, LIMITED], ids=['turtlesim', 'limited'])
@pytest.mark.parametrize(('name', 'request_'), [
    ('square', shape(size=1.0)), ('circle', shape(size=1.0)),
    ('sine', shape(size=0.5, frequency=1.0, length=2.0)),
    ('go_to', shape(x=7.0, y=3.0, use_theta=True, theta=1.0, tolerance=0.0))])
def test_the_estimate_comes_within_ten_percent_of_the_run(name, request_, settings):
    loop = Loop(name, request_, settings=settings)
    poses = loop.drive()
    assert loop.run.ending[0], loop.run.ending
    elapsed = loop.run.outcome(poses[-1], len(poses) * STEP_S).elapsed_s
    estimate = loop.run.plan.least_time_s(settings.control)
    kinematic = loop.run.plan.lower_bound_s(settings.control)
    # measured: within 1% but for the sine on a limited base (7%: the profile plans with the
    # limits, the steering back onto the path costs the rest); the kinematic bound is 25% off
    assert estimate == pytest.approx(elapsed, rel=0.1)
    assert estimate >= kinematic - 1e-9 and math.isfinite(estimate)


def _curvature_limit_s(points, linear_speed: float, angular_speed: float,
                       share: float = 1.0) -> float:
    """A polyline's time on turtlesim, each segment at the speed its sharper end allows under
    this share of the top turn rate (the curvature at a vertex: its turn over the mean of its
    two segments), integrated here from the points."""
    import numpy as np
    steps = np.diff(points, axis=0)
    lengths = np.hypot(*steps.T)
    turns = np.abs(np.angle(np.exp(1j * np.diff(np.arctan2(steps[:, 1], steps[:, 0])))))
    at_vertices = turns / (0.5 * (lengths[:-1] + lengths[1:]))
    sharpest = np.maximum(np.concatenate(([0.0], at_vertices)),
                          np.concatenate((at_vertices, [0.0])))
    speed = np.minimum(linear_speed, share * angular_speed / np.maximum(sharpest, 1e-9))
    return float(np.sum(lengths / speed))


@pytest.mark.parametrize(('tolerance', 'sine', 'within_m'), [
    (0.02, dict(size=0.5, frequency=1.0, length=2.0), 0.02),
    (0.0, dict(size=0.5, frequency=0.5, length=4.0), 0.0005)], ids=['rounded', 'exact'])
def test_a_curve_on_turtlesim_is_driven_at_the_whole_turn_rate(tolerance, sine, within_m):
    """The sine's time is its path's length at min(top speed, turn rate / |curvature|): a
    rounded path's own turn may take the whole top turn rate (the tolerance's reserve is the
    steering's), and so may an exact curve's (each step lands on the curve: `curve_step`),
    which keeps within half a millimetre of the polyline drawn."""
    import numpy as np

    from turtle_traj.core.geometry.path import Polyline
    from turtle_traj.testing.geometry import distance_to_polyline

    loop = Loop('sine', shape(**sine, corner_tolerance=tolerance))
    poses = loop.drive()
    assert loop.run.ending[0], loop.run.ending
    elapsed = loop.run.outcome(poses[-1], len(poses) * STEP_S).elapsed_s
    turn, curve = loop.run.plan.path.legs  # onto the sine's first direction, then the sine
    assert isinstance(curve, Polyline)
    control = DEFAULT_SETTINGS.control
    whole_turn_rate_s = _curvature_limit_s(curve.points, control.linear_speed,
                                           control.angular_speed)
    four_fifths_s = _curvature_limit_s(curve.points, control.linear_speed,
                                       control.angular_speed, share=0.8)
    assert four_fifths_s > 1.08 * whole_turn_rate_s  # the turn rate binds on this sine
    turn_s = abs(turn.sweep_rad) / control.angular_speed
    assert elapsed == pytest.approx(turn_s + whole_turn_rate_s, rel=0.03)
    drawn = loop.run.plan.drawn_points()
    assert distance_to_polyline(np.array([(p.x, p.y) for p in poses]), drawn).max() <= max(
        tolerance, within_m)

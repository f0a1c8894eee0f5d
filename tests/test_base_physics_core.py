"""The physics base's plain-Python parts: wheel odometry, the command limits and wheel speeds,
the model's checks, and the MuJoCo model rolling as its dimensions say."""

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from turtle_traj.base.drive import DriveLimits, VelocityLimiter, wheel_speeds
from turtle_traj.base.model import BaseSpec
from turtle_traj.base.odometry import WheelOdometry
from turtle_traj.base.physics import DiffDrivePhysics

R, SEP, TICKS = 0.033, 0.160, 4096


def _odometry() -> WheelOdometry:
    odometry = WheelOdometry(wheel_radius=R, wheel_separation=SEP, ticks_per_revolution=TICKS)
    odometry.update(0.0, 0.0, 0.016)
    return odometry


@given(st.floats(-0.3, 0.3), st.floats(-3.0, 3.0))
def test_odometry_follows_an_arc_exactly_but_for_the_encoder_ticks(speed, turn_rate):
    odometry, steps, period = _odometry(), 100, 0.016
    for k in range(1, steps + 1):
        t = k * period
        odometry.update((speed - turn_rate * SEP / 2) * t / R,
                        (speed + turn_rate * SEP / 2) * t / R, period)
    t = steps * period
    yaw = turn_rate * t
    if abs(turn_rate) > 1e-9:
        x = speed / turn_rate * math.sin(yaw)
        y = speed / turn_rate * (1 - math.cos(yaw))
    else:
        x, y = speed * t, 0.0
    tick_m = 2 * math.pi / TICKS * R
    assert math.dist((odometry.x, odometry.y), (x, y)) < 2 * tick_m * (1 + t * abs(turn_rate))
    assert abs(math.remainder(odometry.yaw - yaw, math.tau)) < 2 * tick_m / SEP * 2


def test_odometry_counts_whole_ticks():
    odometry = _odometry()
    odometry.update(0.4 * 2 * math.pi / TICKS, 0.4 * 2 * math.pi / TICKS, 0.016)
    assert (odometry.x, odometry.linear) == (0.0, 0.0)  # less than a tick: nothing seen


@given(st.floats(-1.0, 1.0), st.floats(-10.0, 10.0))
def test_wheel_speeds_keep_the_curvature_and_the_motor_limit(linear, angular):
    left, right, scaled = wheel_speeds(linear, angular, wheel_radius=R, wheel_separation=SEP,
                                       max_wheel_speed=6.9)
    assert max(abs(left), abs(right)) <= 6.9 * (1 + 1e-12)
    assert scaled == (max(abs(linear - angular * SEP / 2),
                          abs(linear + angular * SEP / 2)) / R > 6.9)
    got_linear, got_angular = R * (left + right) / 2, R * (right - left) / SEP
    # the same curvature: omega / v unchanged (cross-multiplied, for v = 0)
    assert got_angular * linear == pytest.approx(got_linear * angular, abs=1e-9)


def test_the_limiter_keeps_speed_and_acceleration():
    limiter = VelocityLimiter(DriveLimits())
    speeds = [limiter.limit(1.0, -5.0, 0.016) for _ in range(20)]
    assert speeds[0] == pytest.approx((2.5 * 0.016, -3.2 * 0.016))
    assert speeds[-1] == pytest.approx((0.22, -0.016 * 3.2 * 20))
    assert max(abs(a) for _, a in speeds) <= 2.84


@pytest.mark.parametrize(('spec', 'said'), [
    (BaseSpec(mass=-1.0), 'mass must be above 0, got -1'),
    (BaseSpec(wheel_radius=0.0), 'wheel_radius must be above 0, got 0'),
    (BaseSpec(tire_friction=math.nan), 'tire_friction must be a finite number'),
    (BaseSpec(timestep=0.004), 'timestep must be at most 0.002 s'),
])
def test_the_model_refuses_what_it_cannot_build(spec, said):
    assert any(said in problem for problem in spec.problems())
    with pytest.raises(ValueError, match=said.split(',')[0]):
        DiffDrivePhysics(spec)


def test_the_model_rolls_as_its_wheels_turn_and_stands_still_without_commands():
    physics = DiffDrivePhysics(BaseSpec())
    physics.advance(0.5)
    assert physics.pose() == pytest.approx((0.0, 0.0, 0.0), abs=1e-6)
    speed = 0.1
    for k in range(1, 101):  # ramp to 0.1 m/s over 0.4 s, hold
        physics.drive(*[min(speed, k * 0.004) / R] * 2)
        physics.advance(0.016)
    x, y, yaw = physics.pose()
    rolled = R * sum(physics.wheel_angles()) / 2
    assert x == pytest.approx(rolled, rel=0.01)  # tyres slip and sink a little, not more
    assert abs(y) < 1e-6 and abs(yaw) < 1e-6
    assert physics.twist()[0] == pytest.approx(speed, rel=0.01)
    assert abs(physics.height()) < 0.001  # on its wheels

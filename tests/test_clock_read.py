"""A clock read as a number (rosutils/clock_read.py) against rclpy's own `Clock.now()`."""

from __future__ import annotations

from rclpy.clock import Clock, ClockType, ROSClock
from rclpy.time import Time

from turtle_traj.rosutils.clock_read import now_ns


def test_simulated_time_reads_as_the_clock_says_to_the_nanosecond():
    clock = ROSClock()
    clock._set_ros_time_is_active(True)  # as a TimeSource does with use_sim_time
    for nanoseconds in (0, 16_000_000, 123_456_789_012):
        clock.set_ros_time_override(Time(nanoseconds=nanoseconds, clock_type=ClockType.ROS_TIME))
        assert now_ns(clock) == clock.now().nanoseconds == nanoseconds


def test_a_running_clock_reads_between_two_of_its_own_readings():
    clock = Clock(clock_type=ClockType.STEADY_TIME)
    before = clock.now().nanoseconds
    read = now_ns(clock)
    assert before <= read <= clock.now().nanoseconds

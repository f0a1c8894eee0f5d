"""A clock read as a number (rosutils/clock_read.py) against rclpy's own `Clock.now()`."""

from __future__ import annotations

from rclpy.clock import Clock, ClockType, ROSClock
from rclpy.time_source import TimeSource

from turtle_traj.rosutils.clock_read import now_ns
from turtle_traj.rosutils.lockstep import clock_message


def test_simulated_time_reads_as_the_clock_says_to_the_nanosecond():
    clock, source = ROSClock(), TimeSource()
    source.ros_time_is_active = True  # as lock-step drives its nodes' clocks
    source.attach_clock(clock)
    for seconds in (0.0, 0.016, 123.456789012):
        source.clock_callback(clock_message(seconds))
        assert now_ns(clock) == clock.now().nanoseconds == round(seconds * 1e9)


def test_a_running_clock_reads_between_two_of_its_own_readings():
    clock = Clock(clock_type=ClockType.STEADY_TIME)
    before = clock.now().nanoseconds
    read = now_ns(clock)
    assert before <= read <= clock.now().nanoseconds

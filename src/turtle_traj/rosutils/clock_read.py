"""A clock's time as a number, without the `Time` object `Clock.now()` makes."""

from __future__ import annotations

from rclpy.clock import Clock


def now_ns(clock: Clock) -> int:
    """`clock.now().nanoseconds`, at a fifth of its cost (0.5 us against 2.3 us here): a
    lock-step step of 20 turtles reads their clocks about 100 times. The clock must live
    (a node's does, as long as its node)."""
    return clock.handle.get_now().nanoseconds

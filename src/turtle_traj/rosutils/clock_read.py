"""A clock's time as a number, without the `Time` object `Clock.now()` makes."""

from __future__ import annotations

from rclpy.clock import Clock


def now_ns(clock: Clock) -> int:
    """`clock.now().nanoseconds`, at a fifth of its cost (0.5 us against 2.3 us here): every
    control tick and pose reads a clock, about 100 times a lock-step step with 20 turtles.
    The clock must live (a node's does, as long as its node)."""
    return clock.handle.get_now().nanoseconds

"""The exact follower's tuning, declared apart from it: the node's parameter table serves these
four under their own names, and imports them without the follower's numpy. Pure Python."""

from __future__ import annotations

from turtle_traj.core.control.tuning import Tunable


class ExactTuning:
    """The exact follower's gains (`exact.ExactFollower`)."""

    heading_gain = Tunable(8.0, 'Turn rate per radian of heading error', '1/s', 0.1, 50.0)
    cross_track_gain = Tunable(2.5, 'How hard curves pull back onto the path', '1/m', 0.0, 50.0)
    deceleration = Tunable(20.0, 'Braking towards the end of a curve, on a base without '
                           'acceleration limits (with them, max_linear_decel or '
                           'max_linear_accel brakes)', 'm/s^2', 0.1, 100.0)
    turn_first_angle = Tunable(0.6, 'Heading error beyond which the turtle turns before '
                               'driving', 'rad', 0.05, 3.14159)

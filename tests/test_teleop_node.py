"""The teleop node's keys against our simulator in lock-step (no terminal, no timing): what F
cancels when the answer to the goal it should cancel is still on its way."""

from __future__ import annotations

import math

import pytest

from turtle_traj.core.teleop_keys import ROTATIONS


@pytest.fixture
def teleop(turtle_sim, rclpy_context):
    """The teleop node in the simulator's lock-step executor, connected to turtle1."""
    from turtle_traj.cli.teleop import TeleopNode
    node = TeleopNode(context=rclpy_context)
    turtle_sim.add_node(node)  # destroyed with the simulator
    assert turtle_sim.spin_until(node.connected, timeout_s=10.0)
    return node


def test_f_cancels_the_goal_just_sent_even_before_its_acceptance_is_back(turtle_sim, teleop):
    target = ROTATIONS['e']  # 135 degrees: 2.36 rad from the spawn heading, 2.4 s at 1 rad/s
    teleop.press('e')
    teleop.press('f')  # nothing spun between: the goal's acceptance cannot have come back
    turtle_sim.spin_sim_seconds(3.0)  # longer than the whole rotation
    turtle = turtle_sim.sim.world.turtle('turtle1')
    assert turtle.rotation is None
    assert abs(math.remainder(turtle.theta - target, math.tau)) > 2.0  # cancelled at once

def test_f_cancels_the_latest_goal_not_an_earlier_one(turtle_sim, teleop):
    teleop.press('t')  # to 45 degrees, and done
    turtle_sim.spin_sim_seconds(1.5)
    turtle = turtle_sim.sim.world.turtle('turtle1')
    assert abs(turtle.theta - ROTATIONS['t']) < 0.02 and turtle.rotation is None
    teleop.press('v')  # to -90 degrees: 2.36 rad clockwise, 2.4 s
    teleop.press('f')  # cancels this one, not the 45 degrees one (done already)
    turtle_sim.spin_sim_seconds(3.0)
    assert turtle.rotation is None
    assert abs(math.remainder(turtle.theta - ROTATIONS['v'], math.tau)) > 2.0


def test_f_cancels_a_rotation_on_its_way(turtle_sim, teleop):
    teleop.press('e')
    turtle_sim.spin_sim_seconds(0.5)  # accepted, and turning
    turtle = turtle_sim.sim.world.turtle('turtle1')
    assert turtle.rotation is not None and 0.2 < turtle.theta < 0.8
    teleop.press('f')
    turtle_sim.spin_sim_seconds(3.0)
    assert turtle.rotation is None and 0.2 < turtle.theta < 1.0  # stopped on its way

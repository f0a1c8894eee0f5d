"""The trajectory node's control loop on the simulator's physics, in pure Python (no ROS).

`Loop` is the node's loop exactly (a pose in, one command out per 16 ms step, the velocity echo
in float32 as turtlesim's Pose carries it), with the turtle moved by `sim.physics.World` as the
simulator moves it: a run in milliseconds, the same on every machine.

    loop = Loop('polygon', shape(sides=4, size=2.0))
    poses = loop.drive()
    assert loop.run.ending == (True, 'polygon done')
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from turtle_traj.core.control.loop import ControlLoop
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.sim.physics import World


def shape(**fields) -> SimpleNamespace:
    """A DrawShape request: every field zero (the node's parameters) but `fields`."""
    values = dict(sides=0, size=0.0, clockwise=False, turns=0.0, growth=0.0, max_radius=0.0,
                  frequency=0.0, length=0.0, linear_speed=0.0, angular_speed=0.0,
                  forever=False)
    return SimpleNamespace(**{**values, **fields})


class Loop:
    """One trajectory run: the physics and the node's control loop, a 16 ms step apart."""

    def __init__(self, name: str, request, x: float = 5.5, y: float = 5.5,
                 theta: float = 0.0, settings=DEFAULT_SETTINGS) -> None:
        self.world = World()
        self.turtle = self.world.spawn(x, y, theta, 'turtle1')
        self.control = ControlLoop(STEP_S)
        self.control.observe(Pose2D(x, y, theta), 0.0, 0.0)
        self.settings = settings
        plan = planning.plan(name, request, Pose2D(x, y, theta), settings)
        self.run = self.control.start(plan, arena=settings.arena, now_s=0.0)
        self.model = self.control.model

    def drive(self, disturb=None, max_steps: int = 20_000) -> list[Pose2D]:
        """Step until the supervisor decides; the poses the turtle reported."""
        turtle, control = self.turtle, self.control
        poses = []
        for step in range(max_steps):
            if disturb is not None:
                disturb(step, turtle)
            pose = Pose2D(turtle.x, turtle.y, turtle.theta)
            poses.append(pose)
            # the velocity echo as turtlesim's Pose carries it: float32
            control.observe(pose, float(np.float32(turtle.linear_speed)),
                            float(np.float32(turtle.omega)))
            command = control.command(self.settings.control, self.settings.arena,
                                      step * STEP_S)
            if self.run.ending is not None:
                return poses
            control.sent(command, step * STEP_S)
            self.world.command('turtle1', command.linear, 0.0, command.angular)
            self.world.step()
        raise AssertionError('the run never ended')

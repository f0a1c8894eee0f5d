"""A plan driven by the node's control loop on the simulator's physics, in pure Python.

The loop the node runs (a pose in, one command out per 16 ms step, the velocity echo in float32
as turtlesim's Pose carries it, the pen confirmed at once), on `sim.physics.World`, with or
without inertia, with the exact follower or any controller: a run in milliseconds, the same on
every machine.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.controllers.catalogue import ControllerChoice
from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.loop import ControlLoop
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.control.supervisor import RunSupervisor
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import Settings
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.sim.physics import Inertia, World


@dataclass
class Drive:
    """One run: the poses reported, the commands sent, and the run's supervisor."""

    run: RunSupervisor
    poses: list[Pose2D] = field(default_factory=list)
    commands: list[Command] = field(default_factory=list)  # as sent
    steps: int = 0  # 16 ms steps until the run ended

    @property
    def elapsed_s(self) -> float:
        return self.steps * STEP_S

    def xy(self) -> np.ndarray:
        return np.array([(pose.x, pose.y) for pose in self.poses]).reshape(-1, 2)


def drive(plan: Plan, start: Pose2D, settings: Settings, *, inertia: Inertia | None = None,
          controller: ControllerChoice | None = None, disturb=None,
          late_if: Callable[[int, Command], bool] | None = None, late_prior: float = 0.0,
          max_s: float = 600.0) -> Drive:
    """Drive `plan` from `start` until its run ends (or `max_s` of simulated time).

    :param disturb: called as disturb(step, turtle) before each step (a push, a teleport).
    :param late_if: called as late_if(step, command) for each command sent: whether it reaches
        the simulator a step late, the one before it acting a step longer, as a loaded
        transport delivers them (None: none is).
    :param late_prior: the control loop's (`ControlLoop`).
    """
    world = World(inertia=inertia)
    turtle = world.spawn(start.x, start.y, start.theta, 'turtle1')
    loop = ControlLoop(STEP_S, late_prior=late_prior)
    loop.observe(start, 0.0, 0.0)
    record = Drive(loop.start(plan, arena=settings.arena, now_s=0.0, controller=controller))
    run, late = record.run, None
    for step in range(int(max_s / STEP_S)):
        if disturb is not None:
            disturb(step, turtle)
        pose = Pose2D(turtle.x, turtle.y, turtle.theta)
        record.poses.append(pose)
        loop.observe(pose, float(np.float32(turtle.linear_speed)), float(np.float32(turtle.omega)))
        command = loop.command(settings.control, settings.arena, step * STEP_S)
        if run.ending is not None:
            record.steps = step
            return record
        if run.pen_wanted is not None:
            run.pen_is(run.pen_wanted)  # the simulator's set_pen answers at once
        if late is not None:
            world.command('turtle1', late.linear, 0.0, late.angular)
            late = None
        if command is not None:  # None: commands wait at the robot, none is sent
            loop.sent(command, step * STEP_S)
            if late_if is not None and late_if(step, command):
                late = command
            else:
                world.command('turtle1', command.linear, 0.0, command.angular)
            record.commands.append(command)
        world.step()
    record.steps = int(max_s / STEP_S)
    run.end(False, f'{run.name} still running after {max_s:g} s', Ending.TIMED_OUT)
    return record

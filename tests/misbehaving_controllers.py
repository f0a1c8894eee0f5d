"""Controllers that misbehave on their first stroke and then drive as DWPP: the node, started
with `controller:=tests.misbehaving_controllers:<Class>`, must end that run, stop the turtle,
and serve the next request."""

import math
import time

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.controllers.dwpp import Dwpp


class _FirstStrokeOnly(Dwpp):
    strokes = 0  # started, over every instance of the class

    def start(self, stroke, limits):
        type(self).strokes += 1
        super().start(stroke, limits)

    @property
    def misbehaving(self) -> bool:
        return type(self).strokes == 1


class Raises(_FirstStrokeOnly):
    def command(self, state):
        if self.misbehaving:
            raise KeyError('wheel')
        return super().command(state)


class ReturnsNan(_FirstStrokeOnly):
    def command(self, state):
        return Command(math.nan, 0.0) if self.misbehaving else super().command(state)


class SleepsOneSecond(_FirstStrokeOnly):
    def command(self, state):
        if self.misbehaving:
            time.sleep(1.0)
        return super().command(state)


class ExceedsTheLimits(_FirstStrokeOnly):
    def command(self, state):
        command = super().command(state)
        return None if command is None else Command(3.0 * command.linear, 3.0 * command.angular)


class StopsNearTheLastPoint(Dwpp):
    """The tutorial's slip: 'the end is reached' whenever the robot is within 1 cm of the
    stroke's last point, which on a closed stroke (a square, a circle) it is at the start."""

    def start(self, stroke, limits):
        super().start(stroke, limits)
        self.end = stroke.points[-1]

    def command(self, state):
        if math.dist((state.pose.x, state.pose.y), self.end) < 0.01:
            return None
        return super().command(state)


class StopsHalfWay(Dwpp):
    """Drives as DWPP and says 'the end is reached' half-way along the stroke, still moving."""

    def command(self, state):
        command = super().command(state)
        return None if self.arc[self.nearest] >= self.arc[-1] / 2 else command

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

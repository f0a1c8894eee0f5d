"""The physics base in the simulator's live view: its ground-truth trail drawn on a turtlesim
canvas (the world's origin at the canvas's centre, 45 pixels a metre), the base drawn as the
turtle `base`. The view's keys drive turtlesim's topics, which the base does not have."""

from __future__ import annotations

from collections.abc import Callable, Iterator

from turtle_traj.base.node import BaseNode
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M
from turtle_traj.sim.canvas import Canvas
from turtle_traj.sim.state import Pen, Segment, Turtle

BACKGROUND = (69, 86, 255)  # turtlesim's
TRAIL = Pen()  # turtlesim's default pen


class _BaseWorld:
    """What the live view reads of a simulator's world: its turtles and its time."""

    def __init__(self, base: BaseNode, turtle: Turtle) -> None:
        self._base, self._turtle = base, turtle

    def __iter__(self) -> Iterator[Turtle]:
        return iter([self._turtle])

    @property
    def turtles(self) -> dict[str, Turtle]:
        return {self._turtle.name: self._turtle}

    @property
    def time_s(self) -> float:
        return self._base.time_s


class BaseScene:
    """A live view's simulator made of the physics base: `canvas`, `background`, `world` and
    `step_listeners`, as `SimLiveView` reads them."""

    def __init__(self, base: BaseNode) -> None:
        self.canvas = Canvas()
        self.background = BACKGROUND
        self.step_listeners: list[Callable[[], None]] = []
        self.turtle = Turtle('base', SPAWN_XY_M, SPAWN_XY_M, 0.0)
        self.world = _BaseWorld(base, self.turtle)
        self._base = base
        base.step_listeners.append(self._on_step)

    def close(self) -> None:
        if self._on_step in self._base.step_listeners:
            self._base.step_listeners.remove(self._on_step)

    def _on_step(self) -> None:
        x, y, yaw = self._base.physics.pose()
        turtle, new = self.turtle, (x + SPAWN_XY_M, y + SPAWN_XY_M)
        if new != (turtle.x, turtle.y):
            self.canvas.draw(Segment((turtle.x, turtle.y), new, TRAIL))
        turtle.x, turtle.y, turtle.theta = *new, yaw
        for listener in self.step_listeners:
            listener()

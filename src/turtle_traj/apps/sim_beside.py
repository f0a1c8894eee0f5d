"""`--with-sim`: our simulator in the trajectory node's process (loaded only when asked for)."""

from __future__ import annotations

from collections.abc import Callable

from rclpy.node import Node

from turtle_traj.apps import sim as sim_main
from turtle_traj.sim.node import SimNode
from turtle_traj.sim.options import SimOptions


class SimBeside:
    """The simulator node next to the trajectory node: made once rclpy is up, saved at exit."""

    def __init__(self, options: SimOptions) -> None:
        self.options = options
        self.node: SimNode | None = None

    def create(self, stop: Callable[[], None], *, lockstep: bool = False) -> list[Node]:
        """The simulator node and its live view, if asked for; SimUnavailable when its window
        cannot open (`--gui`) or the view cannot listen (`--web`). With `lockstep` the
        simulator has no timer of its own (a `LockstepExecutor` steps it)."""
        nodes = sim_main.create_sim(self.options, stop, lockstep=lockstep)
        self.node = nodes[0]
        return nodes

    def save_outputs(self) -> None:
        if self.node is not None:
            sim_main.save_outputs(self.node, self.options)

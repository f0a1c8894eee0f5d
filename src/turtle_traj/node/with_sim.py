"""`--with-sim`: our simulator in the trajectory node's process (loaded only when asked for)."""

from __future__ import annotations

from collections.abc import Callable

from turtle_traj.sim import main as sim_main
from turtle_traj.sim.gui import GuiUnavailable
from turtle_traj.sim.node import SimNode
from turtle_traj.sim.options import SimOptions, SimUnavailable


class SimBeside:
    """The simulator node next to the trajectory node: made once rclpy is up, saved at exit."""

    def __init__(self, options: SimOptions) -> None:
        self.options = options
        self.node: SimNode | None = None

    def create(self, stop: Callable[[], None]) -> SimNode:
        """The simulator node; SimUnavailable when its window cannot open (`--gui`)."""
        try:
            self.node = sim_main.create_sim(self.options, stop)
        except GuiUnavailable as error:
            raise SimUnavailable(f'--gui: {error}') from None
        return self.node

    def save_snapshot(self) -> None:
        if self.node is not None:
            sim_main.save_snapshot(self.node, self.options.snapshot)

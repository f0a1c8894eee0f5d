"""A planned run: a checked path, its per-run speed overrides, end tolerance and pen."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.duration import least_time_s
from turtle_traj.core.control.profile import SpeedProfile
from turtle_traj.core.geometry.path import Path
from turtle_traj.core.turtlesim_contract import PenStyle


@dataclass(frozen=True)
class Plan:
    """A checked path plus its per-run speed overrides and end tolerance."""

    trajectory: str
    path: Path
    linear_speed: float | None = None  # None: the node's parameter, read live
    angular_speed: float | None = None
    end_tolerance: float | None = None
    pen: PenStyle | None = None  # a drawing's pen: the node sets it, and restores its own after
    pen_up_unordered: float = 0.0  # pen-up distance had the strokes not been reordered [m]
    drawn: np.ndarray | None = None  # the path as drawn, when its corners are rounded (N, 2)
    tolerance: float = 0.0  # how far the motion may stray from `drawn` (0: none, exact) [m]
    # Each leg's speed profile on a base with acceleration limits (None: a turn, a straight
    # line), planned with the request; empty without limits.
    profiles: tuple[SpeedProfile | None, ...] = ()

    def drawn_points(self) -> np.ndarray:
        """The points deviation is measured against: the path as drawn, corners included."""
        return self.drawn if self.drawn is not None else self.path.points()

    def control(self, config: ControlConfig) -> ControlConfig:
        """The node's control config with this run's speeds."""
        return replace(config, linear_speed=self.linear_speed or config.linear_speed,
                       angular_speed=self.angular_speed or config.angular_speed)

    def lower_bound_s(self, config: ControlConfig) -> float:
        """Kinematic lower bound of the run's duration at its top speeds (under `config`)."""
        run = self.control(config)
        return self.path.lower_bound_s(run.linear_speed, run.angular_speed)

    def least_time_s(self, config: ControlConfig) -> float:
        """The least time the controller can take, at its limits (`duration.least_time_s`)."""
        return least_time_s(self.path, self.control(config), self.profiles)

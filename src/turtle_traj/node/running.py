"""What the services, the draw action and the commands need of the node's runs
(`RunManager` is it): they reach the runs through this, never the node class."""

from __future__ import annotations

from typing import Any, Protocol

from rclpy.task import Future

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.controllers.catalogue import ControllerChoice
from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.supervisor import RunSupervisor
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import Settings
from turtle_traj.core.registry import TrajectoryKind
from turtle_traj.node.outcomes import RunRefused


class RunningNode(Protocol):
    """One turtle's runs, one at a time."""

    @property
    def pose(self) -> Pose2D | None: ...

    @property
    def settings(self) -> Settings: ...

    @property
    def pen_ready(self) -> bool: ...

    def now_s(self) -> float: ...

    def choose_controller(self, name: str) -> ControllerChoice: ...

    def refusal(self, replacing: RunSupervisor | None = None) -> RunRefused | None: ...

    def refuse(self, message: str, reason: Ending) -> RunRefused: ...

    @property
    def last_command(self) -> Command: ...

    @property
    def frame_id(self) -> str: ...

    async def start_run(self, kind: TrajectoryKind, request: Any, *,
                        controller: ControllerChoice | None = None,
                        replacing: RunSupervisor | None = None
                        ) -> tuple[RunSupervisor, Future]: ...

    def stop_run(self, run: RunSupervisor, reason: Ending = Ending.STOPPED) -> None: ...

    def stop_planning(self, request: Any, reason: Ending = Ending.STOPPED) -> None: ...

    def stop(self) -> str: ...

    def abort_run(self, why: str, reason: Ending) -> None: ...

    def forget_turtle(self) -> None: ...

    def send_stop(self) -> None: ...

    def commands_heard(self) -> bool: ...

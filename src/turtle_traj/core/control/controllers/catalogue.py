"""A controller chosen for a run (`Chosen`): the exact follower, or a `Controller` class driven
stroke by stroke, with what times its answers and reads its tuning. Pure Python: finding a
controller by name (entry points, imports) is `turtle_traj.api.controllers`'s job.

`exact` is the node's own follower (`follower.PathFollower`); `dwpp` and `pure_pursuit` are
shipped beside it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from turtle_traj.core.control.controller import Controller, PlanController
from turtle_traj.core.control.controllers.dwpp import Dwpp
from turtle_traj.core.control.controllers.pure_pursuit import PurePursuit
from turtle_traj.core.control.follower import PathFollower
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.control.strokes import AnswerTimer, StrokeDriver
from turtle_traj.core.control.tuning import Spec, tunables

EXACT = 'exact'
SHIPPED: dict[str, type] = {'dwpp': Dwpp, 'pure_pursuit': PurePursuit}

ControllerFactory = Callable[[], Controller]
TuningSource = Callable[[], Mapping[str, float]]  # the tuning's values now, by name


@dataclass(frozen=True)
class Chosen:
    """A controller chosen by name: a new one is made for every run."""

    name: str = EXACT
    factory: ControllerFactory | None = None  # a `Controller` class; None: the exact follower
    # Times its answers: later than the control period ends the run (`strokes.LATE_ANSWERS`
    # in a row; the node's runs, in real or lock-step time). None in pure loops (`turtle-traj
    # score`), whose simulated time waits for the controller: their figures then never depend
    # on how busy the machine is.
    timer: AnswerTimer | None = None
    tuning: TuningSource | None = None  # None: the class's defaults

    @property
    def prefix(self) -> str:
        """The prefix of its tuning's parameters: its name, or its class's for
        `module:Class`."""
        return parameter_prefix(self.name)

    @property
    def tunables(self) -> tuple[Spec, ...]:
        """The tuning its class declares (none for the exact follower)."""
        return () if self.factory is None else tunables(self.factory)

    def driver(self, plan: Plan, *, manage_pen: bool) -> PlanController:
        """The controller of this run's whole plan: the exact follower, or the chosen
        `Controller` stroke by stroke (its constructor's exception propagates)."""
        if self.factory is None:
            return PathFollower(plan.path, end_tolerance=plan.end_tolerance,
                                manage_pen=manage_pen, profiles=plan.profiles)
        return StrokeDriver(plan.path, self.factory(), self.name, manage_pen=manage_pen,
                            timer=self.timer, tuning=self.tuning)


def parameter_prefix(name: str) -> str:
    """The prefix of a controller's tuning parameters: `name`, or the class of `module:Class`
    (`my_controller:WaypointP` -> `WaypointP`)."""
    return name.rpartition(':')[2]

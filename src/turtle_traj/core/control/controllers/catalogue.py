"""A controller chosen for a run (`ControllerChoice`): a `Controller` class, driven by the plan
walker, with what times its answers and reads its tuning. Pure Python: finding a controller by name
(entry points, imports) is `turtle_traj.api.controllers`'s job.

`exact` is the node's own follower (`exact.ExactFollower`); `dwpp` and `pure_pursuit` are
shipped beside it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from turtle_traj.core.control.controller import Controller
from turtle_traj.core.control.controllers.dwpp import Dwpp
from turtle_traj.core.control.controllers.exact import ExactFollower
from turtle_traj.core.control.controllers.pure_pursuit import PurePursuit
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.control.tuning import Spec, tunables
from turtle_traj.core.control.walker import AnswerTimer, PlanWalker

EXACT = 'exact'
SHIPPED: dict[str, type] = {EXACT: ExactFollower, 'dwpp': Dwpp, 'pure_pursuit': PurePursuit}

ControllerFactory = Callable[[], Controller]
TuningSource = Callable[[], Mapping[str, float]]  # the tuning's values now, by name


@dataclass(frozen=True)
class ControllerChoice:
    """A controller chosen by name: a new one is made for every run."""

    name: str = EXACT
    factory: ControllerFactory = ExactFollower  # a `Controller` class
    # Times its answers: later than the control period ends the run (`walker.LATE_ANSWERS`
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
        """The tuning its class declares."""
        return tunables(self.factory)

    def driver(self, plan: Plan, *, manage_pen: bool) -> PlanWalker:
        """This run's plan, walked with a new controller of the class (its constructor's
        exception propagates)."""
        return PlanWalker(plan, self.factory(), self.name, manage_pen=manage_pen,
                          timer=self.timer, tuning=self.tuning)


def parameter_prefix(name: str) -> str:
    """The prefix of a controller's tuning parameters: `name`, or the class of `module:Class`
    (`my_controller:WaypointP` -> `WaypointP`)."""
    return name.rpartition(':')[2]

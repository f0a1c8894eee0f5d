"""Controllers by name: the node's `controller` parameter.

`exact` is the node's own follower (`follower.PathFollower`); `dwpp` and `pure_pursuit` are
shipped beside it; entry points in the group `turtle_traj.controllers` add more by name; and
`package.module:Class` names any importable class (or one in a module in the current folder).
"""

from __future__ import annotations

import functools
import importlib
import os
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from importlib.metadata import entry_points

from turtle_traj.core.control.controller import Controller, PlanController, interface_problem
from turtle_traj.core.control.controllers.dwpp import Dwpp
from turtle_traj.core.control.controllers.pure_pursuit import PurePursuit
from turtle_traj.core.control.follower import PathFollower
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.control.strokes import StrokeDriver
from turtle_traj.core.control.tuning import Spec, tunables

EXACT = 'exact'
SHIPPED: dict[str, type] = {'dwpp': Dwpp, 'pure_pursuit': PurePursuit}
ENTRY_POINT_GROUP = 'turtle_traj.controllers'

ControllerFactory = Callable[[], Controller]
TuningSource = Callable[[], Mapping[str, float]]  # the tuning's values now, by name


@dataclass(frozen=True)
class Chosen:
    """A controller chosen by name: a new one is made for every run."""

    name: str = EXACT
    factory: ControllerFactory | None = None  # a `Controller` class; None: the exact follower
    # Answers later than the control period end the run (`strokes.LATE_ANSWERS` in a row; the
    # node's runs, in real or lock-step time). False in pure loops (`turtle-traj score`),
    # whose simulated time waits for the controller: their figures then never depend on how
    # busy the machine is.
    timed: bool = True
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
                            timed=self.timed, tuning=self.tuning)


class UnknownController(ValueError):
    """A controller name that names no controller, or a class that is not one."""


def parameter_prefix(name: str) -> str:
    """The prefix of a controller's tuning parameters: `name`, or the class of `module:Class`
    (`my_controller:WaypointP` -> `WaypointP`)."""
    return name.rpartition(':')[2]


def names() -> list[str]:
    """Every controller offered by name: shipped, then installed entry points."""
    installed = sorted(point.name for point in entry_points(group=ENTRY_POINT_GROUP))
    return [EXACT, *SHIPPED, *(name for name in installed if name not in SHIPPED)]


def choose(name: str, *, timed: bool = True) -> Chosen:
    """The controller a name stands for.

    :raises UnknownController: with the reason.
    """
    return Chosen(name, resolve(name), timed)


@functools.lru_cache(maxsize=64)
def resolve(name: str) -> ControllerFactory | None:
    """The class a name stands for (None: the exact follower); found once per process (the
    node checks its parameter as it is declared, then takes the class).

    :raises UnknownController: with the reason.
    """
    if name == EXACT:
        return None
    if name in SHIPPED:
        return SHIPPED[name]
    points = [point for point in entry_points(group=ENTRY_POINT_GROUP) if point.name == name]
    if points:
        candidate = _loaded(name, points[0].load)
    elif ':' in name:
        module, _, attribute = name.partition(':')
        candidate = _loaded(name, lambda: getattr(_imported(module), attribute))
    else:
        raise UnknownController(
            f"controller {name!r} is unknown: choose one of {', '.join(names())}, or name a "
            'class as package.module:Class')
    problem = interface_problem(candidate)
    if problem is not None:
        raise UnknownController(f'controller {name!r}: {problem}')
    _loaded(name, candidate)  # one made now: a class that cannot be made is refused now
    return candidate


def _imported(module: str) -> object:
    """The module, found on the import path or else in the current folder (a user's
    controller beside them, as `python -m` would find it)."""
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as error:
        if error.name != module.split('.')[0] or os.getcwd() in sys.path:
            raise
    sys.path.append(os.getcwd())
    return importlib.import_module(module)


def _loaded(name: str, load: Callable[[], object]) -> object:
    try:
        return load()
    except Exception as error:  # an import error, a missing attribute, a failing constructor
        raise UnknownController(f'controller {name!r} cannot be loaded: '
                                f'{type(error).__name__}: {error}') from None

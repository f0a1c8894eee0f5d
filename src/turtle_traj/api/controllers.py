"""Controllers by name: the node's `controller` parameter and FollowPath's `controller_id`.

`exact` (the node's own follower) and the shipped `dwpp` and `pure_pursuit` by name; entry
points in the group `turtle_traj.controllers` add more by name; and `package.module:Class`
names any importable class (or one in a module in the current folder).
"""

from __future__ import annotations

import functools
import importlib
import os
import sys
from collections.abc import Callable
from importlib.metadata import entry_points

from turtle_traj.core.control.controller import interface_problem
from turtle_traj.core.control.controllers.catalogue import (
    SHIPPED,
    Chosen,
    ControllerFactory,
)

ENTRY_POINT_GROUP = 'turtle_traj.controllers'


class UnknownController(ValueError):
    """A controller name that names no controller, or a class that is not one."""


def names() -> list[str]:
    """Every controller offered by name: shipped, then installed entry points."""
    installed = sorted(point.name for point in entry_points(group=ENTRY_POINT_GROUP))
    return [*SHIPPED, *(name for name in installed if name not in SHIPPED)]


def choose(name: str) -> Chosen:
    """The controller a name stands for, untimed.

    :raises UnknownController: with the reason.
    """
    return Chosen(name, resolve(name))


@functools.lru_cache(maxsize=64)
def resolve(name: str) -> ControllerFactory:
    """The class a name stands for; found once per process (the node checks its parameter as
    it is declared, then takes the class).

    :raises UnknownController: with the reason.
    """
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

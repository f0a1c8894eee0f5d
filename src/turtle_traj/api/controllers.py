"""Controllers by name: the node's `controller` parameter and FollowPath's `controller_id`.

`exact` (the node's own follower) and the shipped `dwpp` and `pure_pursuit` by name; entry
points in the group `turtle_traj.controllers` add more by name; and `package.module:Class`
names any importable class (or one in a module in the current folder). In a Nav2 parameter
file (`<id>.plugin`), the shipped ones are `turtle_traj::<Class>` (`plugin_names`).
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
    ControllerChoice,
    ControllerFactory,
)

ENTRY_POINT_GROUP = 'turtle_traj.controllers'
PLUGIN_PREFIX = 'turtle_traj::'


class UnknownController(ValueError):
    """A controller name that names no controller, or a class that is not one."""


def names() -> list[str]:
    """Every controller offered by name: shipped, then installed entry points."""
    installed = sorted(point.name for point in entry_points(group=ENTRY_POINT_GROUP))
    return [*SHIPPED, *(name for name in installed if name not in SHIPPED)]


def plugin_names() -> dict[str, str]:
    """The shipped controllers' names in a Nav2 parameter file (`turtle_traj::Dwpp`), to ours."""
    return {f'{PLUGIN_PREFIX}{factory.__name__}': name for name, factory in SHIPPED.items()}


def from_plugin_name(plugin: str) -> str:
    """Our name of the controller a Nav2 parameter file's `<id>.plugin` names: a shipped one
    as `turtle_traj::<Class>`, or a class of one's own as `package.module:Class`.

    :raises UnknownController: any other, a Nav2 C++ plugin among them, with the names to use.
    """
    shipped = plugin_names()
    if plugin in shipped:
        return shipped[plugin]
    if '::' not in plugin and ':' in plugin:
        resolve(plugin)
        return plugin
    kind = ("a Nav2 C++ plugin, which this server cannot load" if '::' in plugin
            and not plugin.startswith(PLUGIN_PREFIX) else 'not a controller of this server')
    raise UnknownController(f"{plugin!r} is {kind}: name one of {', '.join(shipped)}, or "
                            'your own as package.module:Class')


def choose(name: str) -> ControllerChoice:
    """The controller a name stands for, untimed.

    :raises UnknownController: with the reason.
    """
    return ControllerChoice(name, resolve(name))


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

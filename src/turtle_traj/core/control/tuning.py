"""Settings with a name, a default, a unit and a range: the node's parameters (`Spec`), and a
controller's own tuning, declared on its class (`Tunable`). Pure Python.

A controller declares each number it can be tuned by as a class attribute::

    class WaypointP:
        gain = Tunable(4.0, 'Turn rate per radian of heading error', '1/s', 0.0, 50.0)

Read as `self.gain`, it is the default until the node sets the instance's value: the node
serves it as the ROS parameter `<controller>.gain`, checked against its range, and sets the
value it has then before each stroke starts.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace


@dataclass(frozen=True)
class Spec:
    """One setting: default, description, unit, allowed range and whether it can change at run
    time."""

    name: str
    default: float | int | str
    description: str
    unit: str = ''
    low: float | None = None
    high: float | None = None
    read_only: bool = False
    choices: tuple[str, ...] = ()  # the values a text setting may take (empty: any)


class Tunable:
    """A controller's number, declared on its class: the default until the node sets it."""

    def __init__(self, default: float, description: str, unit: str = '', low: float = 0.0,
                 high: float = 1e3) -> None:
        if not low <= default <= high:
            raise ValueError(f'default {default} outside [{low}, {high}]')
        self.spec = Spec('', float(default), description, unit, float(low), float(high))

    def __set_name__(self, owner: type, name: str) -> None:
        self.spec = replace(self.spec, name=name)

    def __get__(self, instance: object, owner: type | None = None) -> float | Tunable:
        """On the class: the Tunable itself; on an instance without its own value: the default
        (a value set on the instance hides this descriptor)."""
        return self if instance is None else self.spec.default


def tunables(controller_class: type) -> tuple[Spec, ...]:
    """The tuning a controller class declares, its base classes' included (a subclass hides one
    by setting the name to something else)."""
    found: dict[str, Spec | None] = {}
    for klass in controller_class.__mro__:
        for name, value in vars(klass).items():
            if name not in found and not name.startswith('__'):
                found[name] = value.spec if isinstance(value, Tunable) else None
    return tuple(spec for spec in found.values() if spec is not None)


def tune(controller: object, values: Mapping[str, float]) -> None:
    """Set a controller's tuning to `values` (by name; names it does not declare are ignored)."""
    for spec in tunables(type(controller)):
        if spec.name in values:
            setattr(controller, spec.name, float(values[spec.name]))

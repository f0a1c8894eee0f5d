"""The trajectory node's parameters: the settings table declared with descriptors, read back."""

from __future__ import annotations

from rcl_interfaces.msg import (
    FloatingPointRange,
    IntegerRange,
    ParameterDescriptor,
    SetParametersResult,
)
from rclpy.node import Node
from rclpy.parameter import Parameter

from turtle_traj.api.controllers import UnknownController, resolve
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import (
    ARENA_PARAMETERS,
    Settings,
    arena_problem,
    pen_color_problem,
    settings_from_values,
)
from turtle_traj.core.parameters.table import DEFAULTS, PARAMETER, PARAMETERS, Spec


def descriptor(spec: Spec) -> ParameterDescriptor:
    """The ROS descriptor of one setting: description with unit, range, read-only."""
    result = ParameterDescriptor(
        description=f'{spec.description} [{spec.unit}]' if spec.unit else spec.description,
        read_only=spec.read_only)
    if isinstance(spec.default, int):
        result.integer_range = [IntegerRange(from_value=spec.low, to_value=spec.high, step=1)]
    elif spec.low is not None:
        result.floating_point_range = [FloatingPointRange(from_value=spec.low, to_value=spec.high)]
    return result


def declare(node: Node) -> None:
    for spec in PARAMETERS:
        node.declare_parameter(spec.name, spec.default, descriptor(spec))


def read_settings(node: Node) -> Settings:
    """Settings from the node's current parameters."""
    return settings_from_values({spec.name: node.get_parameter(spec.name).value
                                 for spec in PARAMETERS})


def validate(node: Node, parameters: list[Parameter],
             turtle: Pose2D | None = None) -> SetParametersResult:
    """Cross-field rules of the settings table, on the values the change would leave (and the
    turtle's pose, which a new arena must contain)."""
    incoming = {p.name: p.value for p in parameters}
    problem = (_choice_problem(incoming) or _controller_problem(incoming)
               or _pen_color_problem(incoming) or _arena_change_problem(node, incoming, turtle))
    return SetParametersResult(successful=problem is None, reason=problem or '')


def _choice_problem(incoming: dict[str, object]) -> str | None:
    for name, value in incoming.items():
        spec = PARAMETER.get(name)
        if spec is not None and spec.choices and value not in spec.choices:
            return f'{name} must be one of {", ".join(map(repr, spec.choices))}, got {value!r}'
    return None


def _controller_problem(incoming: dict[str, object]) -> str | None:
    if 'controller' not in incoming:
        return None
    try:
        resolve(incoming['controller'])
    except UnknownController as error:
        return str(error)
    return None


def _pen_color_problem(incoming: dict[str, object]) -> str | None:
    return pen_color_problem(incoming['pen_color']) if 'pen_color' in incoming else None


def _arena_change_problem(node: Node, incoming: dict[str, object],
                          turtle: Pose2D | None) -> str | None:
    if not incoming.keys() & ARENA_PARAMETERS:
        return None
    values = {name: incoming[name] if name in incoming
              else node.get_parameter(name).value if node.has_parameter(name)
              else DEFAULTS[name] for name in ARENA_PARAMETERS}
    return arena_problem(values, turtle)

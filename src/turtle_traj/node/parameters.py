"""The trajectory node's parameters: the settings table declared with descriptors, read back."""

from __future__ import annotations

from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor, SetParametersResult
from rclpy.node import Node
from rclpy.parameter import Parameter

from turtle_traj.settings import DEFAULTS, SPECS, Settings, Spec, settings_from_values


def descriptor(spec: Spec) -> ParameterDescriptor:
    """The ROS descriptor of one setting: description with unit, range, read-only."""
    result = ParameterDescriptor(
        description=f'{spec.description} [{spec.unit}]' if spec.unit else spec.description,
        read_only=spec.read_only)
    if spec.low is not None:
        result.floating_point_range = [FloatingPointRange(from_value=spec.low, to_value=spec.high)]
    return result


def declare(node: Node) -> None:
    for spec in SPECS:
        node.declare_parameter(spec.name, spec.default, descriptor(spec))


def read_settings(node: Node) -> Settings:
    """Settings from the node's current parameters."""
    return settings_from_values({spec.name: node.get_parameter(spec.name).value
                                 for spec in SPECS})


def validate(node: Node, parameters: list[Parameter]) -> SetParametersResult:
    """Cross-field rule: the arena, shrunk by the margin, must keep some room."""
    incoming = {p.name: p.value for p in parameters}
    names = {'arena_min_x', 'arena_min_y', 'arena_max_x', 'arena_max_y', 'wall_margin'}
    if not incoming.keys() & names:
        return SetParametersResult(successful=True)

    def current(name: str) -> float:
        if name in incoming:
            return incoming[name]
        if node.has_parameter(name):
            return node.get_parameter(name).value
        return DEFAULTS[name]

    margin = current('wall_margin')
    for axis in 'xy':
        room = current(f'arena_max_{axis}') - current(f'arena_min_{axis}') - 2 * margin
        if room <= 0.1:
            return SetParametersResult(
                successful=False,
                reason=f'arena_max_{axis} - arena_min_{axis} must exceed 2 * wall_margin + 0.1 m '
                       f'(it leaves {room:.3f} m)')
    return SetParametersResult(successful=True)

"""The simulator node's parameters: turtlesim's own, and turtle_traj's read-only extensions."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from rcl_interfaces.msg import (
    FloatingPointRange,
    IntegerRange,
    ParameterDescriptor,
    SetParametersResult,
)
from rclpy.node import Node
from rclpy.parameter import Parameter


@dataclass(frozen=True)
class SimParameters:
    """The read-only extensions' values, as declared (with their overrides)."""

    time_scale: float
    publish_clock: bool
    output_dir: Path
    command_delay_s: float
    command_jitter_s: float
    command_jitter_seed: int
    max_linear_accel: float
    max_angular_accel: float


def _color_range() -> list[IntegerRange]:
    return [IntegerRange(from_value=0, to_value=255, step=1)]


def declare_parameters(node: Node) -> SimParameters:
    """Declare every parameter of the simulator on `node`; the extensions' values."""
    node.declare_parameter('background_r', 69, ParameterDescriptor(
        description='Red channel of the background color', integer_range=_color_range()))
    node.declare_parameter('background_g', 86, ParameterDescriptor(
        description='Green channel of the background color', integer_range=_color_range()))
    node.declare_parameter('background_b', 255, ParameterDescriptor(
        description='Blue channel of the background color', integer_range=_color_range()))
    node.declare_parameter('holonomic', False, ParameterDescriptor(
        description='If true, then turtles will be holonomic'))
    time_scale = node.declare_parameter('time_scale', 1.0, ParameterDescriptor(
        description='Simulated seconds per wall-clock second (turtle_traj extension)',
        read_only=True,
        floating_point_range=[FloatingPointRange(from_value=0.1, to_value=1000.0)])).value
    publish_clock = node.declare_parameter('publish_clock', False, ParameterDescriptor(
        description='Publish simulated time on /clock, for nodes with use_sim_time '
                    '(turtle_traj extension)', read_only=True)).value
    output_dir = Path(node.declare_parameter('output_dir', 'output', ParameterDescriptor(
        description='Folder that save_image writes into (turtle_traj extension)',
        read_only=True)).value).resolve()
    delay = (
        node.declare_parameter('command_delay', 0.0, ParameterDescriptor(
            description='Apply each cmd_vel this long after it arrives [s] (turtle_traj '
                        'extension for latency tests; simulated time)', read_only=True,
            floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1.0)])).value,
        node.declare_parameter('command_jitter', 0.0, ParameterDescriptor(
            description='Plus a random extra delay of up to this much [s], order kept '
                        '(turtle_traj extension)', read_only=True,
            floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1.0)])).value,
        node.declare_parameter('command_jitter_seed', 0, ParameterDescriptor(
            description='Seed of the jitter, so runs repeat (turtle_traj extension)',
            read_only=True)).value)
    inertia = (
        node.declare_parameter('max_linear_accel', 0.0, ParameterDescriptor(
            description='Inertia: how fast a turtle\'s speed may change [m/s^2]; 0 is '
                        'turtlesim\'s instant response (turtle_traj extension, to test '
                        'controllers meant for real bases)', read_only=True,
            floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1000.0)])).value,
        node.declare_parameter('max_angular_accel', 0.0, ParameterDescriptor(
            description='Inertia: how fast a turtle\'s turn rate may change [rad/s^2]; 0 is '
                        'instant (turtle_traj extension)', read_only=True,
            floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1000.0)])).value)
    node.declare_parameter('motor_gains', '', ParameterDescriptor(
        description='Worn motors: "turtle3=0.5,turtle7=0.8" has those turtles deliver that '
                    'share of every commanded velocity, above 0 and at most 1 (turtle_traj '
                    'extension, for fleet fault tests)'))
    return SimParameters(time_scale, publish_clock, output_dir, *delay, *inertia)


def motor_gains(text: str) -> dict[str, float]:
    """The `motor_gains` parameter read: turtle name to gain.

    :raises ValueError: not "name=gain" pairs separated by commas, or a gain outside (0, 1].
    """
    gains: dict[str, float] = {}
    for item in filter(None, (part.strip() for part in text.split(','))):
        name, equals, value = item.partition('=')
        try:
            gain = float(value)
        except ValueError:
            gain = math.nan
        if not equals or not name.strip() or not 0.0 < gain <= 1.0:
            raise ValueError(f'motor_gains: {item!r} is not name=gain with a gain in (0, 1]')
        gains[name.strip()] = gain
    return gains


def check_parameters(parameters: list[Parameter]) -> SetParametersResult:
    """Refuse a `motor_gains` that does not read (the others are checked by their ranges)."""
    for parameter in parameters:
        if parameter.name == 'motor_gains':
            try:
                motor_gains(parameter.value)
            except ValueError as error:
                return SetParametersResult(successful=False, reason=str(error))
    return SetParametersResult(successful=True)

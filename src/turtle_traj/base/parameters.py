"""The physics base's parameters: the model's (read-only: the model is built once), the base
controller's limits and command timeout (live), and how it runs."""

from __future__ import annotations

import re
from dataclasses import dataclass

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
from rclpy.node import Node

from turtle_traj.base.drive import DriveLimits
from turtle_traj.base.model import BaseSpec

CMD_VEL_TYPES = ('TwistStamped', 'Twist')
# name: (default, description [unit], low, high); model parameters by BaseSpec's field names
MODEL = {
    'wheel_radius': (0.033, 'Wheel radius [m]', 0.011, 0.5),
    'wheel_separation': (0.160, 'Distance between the wheels\' contact points [m]', 0.02, 2.0),
    'mass': (1.0, 'Mass of the whole base [kg]', 0.05, 500.0),
    'max_wheel_speed': (6.9, 'Top speed of a wheel motor [rad/s]', 0.1, 200.0),
    'max_wheel_torque': (1.4, 'Torque limit of a wheel motor [N m]', 0.001, 1000.0),
    'motor_gain': (0.5, 'Velocity loop of a wheel motor: torque per speed error '
                   '[N m s/rad]', 0.001, 100.0),
    'tire_friction': (1.0, 'Sliding friction coefficient of tyres on the floor', 0.05, 5.0),
    'timestep': (0.002, 'Physics step [s]', 0.0001, 0.002),
}
LIMITS = {
    'max_linear_speed': (0.22, 'Commands are limited to this forward speed [m/s]', 0.0, 20.0),
    'max_angular_speed': (2.84, 'Commands are limited to this turn rate [rad/s]', 0.0, 50.0),
    'max_linear_accel': (2.5, 'Commands change forward speed at most this fast; 0: no limit '
                         '[m/s^2]', 0.0, 100.0),
    'max_angular_accel': (3.2, 'Commands change turn rate at most this fast; 0: no limit '
                          '[rad/s^2]', 0.0, 500.0),
}

# How the base runs (read-only but for LIVE); a text or flag parameter has no range.
RUNNING = {
    'encoder_resolution': (4096, 'Encoder ticks per wheel turn, which the odometry counts (a '
                           'Dynamixel XL430\'s)', 16, 10_000_000),
    'update_rate': (62.5, 'Rate of the base controller: commands taken, odometry published '
                    '[Hz]', 1.0, 1000.0),
    'cmd_vel_timeout': (0.5, 'The wheels stop when no command came for this long [s]', 0.01,
                        60.0),
    'cmd_vel_type': ('TwistStamped', "Message type on cmd_vel: 'TwistStamped' (ROS 2 Jazzy's "
                     "bases) or 'Twist'", None, None),
    'time_scale': (1.0, 'Simulated seconds per wall-clock second', 0.1, 1000.0),
    'command_delay': (0.0, 'Apply each cmd_vel this much later, in simulated time, order kept: '
                      'a latency for tests [s]', 0.0, 1.0),
    'command_jitter': (0.0, 'and a further random share of this, seeded [s]', 0.0, 1.0),
    'publish_clock': (False, 'Publish simulated time on /clock', None, None),
}
LIVE = frozenset(LIMITS) | {'cmd_vel_timeout'}
_KINDS = {float: 'a number with a decimal point (1.0)', int: 'a whole number', str: 'text',
          bool: 'true or false'}


class BaseConfigError(ValueError):
    """Parameters the base cannot run with; the message names each and why."""


@dataclass(frozen=True)
class BaseParameters:
    """The base's parameters as declared (with their overrides)."""

    spec: BaseSpec
    limits: DriveLimits
    encoder_resolution: int
    update_period_s: float
    cmd_vel_timeout_s: float
    cmd_vel_type: str
    time_scale: float
    publish_clock: bool
    command_delay_s: float = 0.0
    command_jitter_s: float = 0.0


def _range(low: float, high: float) -> ParameterDescriptor:
    return ParameterDescriptor(
        floating_point_range=[FloatingPointRange(from_value=low, to_value=high)])


def _declare(node: Node, problems: list[str], name: str, default, description: str, *,
             read_only: bool, low=None, high=None):
    """Declare one parameter; its value, or its default with the reason added to `problems`
    when its override is refused (so that every refusal is reported at once)."""
    if isinstance(default, int) and not isinstance(default, bool) and low is not None:
        descriptor = ParameterDescriptor(
            integer_range=[IntegerRange(from_value=low, to_value=high, step=1)])
    elif low is not None:
        descriptor = ParameterDescriptor(
            floating_point_range=[FloatingPointRange(from_value=low, to_value=high)])
    else:
        descriptor = ParameterDescriptor()
    descriptor.description, descriptor.read_only = description, read_only
    try:
        return node.declare_parameter(name, default, descriptor).value
    except InvalidParameterValueException as error:
        given = re.search(r'value: (.*): ' + re.escape(name) + '$', str(error))
        problems.append(f'{name} must be within {low:g} and {high:g}, got '
                        f'{given.group(1) if given else "a value out of range"}')
    except InvalidParameterTypeException:
        problems.append(f'{name} must be {_KINDS[type(default)]}')
    return node.declare_parameter(name, default, descriptor, ignore_override=True).value


def declare_parameters(node: Node) -> BaseParameters:
    """Declare the base's parameters on `node`.

    :raises BaseConfigError: an override out of range, or values that do not fit together.
    """
    problems: list[str] = []
    model = {name: _declare(node, problems, name, default, text, read_only=True, low=low,
                            high=high) for name, (default, text, low, high) in MODEL.items()}
    limits = {name: _declare(node, problems, name, default, text, read_only=False, low=low,
                             high=high) for name, (default, text, low, high) in LIMITS.items()}
    run = {name: _declare(node, problems, name, default, text, read_only=name not in LIVE,
                          low=low, high=high)
           for name, (default, text, low, high) in RUNNING.items()}
    cmd_vel_type, rate = run['cmd_vel_type'], run['update_rate']
    spec = BaseSpec(**model)
    problems += spec.problems()
    if cmd_vel_type not in CMD_VEL_TYPES:
        problems.append(f'cmd_vel_type must be one of {", ".join(CMD_VEL_TYPES)}, got '
                        f'{cmd_vel_type!r}')
    period = 1.0 / rate
    steps = period / spec.timestep
    if abs(steps - round(steps)) > 1e-6 * steps:
        problems.append(f'update_rate {rate:g} Hz must give a period that is a whole number of '
                        f'physics steps ({spec.timestep:g} s), got {steps:.3f} steps')
    if problems:
        raise BaseConfigError('; '.join(problems))
    return BaseParameters(spec, DriveLimits(**limits), run['encoder_resolution'], period,
                          run['cmd_vel_timeout'], cmd_vel_type, run['time_scale'],
                          run['publish_clock'], run['command_delay'], run['command_jitter'])

"""The `controller_server:` section of a Nav2 parameter file, read as our node's settings.
Pure Python.

A Nav2 stack configures its controller server with one YAML file (nav2_bringup's
`params/nav2_params.yaml`). `read_server_section` takes that section's values by their dotted
names (`FollowPath.plugin`, `general_goal_checker.xy_goal_tolerance`) and answers what our
controller server makes of them (`ServerConfig`): the controller of each id in
`controller_plugins`, the trajectory node's parameters they set, the goal and progress
checkers, and every key it does not use. A value it cannot honour raises `Nav2ConfigError`,
whose message says which key and why.

Each plugin's limits map onto the node's where they mean the same thing, under the names
Nav2's controllers give them (MPPI's `vx_max`, Regulated Pure Pursuit's `desired_linear_vel`,
DWB's `max_vel_x`, ...); a plugin's other keys that name one of our controller's `Tunable`s
set it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

from turtle_traj.core.control.goal_check import GoalChecker
from turtle_traj.core.control.tuning import Spec
from turtle_traj.core.parameters.table import PARAMETER as NODE_PARAMETERS

PLUGIN_PREFIX = 'turtle_traj::'
GOAL_CHECKERS = ('nav2_controller::SimpleGoalChecker', 'nav2_controller::StoppedGoalChecker')
PROGRESS_CHECKERS = ('nav2_controller::SimpleProgressChecker',)
GOAL_CHECKER_KEYS = ('xy_goal_tolerance', 'yaw_goal_tolerance', 'stateful',
                     'trans_stopped_velocity', 'rot_stopped_velocity')
# The node's parameter each Nav2 controller's limit sets, and its sign (MPPI's ax_min and DWB's
# decel_lim_x are negative), by the names MPPI, Regulated Pure Pursuit and DWB give them.
LIMIT_KEYS = {
    'vx_max': ('linear_speed', 1.0), 'desired_linear_vel': ('linear_speed', 1.0),
    'max_vel_x': ('linear_speed', 1.0),
    'wz_max': ('angular_speed', 1.0), 'max_vel_theta': ('angular_speed', 1.0),
    'max_angular_vel': ('angular_speed', 1.0),
    'ax_max': ('max_linear_accel', 1.0), 'max_linear_accel': ('max_linear_accel', 1.0),
    'acc_lim_x': ('max_linear_accel', 1.0),
    'ax_min': ('max_linear_decel', -1.0), 'max_linear_decel': ('max_linear_decel', 1.0),
    'decel_lim_x': ('max_linear_decel', -1.0),
    'az_max': ('max_angular_accel', 1.0), 'max_angular_accel': ('max_angular_accel', 1.0),
    'acc_lim_theta': ('max_angular_accel', 1.0),
    'path_tolerance': ('path_tolerance', 1.0),  # ours: how far a goal's path may be smoothed
}
# Keys of the server itself that it reads, with Nav2's defaults.
SERVER_DEFAULTS: dict[str, object] = {
    'controller_frequency': 20.0, 'controller_plugins': ['FollowPath'],
    'goal_checker_plugins': ['goal_checker'], 'progress_checker_plugins': ['progress_checker'],
    'odom_topic': 'odom', 'enable_stamped_cmd_vel': False, 'speed_limit_topic': 'speed_limit',
    'publish_zero_velocity': True, 'failure_tolerance': 0.0,
}
# Keys of the server it accepts without using them, and why.
NOT_USED = {
    'min_x_velocity_threshold': 'commands are never zeroed below a threshold: the exact '
                                'follower lands on the end with commands that small',
    'min_y_velocity_threshold': 'the robot is a differential drive',
    'min_theta_velocity_threshold': 'commands are never zeroed below a threshold',
    'costmap_update_timeout': 'this server has no costmap',
    'use_realtime_priority': 'the program has its own priority option',
    'path_handler_plugins': 'paths are taken whole',
}


class Nav2ConfigError(ValueError):
    """A value of the section this server cannot honour: the message names it."""


@dataclass(frozen=True)
class Checker:
    """A goal or progress checker: its Nav2 class and its parameters by name."""

    plugin: str
    values: Mapping[str, object]


@dataclass(frozen=True)
class ServerConfig:
    """What our controller server makes of a `controller_server:` section."""

    controllers: Mapping[str, str]  # controller id -> our controller's name
    node_parameters: Mapping[str, object]  # the trajectory node's parameters, by name
    goal_checkers: Mapping[str, GoalChecker]
    progress_checkers: Mapping[str, Checker]
    speed_limit_topic: str
    ignored: Sequence[str] = field(default_factory=tuple)  # keys read and not used, with why

    @property
    def default_controller(self) -> str:
        """The id a goal with an empty `controller_id` gets: the first."""
        return next(iter(self.controllers))


def read_server_section(values: Mapping[str, object], *,
                        controller_name: Callable[[str], str],
                        tunables: Callable[[str], Sequence[Spec]],
                        prefix: Callable[[str], str]) -> ServerConfig:
    """The section's `values` (dotted names, as rclpy holds a YAML file's) as a ServerConfig.

    :param controller_name: our controller's name for a plugin name (`turtle_traj::Dwpp`,
        `module:Class`); raises ValueError with the reason for any other.
    :param tunables: a controller's `Tunable`s, by our name.
    :param prefix: the prefix of a controller's tuning parameters, by our name.
    :raises Nav2ConfigError: a value that cannot be honoured.
    """
    server = {**SERVER_DEFAULTS, **{key: value for key, value in values.items()
                                    if key in SERVER_DEFAULTS}}
    used = set(SERVER_DEFAULTS) | set(NOT_USED)
    parameters, ignored = _server_settings(server, values)
    controllers: dict[str, str] = {}
    for index in _ids(server, 'controller_plugins'):
        controllers[index] = _plugin(values, index, controller_name)
        used.add(f'{index}.plugin')
        _plugin_settings(values, index, tunables(controllers[index]),
                         prefix(controllers[index]), parameters, used)
    goal_checkers = {}
    for index, checker in _checkers(values, server, 'goal_checker_plugins', GOAL_CHECKERS,
                                    used).items():
        try:
            goal_checkers[index] = GoalChecker.from_values(index, checker.plugin, checker.values)
        except ValueError as error:
            raise Nav2ConfigError(str(error)) from None
        used.update(f'{index}.{key}' for key in GOAL_CHECKER_KEYS if key in checker.values)
    progress_checkers = _checkers(values, server, 'progress_checker_plugins', PROGRESS_CHECKERS,
                                  used)
    for index in progress_checkers:
        key = f'{index}.movement_time_allowance'
        if key in values:  # no progress for this long ends the goal, as Nav2's does
            spec = NODE_PARAMETERS['progress_timeout']
            _agree(parameters, 'progress_timeout', _number(values, key, spec.low, spec.high),
                   key)
            used.add(key)
    ignored += [f'{key} ({_why_unused(key, progress_checkers)})'
                for key in sorted(values) if key not in used and not _is_ours(key)]
    return ServerConfig(controllers, parameters, goal_checkers, progress_checkers,
                        _text(server, 'speed_limit_topic'), tuple(ignored))


def _server_settings(server: Mapping[str, object], values: Mapping[str, object]
                     ) -> tuple[dict[str, object], list[str]]:
    """The node's parameters the server's own keys set, and those of its keys not used."""
    parameters: dict[str, object] = {
        'control_rate': _number(server, 'controller_frequency', 1.0, 500.0),
        'pose_source': 'odometry', 'odom_topic': _text(server, 'odom_topic'),
        'turtle_name': '', 'arena': 'none',
        'cmd_vel_type': 'TwistStamped' if _flag(server, 'enable_stamped_cmd_vel') else 'Twist'}
    ignored = [f'{key} ({why})' for key, why in NOT_USED.items() if key in values]
    if not _flag(server, 'publish_zero_velocity'):
        ignored.append('publish_zero_velocity (false: the robot is always stopped when a goal '
                       'ends)')
    if _number(server, 'failure_tolerance', -1.0, math.inf) != 0.0:
        ignored.append('failure_tolerance (a controller fault ends the goal at once)')
    return parameters, ignored


def _plugin_settings(values: Mapping[str, object], index: str, own: Sequence[Spec],
                     prefix: str, parameters: dict[str, object], used: set[str]) -> None:
    """The node's parameters a controller id's keys set: its limits under Nav2's names, and
    its controller's tunables (`<prefix>.<name>`); the keys read are added to `used`."""
    tunable = {spec.name: spec for spec in own}
    for key in _keys_under(values, index):
        dotted = f'{index}.{key}'
        if key in LIMIT_KEYS:
            target, sign = LIMIT_KEYS[key]
            spec = NODE_PARAMETERS[target]
            low, high = sorted((sign * spec.low, sign * spec.high))
            _agree(parameters, target, sign * _number(values, dotted, low, high), dotted)
        elif key in tunable:
            _agree(parameters, f'{prefix}.{key}',
                   _number(values, dotted, tunable[key].low, tunable[key].high), dotted)
        else:
            continue
        used.add(dotted)


def _why_unused(key: str, progress_checkers: Mapping[str, Checker]) -> str:
    index = key.partition('.')[0]
    if index in progress_checkers:
        return 'progress is measured along the path'
    return 'not used by this server'


def _is_ours(key: str) -> bool:
    """rclpy's own parameters, not the section's."""
    return key in ('use_sim_time', 'start_type_description_service')


def _ids(server: Mapping[str, object], key: str) -> list[str]:
    ids = server[key]
    if (isinstance(ids, str) or not isinstance(ids, Sequence) or not ids
            or not all(isinstance(value, str) and value for value in ids)):
        raise Nav2ConfigError(f'{key} must be a non-empty list of ids, not {ids!r}')
    if len(set(ids)) != len(ids):
        raise Nav2ConfigError(f'{key} names an id twice: {list(ids)}')
    return list(ids)


def _plugin(values: Mapping[str, object], index: str,
            controller_name: Callable[[str], str]) -> str:
    plugin = values.get(f'{index}.plugin')
    if not isinstance(plugin, str) or not plugin:
        raise Nav2ConfigError(f'{index}.plugin is not set: name the controller of '
                              f'controller id {index!r}')
    try:
        return controller_name(plugin)
    except ValueError as error:
        raise Nav2ConfigError(f'{index}.plugin: {error}') from None


def _keys_under(values: Mapping[str, object], index: str) -> list[str]:
    """The keys of one plugin's own section (`FollowPath.vx_max` -> `vx_max`), not nested."""
    start = f'{index}.'
    return [key[len(start):] for key in values
            if key.startswith(start) and '.' not in key[len(start):] and key != f'{index}.plugin']


def _agree(limits: dict[str, object], name: str, value: float, key: str) -> None:
    """Set the node's `name`; two controller ids that set it differently are refused."""
    if name in limits and limits[name] != value:
        raise Nav2ConfigError(f'{key} is {value:g}, but another controller id sets {name} to '
                              f'{limits[name]:g}: this server drives one robot with one set '
                              'of limits and tunings')
    limits[name] = value


def _checkers(values: Mapping[str, object], server: Mapping[str, object], key: str,
              known: Sequence[str], used: set[str]) -> dict[str, Checker]:
    checkers = {}
    for index in _ids(server, key):
        plugin = values.get(f'{index}.plugin', known[0])
        if plugin not in known:
            raise Nav2ConfigError(f'{index}.plugin {plugin!r} is not a checker this server '
                                  f"has: {', '.join(known)}")
        own = {name: values[f'{index}.{name}'] for name in _keys_under(values, index)}
        used.add(f'{index}.plugin')
        checkers[index] = Checker(plugin, own)
    return checkers


def _number(values: Mapping[str, object], key: str, low: float, high: float) -> float:
    value = values[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise Nav2ConfigError(f'{key} must be a number, not {value!r}')
    if not (math.isfinite(value) and low <= value <= high):
        raise Nav2ConfigError(f'{key} is {value!r}: it must be within [{low:g}, {high:g}]')
    return float(value)


def _text(values: Mapping[str, object], key: str) -> str:
    value = values[key]
    if not isinstance(value, str) or not value:
        raise Nav2ConfigError(f'{key} must be a topic name, not {value!r}')
    return value


def _flag(values: Mapping[str, object], key: str) -> bool:
    value = values[key]
    if not isinstance(value, bool):
        raise Nav2ConfigError(f'{key} must be true or false, not {value!r}')
    return value

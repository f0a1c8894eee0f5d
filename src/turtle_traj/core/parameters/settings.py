"""The trajectory node's settings: parameter values (`parameters.table`) turned into the frozen
Settings the controller and the planner read, and the checks of values that depend on others
(the arena, pen colours). Pure: clients and tests use it without ROS.
"""

from __future__ import annotations

from dataclasses import dataclass

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.shapes import Arena
from turtle_traj.core.parameters.table import DEFAULTS, NO_WALLS_M
from turtle_traj.core.turtlesim_contract import PenStyle


@dataclass(frozen=True)
class ShapeDefaults:
    """What a zero field of a request stands for: the `default_*` parameters and tolerances."""

    side_length: float
    radius: float
    spiral_start_radius: float
    spiral_growth: float
    sine_amplitude: float
    sine_frequency: float
    sine_length: float
    curve_width: float
    text_height: float
    svg_size: float
    goal_tolerance: float
    corner_angle: float
    corner_tolerance: float = 0.0
    path_tolerance: float = 0.0  # a Nav2 goal's path may be smoothed within this
    minimum_time_corners: bool = False  # corner_planning: 'minimum_time'


def pen_color_problem(text: str) -> str | None:
    """Why `text` is not a colour, or None."""
    from PIL import ImageColor  # Pillow knows colour names; loaded only when a colour is read
    try:
        ImageColor.getrgb(text)
    except ValueError:
        return f'pen_color {text!r} is not a colour: give a name (red) or #rrggbb'
    return None


def pen_style(color: str, width: int) -> PenStyle:
    """A pen from a colour name or #rrggbb (checked first: `pen_color_problem`) and a width."""
    from PIL import ImageColor
    r, g, b = ImageColor.getrgb(color)[:3]
    return PenStyle(r, g, b, width)


@dataclass(frozen=True)
class Settings:
    """Everything the timer and the planners read, rebuilt after every accepted change."""

    control: ControlConfig
    defaults: ShapeDefaults
    arena: Arena
    pose_timeout_s: float
    pen: PenStyle  # drawings' default pen, and the pen a drawing leaves behind
    svg_dir: str
    lifts_pen: bool = True  # drawings set turtlesim's pen (False: a base without one)


def settings_from_values(value: dict[str, object]) -> Settings:
    """Settings from parameter values by name (a node's, or ones a client fetched)."""
    control = ControlConfig(
        linear_speed=value['linear_speed'], angular_speed=value['angular_speed'],
        angular_deceleration=value['angular_deceleration'],
        position_tolerance=value['position_tolerance'],
        heading_tolerance=value['heading_tolerance'],
        period_s=1.0 / value['control_rate'],
        max_linear_accel=value['max_linear_accel'], max_linear_decel=value['max_linear_decel'],
        max_angular_accel=value['max_angular_accel'],
        progress_timeout_s=value['progress_timeout'])
    defaults = ShapeDefaults(
        side_length=value['default_side_length'], radius=value['default_radius'],
        spiral_start_radius=value['default_spiral_start_radius'],
        spiral_growth=value['default_spiral_growth'],
        sine_amplitude=value['default_sine_amplitude'],
        sine_frequency=value['default_sine_frequency'],
        sine_length=value['default_sine_length'], curve_width=value['default_curve_width'],
        text_height=value['default_text_height'], svg_size=value['default_svg_size'],
        goal_tolerance=value['goal_tolerance'], corner_angle=value['corner_angle'],
        corner_tolerance=value['corner_tolerance'], path_tolerance=value['path_tolerance'],
        minimum_time_corners=value['corner_planning'] == 'minimum_time')
    arena = (Arena(-NO_WALLS_M, -NO_WALLS_M, NO_WALLS_M, NO_WALLS_M, 0.0)
             if value['arena'] == 'none' else
             Arena(value['arena_min_x'], value['arena_min_y'], value['arena_max_x'],
                   value['arena_max_y'], value['wall_margin']))
    pen = pen_style(value['pen_color'], value['pen_width'])
    return Settings(control, defaults, arena, value['pose_timeout'], pen, value['svg_dir'],
                    lifts_pen=value['pen'] == 'turtlesim')


DEFAULT_SETTINGS = settings_from_values(DEFAULTS)
ARENA_PARAMETERS = frozenset({'arena', 'arena_min_x', 'arena_min_y', 'arena_max_x', 'arena_max_y',
                              'wall_margin'})


def arena_problem(value: dict[str, object], turtle: Pose2D | None = None) -> str | None:
    """Why these arena parameters leave no room to drive, or leave the turtle (where it stands
    now) outside the room they leave; None when they are fine (cross-field rule)."""
    if value['arena'] == 'none':
        return None
    margin = value['wall_margin']
    for axis in 'xy':
        room = value[f'arena_max_{axis}'] - value[f'arena_min_{axis}'] - 2 * margin
        if room <= 0.1:
            return (f'arena_max_{axis} - arena_min_{axis} must exceed 2 * wall_margin + 0.1 m '
                    f'(it leaves {room:.3f} m)')
    arena = Arena(value['arena_min_x'], value['arena_min_y'], value['arena_max_x'],
                  value['arena_max_y'], margin)
    if turtle is not None and not arena.contains([(turtle.x, turtle.y)]):
        return (f'the turtle stands at ({turtle.x:.2f}, {turtle.y:.2f}), outside the room this '
                f'arena leaves ({arena.describe()}, after the wall margin): move the turtle '
                'first, or choose bounds around it')
    return None

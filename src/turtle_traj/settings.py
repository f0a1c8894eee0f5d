"""The trajectory node's settings: one table of parameters (default, unit, range), and the
Settings the controller and the planner read. Pure: the node declares the table as ROS
parameters (`node.parameters`); clients and tests use it without ROS.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib.resources import files

from PIL import ImageColor

from turtle_traj.control.config import ControlConfig
from turtle_traj.geometry.path import Pose2D
from turtle_traj.geometry.shapes import Arena
from turtle_traj.turtlesim_contract import DEFAULT_PEN, WORLD_SIZE_M, PenStyle


@dataclass(frozen=True)
class Spec:
    """One parameter: default, unit, allowed range and whether it can change at run time."""

    name: str
    default: float | int | str
    description: str
    unit: str = ''
    low: float | None = None
    high: float | None = None
    read_only: bool = False


SPECS = (
    Spec('turtle_name', 'turtle1', 'Turtle to drive: topics <turtle_name>/pose and /cmd_vel',
         read_only=True),
    Spec('linear_speed', 1.0, 'Top forward speed, used when a request leaves it 0', 'm/s',
         0.01, 10.0),
    Spec('angular_speed', 2.0, 'Top turn rate, used when a request leaves it 0', 'rad/s',
         0.01, 10.0),
    Spec('heading_gain', 8.0, 'Turn rate per radian of heading error', '1/s', 0.1, 50.0),
    Spec('cross_track_gain', 2.5, 'How hard curves pull back onto the path', '1/m', 0.0, 50.0),
    Spec('deceleration', 20.0, 'Braking towards the end of a curve', 'm/s^2', 0.1, 100.0),
    Spec('angular_deceleration', 50.0, 'Braking towards the end of a turn', 'rad/s^2',
         0.1, 100.0),
    Spec('position_tolerance', 0.0005, 'End of a segment reached (corners)', 'm', 0.0005, 0.5),
    Spec('heading_tolerance', 0.0005, 'End of an in-place turn reached', 'rad', 0.0002, 0.5),
    Spec('goal_tolerance', 0.01, 'Go-to: arrived, when a request leaves it 0', 'm', 0.001, 1.0),
    Spec('corner_angle', 0.35, 'Direction changes sharper than this are turned in place',
         'rad', 0.01, 3.0),
    Spec('turn_first_angle', 0.6, 'Heading error beyond which the turtle turns before driving',
         'rad', 0.05, 3.14159),
    Spec('control_rate', 62.5, 'Control timer rate (node clock)', 'Hz', 1.0, 500.0,
         read_only=True),
    Spec('wall_margin', 0.3, 'Planned paths keep this far from the walls; a turtle closer '
         'than half of it is stopped', 'm', 0.0, 3.0),
    Spec('arena_min_x', 0.0, 'Arena left edge', 'm', -1000.0, 1000.0),
    Spec('arena_min_y', 0.0, 'Arena bottom edge', 'm', -1000.0, 1000.0),
    Spec('arena_max_x', WORLD_SIZE_M, 'Arena right edge', 'm', -1000.0, 1000.0),
    Spec('arena_max_y', WORLD_SIZE_M, 'Arena top edge', 'm', -1000.0, 1000.0),
    Spec('pose_timeout', 0.5, 'Time without a pose after which a trajectory aborts (node '
         'clock; wall clock while a simulated clock stands still)', 's', 0.05, 60.0),
    Spec('default_side_length', 2.0, 'Polygon side when a request leaves size 0', 'm',
         0.01, 50.0),
    Spec('default_radius', 1.5, 'Circle radius when a request leaves size 0', 'm', 0.01, 50.0),
    Spec('default_spiral_start_radius', 0.3, 'Spiral start radius when size is 0', 'm',
         0.01, 50.0),
    Spec('default_spiral_growth', 0.4, 'Spiral growth per turn when growth is 0', 'm',
         0.01, 50.0),
    Spec('default_sine_amplitude', 0.5, 'Sine amplitude when size is 0', 'm', 0.01, 50.0),
    Spec('default_sine_frequency', 0.5, 'Sine frequency when frequency is 0', 'cycles/m',
         0.01, 20.0),
    Spec('default_sine_length', 4.0, 'Sine length when length is 0', 'm', 0.01, 100.0),
    Spec('default_curve_width', 3.0, 'Width of a heart, lemniscate, rose or Lissajous curve '
         'when size is 0', 'm', 0.01, 50.0),
    Spec('default_text_height', 1.0, 'Height of capitals when a text request leaves height 0',
         'm', 0.01, 50.0),
    Spec('default_svg_size', 4.0, 'Larger side of an SVG drawing when size is 0', 'm',
         0.01, 50.0),
    Spec('pen_color', DEFAULT_PEN.hex, 'Pen colour of drawings (text, SVG) when a request '
         'gives none, and the colour the pen is left with: a name (red) or #rrggbb; '
         f"turtlesim's own is {DEFAULT_PEN.hex}"),
    Spec('pen_width', DEFAULT_PEN.width, 'Pen width of drawings when a request leaves it 0 '
         f'(turtlesim: {DEFAULT_PEN.width})', 'px', 1, 255),
    Spec('svg_dir', str(files('turtle_traj') / 'drawings'), 'Folder the draw_svg service reads '
         'files from (requests name them relative to it)', read_only=True),
)


SPEC = {spec.name: spec for spec in SPECS}
DEFAULTS = {spec.name: spec.default for spec in SPECS}


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


def pen_color_problem(text: str) -> str | None:
    """Why `text` is not a colour, or None."""
    try:
        ImageColor.getrgb(text)
    except ValueError:
        return f'pen_color {text!r} is not a colour: give a name (red) or #rrggbb'
    return None


def pen_style(color: str, width: int) -> PenStyle:
    """A pen from a colour name or #rrggbb (checked first: `pen_color_problem`) and a width."""
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


def settings_from_values(value: dict[str, object]) -> Settings:
    """Settings from parameter values by name (a node's, or ones a client fetched)."""
    control = ControlConfig(
        linear_speed=value['linear_speed'], angular_speed=value['angular_speed'],
        heading_gain=value['heading_gain'], cross_track_gain=value['cross_track_gain'],
        deceleration=value['deceleration'], angular_deceleration=value['angular_deceleration'],
        position_tolerance=value['position_tolerance'],
        heading_tolerance=value['heading_tolerance'],
        turn_first_angle=value['turn_first_angle'], period_s=1.0 / value['control_rate'])
    defaults = ShapeDefaults(
        side_length=value['default_side_length'], radius=value['default_radius'],
        spiral_start_radius=value['default_spiral_start_radius'],
        spiral_growth=value['default_spiral_growth'],
        sine_amplitude=value['default_sine_amplitude'],
        sine_frequency=value['default_sine_frequency'],
        sine_length=value['default_sine_length'], curve_width=value['default_curve_width'],
        text_height=value['default_text_height'], svg_size=value['default_svg_size'],
        goal_tolerance=value['goal_tolerance'], corner_angle=value['corner_angle'])
    arena = Arena(value['arena_min_x'], value['arena_min_y'], value['arena_max_x'],
                  value['arena_max_y'], value['wall_margin'])
    pen = pen_style(value['pen_color'], value['pen_width'])
    return Settings(control, defaults, arena, value['pose_timeout'], pen, value['svg_dir'])


DEFAULT_SETTINGS = settings_from_values(DEFAULTS)
ARENA_PARAMETERS = frozenset({'arena_min_x', 'arena_min_y', 'arena_max_x', 'arena_max_y',
                              'wall_margin'})


def arena_problem(value: dict[str, object], turtle: Pose2D | None = None) -> str | None:
    """Why these arena parameters leave no room to drive, or leave the turtle (where it stands
    now) outside the room they leave; None when they are fine (cross-field rule)."""
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

"""The trajectory node's parameters as one table: name, default, unit, range and whether each
can change at run time. Pure data (no numpy, no Pillow): the node declares it
(`node.parameters`), `settings` turns values into Settings, and the command line shows it."""

from __future__ import annotations

import os

from turtle_traj.core.control.tuning import Spec
from turtle_traj.core.turtlesim_contract import DEFAULT_PEN, WORLD_SIZE_M

# The drawings shipped with the package (os.path: importlib.resources costs `--help` 6 ms).
_DRAWINGS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(
    __file__)))), 'drawings')


NO_WALLS_M = 100.0  # with arena 'none': how far from the origin paths may go


PARAMETERS = (
    Spec('turtle_name', 'turtle1', 'Turtle to drive: topics <turtle_name>/pose and /cmd_vel '
         "(empty: the node's namespace's own pose and cmd_vel, a turtle's node in its namespace)",
         read_only=True),
    Spec('pose_source', 'turtlesim', "Where the pose comes from: 'turtlesim' "
         "(turtlesim/Pose on <turtle_name>/pose) or 'odometry' (nav_msgs/Odometry on "
         'odom_topic)', read_only=True, choices=('turtlesim', 'odometry')),
    Spec('odom_topic', 'odom', "The pose topic when pose_source is 'odometry' (relative "
         'names follow the namespace)', read_only=True),
    Spec('cmd_vel_topic', '', 'Velocity command topic (empty: <turtle_name>/cmd_vel)',
         read_only=True),
    Spec('cmd_vel_type', 'Twist', "Message type of velocity commands: 'Twist' (turtlesim) "
         "or 'TwistStamped' (diff_drive_controller on Jazzy)", read_only=True,
         choices=('Twist', 'TwistStamped')),
    Spec('cmd_vel_frame_id', 'base_link', 'frame_id of TwistStamped commands', read_only=True),
    Spec('controller', 'exact', "The path-following controller: 'exact' (turtle_traj's own "
         "follower), 'dwpp' (Dynamic Window Pure Pursuit), 'pure_pursuit' (with Regulated Pure "
         "Pursuit's regulations), an entry point of the group turtle_traj.controllers by name, "
         'or package.module:Class', read_only=True),
    Spec('linear_speed', 1.0, 'Top forward speed, used when a request leaves it 0', 'm/s',
         0.01, 10.0),
    Spec('angular_speed', 2.0, 'Top turn rate, used when a request leaves it 0', 'rad/s',
         0.01, 10.0),
    Spec('angular_deceleration', 50.0, 'Braking towards the end of a turn, on a base without '
         'acceleration limits (with them, max_angular_accel brakes)', 'rad/s^2', 0.1, 100.0),
    Spec('max_linear_accel', 0.0, "The base's linear acceleration limit: no command asks "
         'for more; 0 = unlimited (turtlesim)', 'm/s^2', 0.0, 100.0),
    Spec('max_linear_decel', 0.0, "The base's braking limit; 0 = max_linear_accel",
         'm/s^2', 0.0, 100.0),
    Spec('max_angular_accel', 0.0, "The base's angular acceleration limit; 0 = unlimited "
         '(turtlesim)', 'rad/s^2', 0.0, 100.0),
    Spec('corner_tolerance', 0.0, 'Corners may be rounded by up to this much, so the base '
         'keeps moving, when a request leaves it 0; 0 = exact corners, turned in place', 'm',
         0.0, 1.0),
    Spec('path_tolerance', 0.0, "Nav2's goals (the follow_path action): the path may be "
         "smoothed within this of the planner's, its corners rounded, so a grid planner's "
         'staircase is driven as the way it sketches (a corner_tolerance for its goals; '
         '0.05 suits 5 cm cells); 0 = exact', 'm', 0.0, 1.0),
    Spec('corner_planning', 'tube', "How corners within a tolerance are planned on a base "
         "with acceleration limits: 'tube' (the fastest of clothoid corners, racing lines and "
         "smoothings in the tube: tenths of a second for a few metres) or 'minimum_time' (also "
         'the minimum-time trajectory in the tube, by CasADi and IPOPT: seconds for a few '
         'metres, beside the executor)',
         choices=('tube', 'minimum_time')),
    Spec('progress_timeout', 3.0, 'A run that makes no progress along its path for this long '
         'ends with a message (a base slower than its limits, a blocked robot)', 's',
         0.5, 60.0),
    Spec('position_tolerance', 0.0005, 'End of a segment reached (corners)', 'm', 0.0005, 0.5),
    Spec('heading_tolerance', 0.0005, 'End of an in-place turn reached', 'rad', 0.0002, 0.5),
    Spec('goal_tolerance', 0.01, 'Go-to: arrived, when a request leaves it 0', 'm', 0.001, 1.0),
    Spec('corner_angle', 0.35, 'Direction changes sharper than this are turned in place',
         'rad', 0.01, 3.0),
    Spec('control_rate', 62.5, 'Control timer rate (node clock)', 'Hz', 1.0, 500.0,
         read_only=True),
    Spec('arena', 'rectangle', "The arena check: 'rectangle' (arena_min_* to arena_max_*, "
         "turtlesim's walls by default) or 'none' (a base in open space: paths stay within "
         f'{NO_WALLS_M:g} m of the origin, no wall stops)', choices=('rectangle', 'none')),
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
    Spec('pen', 'turtlesim', "How drawings (text, SVG) lift the pen between strokes: "
         "'turtlesim' (its <turtle_name>/set_pen service) or 'none' (a base without a pen: the "
         'strokes and the moves between them are driven alike)', choices=('turtlesim', 'none')),
    Spec('pen_color', DEFAULT_PEN.hex, 'Pen colour of drawings (text, SVG) when a request '
         'gives none, and the colour the pen is left with: a name (red) or #rrggbb; '
         f"turtlesim's own is {DEFAULT_PEN.hex}"),
    Spec('pen_width', DEFAULT_PEN.width, 'Pen width of drawings when a request leaves it 0 '
         f'(turtlesim: {DEFAULT_PEN.width})', 'px', 1, 255),
    Spec('svg_dir', _DRAWINGS, 'Folder the draw_svg service reads '
         'files from (requests name them relative to it)', read_only=True),
    Spec('record_dir', '', 'Record every run as a rosbag2 bag (MCAP) in this folder, named '
         'after the trajectory and the time (empty: no recording)', read_only=True),
)


PARAMETER = {spec.name: spec for spec in PARAMETERS}  # by name
DEFAULTS = {spec.name: spec.default for spec in PARAMETERS}

"""The registry of trajectory kinds: one entry per kind, from which everything else is made.

The node's services, the command line, the menu, the demo and the benchmarks all iterate over
`TRAJECTORIES`. Adding a trajectory is one entry here plus its geometry and its sketch
function in `planning.SKETCHES`.
Pure: service types are named by their ROS type string and resolved by the ROS layers.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from turtle_traj.core.fields import BOOL, INT, POINTS, STRING, Field
from turtle_traj.core.parameters.table import PARAMETER
from turtle_traj.core.planning.limits import (
    MAX_FREQUENCY_RATIO,
    MAX_PETALS,
    MAX_POINTS,
    MAX_SIDES,
    MAX_TIPS,
)


@dataclass(frozen=True)
class Example:
    """A request worth showing: the demo draws it, the benchmarks measure it."""

    start: tuple[float, float, float]  # where the turtle starts: x, y [m], heading [rad]
    given: Mapping[str, Any]  # values as entered (see `TrajectoryKind.request_values`)


@dataclass(frozen=True)
class TrajectoryKind:
    """One kind of trajectory: its names, its service type and its fields (data only: the
    planner maps the name to its geometry, `planning.SKETCHES`)."""

    name: str  # as an action goal names it ('square')
    service: str  # the node's service ('draw_square')
    service_type: str  # ROS type of the service ('turtle_traj_interfaces/srv/DrawShape')
    summary: str
    fields: tuple[Field, ...]
    command: tuple[str, ...]  # command-line words ('draw', 'square')
    example: Example

    def excluded(self, given: Mapping[str, Any]) -> set[str]:
        """Fields that flags given true exclude (`forever` excludes a circle's `turns`)."""
        return {item.excludes for item in self.fields if item.excludes and given.get(item.name)}

    def request_values(self, given: Mapping[str, Any]) -> dict[str, Any]:
        """Request field values from values as entered (missing ones take their defaults)."""
        values = {}
        excluded = self.excluded(given)
        for item in self.fields:
            value = given.get(item.name)
            if value is None:
                if item.name in excluded:
                    values[item.name] = 0.0
                elif item.default is not None:
                    values[item.name] = item.to_request(item.default)
                if item.given:
                    values[item.given] = False
                continue
            if item.negate and given.get(item.negate):
                value = -value
            values[item.name] = item.to_request(value)
            if item.given:
                values[item.given] = True
        return values


# -- the fields people enter, shared by several kinds -----------------------------------------

def _size(help_text: str, parameter: str) -> Field:
    return Field('size', help_text, parameter=parameter, fits=True)


CLOCKWISE = Field('clockwise', 'turn clockwise', type=BOOL, default=False)
LINEAR_SPEED = Field('linear_speed', 'top speed', parameter='linear_speed', flag='speed')
ANGULAR_SPEED = Field('angular_speed', 'top turn rate (corners)', parameter='angular_speed',
                      menu=False)
_SHAPE_SPEEDS = (LINEAR_SPEED, ANGULAR_SPEED)
CORNER_TOLERANCE = Field('corner_tolerance', 'round corners by up to this much, to keep moving',
                         parameter='corner_tolerance', menu=False)
CORNER_ANGLE = Field('corner_angle', 'turn in place where the direction changes more than this',
                     parameter='corner_angle', menu=False)
PEN_CORNER_TOLERANCE = Field('corner_tolerance', 'round pen-down corners by up to this much '
                             '(default: exact, whatever the parameter)', 'm', low=0.0,
                             high=PARAMETER['corner_tolerance'].high, menu=False)
_DRAW_SHAPE = 'turtle_traj_interfaces/srv/DrawShape'
_DRAW_CURVE = 'turtle_traj_interfaces/srv/DrawCurve'
_PEN = (Field('pen_color', "pen colour: a name (red) or #rrggbb; default: the node's "
              'pen_color', type=STRING, default='', menu=False),
        Field('pen_width', "pen width [px]; default: the node's pen_width", type=INT,
              default=0, low=0, high=255, menu=False))


def _curve(name: str, summary: str, fields: tuple[Field, ...], example: Example) -> TrajectoryKind:
    """A parametric curve (DrawCurve): its width (`size`), its own fields and the speeds."""
    return TrajectoryKind(name, f'draw_{name}', _DRAW_CURVE, summary,
                      (_size('width', 'default_curve_width'), *fields, *_SHAPE_SPEEDS,
                       CORNER_TOLERANCE),
                      ('draw', name), example)


def _polygon(name: str, example: Example) -> TrajectoryKind:
    return TrajectoryKind(
        name, f'draw_{name}', _DRAW_SHAPE, f'draw a {name} from where the turtle stands',
        (_size('side length', 'default_side_length'), CLOCKWISE, *_SHAPE_SPEEDS,
         CORNER_TOLERANCE), ('draw', name), example)


def _move(name: str, summary: str, amount: Field, speed: str,
          example: Example) -> TrajectoryKind:
    """A Move request: a signed amount and its top speed (the node's `speed` parameter)."""
    return TrajectoryKind(
        name, name, 'turtle_traj_interfaces/srv/Move', summary,
        (amount, Field('speed', PARAMETER[speed].description.split(',')[0].lower(),
                       parameter=speed, menu=False)),
        (name,), example)


TRAJECTORIES: tuple[TrajectoryKind, ...] = (
    _polygon('square', Example((4.0, 4.0, 0.0), {'size': 3.0})),
    _polygon('triangle', Example((3.5, 3.5, 0.0), {'size': 4.0})),
    _polygon('hexagon', Example((4.5, 2.5, 0.0), {'size': 2.0})),
    TrajectoryKind(
        'polygon', 'draw_polygon', _DRAW_SHAPE,
        'draw a regular polygon with any number of sides',
        (Field('sides', 'number of sides', type=INT, default=5, low=3, high=MAX_SIDES),
         _size('side length', 'default_side_length'), CLOCKWISE, *_SHAPE_SPEEDS,
         CORNER_TOLERANCE), ('draw', 'polygon'),
        Example((4.5, 8.5, 0.0), {'sides': 7, 'size': 2.0, 'clockwise': True})),
    TrajectoryKind(
        'circle', 'draw_circle', _DRAW_SHAPE,
        'drive a circle to the left (or right) of the turtle',
        (_size('radius', 'default_radius'), CLOCKWISE,
         Field('forever', 'circle until stopped (Ctrl-C, cancel or the stop service)',
               type=BOOL, default=False, excludes='turns'),
         Field('turns', 'number of turns', 'turns', default=1.0, low=0.01, high=100.0),
         *_SHAPE_SPEEDS),
        ('draw', 'circle'), Example((5.5, 3.0, 0.0), {'size': 2.5})),
    TrajectoryKind(
        'spiral', 'draw_spiral', _DRAW_SHAPE,
        'drive an outward spiral; it ends at max_radius, after its turns, or before the wall',
        (_size('start radius', 'default_spiral_start_radius'),
         Field('growth', 'radius gained per turn', parameter='default_spiral_growth'),
         Field('turns', 'number of turns (0: until max_radius or the wall)', 'turns',
               low=0.0, high=100.0),
         Field('max_radius', 'radius at which it ends (0: the wall)', 'm', low=0.0, high=50.0,
               menu=False),
         CLOCKWISE, *_SHAPE_SPEEDS),
        ('draw', 'spiral'), Example((5.5, 5.2, 0.0), {'size': 0.3, 'growth': 0.6, 'turns': 6.0,
                                             'linear_speed': 2.0})),
    TrajectoryKind(
        'sine', 'draw_sine', _DRAW_SHAPE,
        'drive a sine wave along the heading',
        (Field('size', 'amplitude', parameter='default_sine_amplitude'),
         Field('frequency', 'cycles per metre', parameter='default_sine_frequency'),
         Field('length', 'length along the heading', parameter='default_sine_length',
               fits=True),
         *_SHAPE_SPEEDS),
        ('draw', 'sine'),
        Example((1.0, 5.5, 0.0), {'size': 1.5, 'frequency': 0.4, 'length': 9.0})),
    TrajectoryKind(
        'star', 'draw_star', _DRAW_CURVE,
        'draw a star, upright, from its top tip',
        (_size('outer radius', 'default_radius'),
         Field('tips', 'number of points', type=INT, default=5, low=3, high=MAX_TIPS),
         Field('inner_radius', 'radius of the inner corners (default: 0.382 x size)', 'm',
               low=0.0, high=50.0, menu=False),
         *_SHAPE_SPEEDS, CORNER_TOLERANCE),
        ('draw', 'star'), Example((5.5, 8.5, 0.0), {'size': 3.0, 'tips': 5})),
    _curve('heart', 'draw a heart, upright, from its bottom tip', (),
           Example((5.5, 1.5, 0.0), {'size': 7.0})),
    _curve('lemniscate',
           'draw the infinity sign (lemniscate of Bernoulli), from its crossing', (),
           Example((5.5, 5.5, 0.0), {'size': 9.0})),
    _curve('rose',
           'draw a rose r = sin(k t), from its centre (size: the circle through its tips)',
           (Field('petals', 'number of petals (odd, or a multiple of 4)', type=INT, default=5,
                  low=1, high=MAX_PETALS),),
           Example((5.5, 5.5, 0.0), {'size': 9.0, 'petals': 5})),
    _curve('lissajous',
           'draw a Lissajous curve x = sin(a t + phase), y = sin(b t)',
           (Field('a', 'x frequency', type=INT, default=3, low=1, high=MAX_FREQUENCY_RATIO),
            Field('b', 'y frequency', type=INT, default=2, low=1, high=MAX_FREQUENCY_RATIO),
            Field('phase', 'phase of x', 'deg', default=90.0, low=-360.0, high=360.0)),
           Example((9.5, 5.5, 0.0), {'size': 8.0, 'a': 3, 'b': 2, 'phase': 90.0})),
    TrajectoryKind(
        'text', 'draw_text', 'turtle_traj_interfaces/srv/DrawText',
        'write text in a single-stroke font, along the heading from where the turtle stands',
        (Field('text', 'what to write', type=STRING, default='', positional=True),
         Field('height', 'height of capitals', parameter='default_text_height', fits=True),
         *_PEN, *_SHAPE_SPEEDS, PEN_CORNER_TOLERANCE),
        ('write',), Example((1.5, 5.0, 0.0), {'text': 'Hello ROS', 'height': 1.0,
                                     'pen_color': 'white'})),
    TrajectoryKind(
        'svg', 'draw_svg', 'turtle_traj_interfaces/srv/DrawSvg',
        "draw SVG paths: a file in the node's svg_dir, or path data (--d)",
        (Field('file', "SVG file, relative to the node's svg_dir (turtle.svg, wave.svg ship "
               'with it)', type=STRING, default='', positional=True),
         Field('path_data', 'SVG path data instead of a file ("M 0 0 C 1 2 3 2 4 0")',
               type=STRING, default='', flag='d'),
         _size('larger side', 'default_svg_size'), *_PEN, *_SHAPE_SPEEDS,
         PEN_CORNER_TOLERANCE),
        ('draw', 'svg'), Example((1.0, 2.5, 0.0), {'file': 'turtle.svg', 'size': 9.0,
                                          'pen_color': 'white'})),
    TrajectoryKind(
        'go_to', 'go_to', 'turtle_traj_interfaces/srv/GoTo',
        'drive to a point (turn, drive straight, optionally turn to a heading)',
        (Field('x', 'goal x', 'm', default=8.0, positional=True, axis='x'),
         Field('y', 'goal y', 'm', default=8.0, positional=True, axis='y'),
         Field('theta', 'final heading (default: none)', 'deg', default=None,
               given='use_theta', low=-180.0, high=180.0, menu=False),
         Field('tolerance', 'arrival tolerance', parameter='goal_tolerance', menu=False),
         CORNER_ANGLE, LINEAR_SPEED),
        ('go-to',), Example((1.5, 1.5, 0.0), {'x': 9.5, 'y': 9.0, 'theta': 180.0})),
    _move('move', 'drive straight along the heading',
          Field('distance', 'distance (negative: backwards)', 'm', default=2.0, low=-50.0,
                high=50.0, positional=True, negate='backward'),
          'linear_speed', Example((2.5, 5.5, 0.0), {'distance': 6.0})),
    _move('rotate',
          'turn in place (counter-clockwise; negative or --clockwise: clockwise)',
          Field('angle', 'angle (negative: clockwise)', 'deg', default=90.0, low=-36000.0,
                high=36000.0, positional=True, negate='clockwise'),
          'angular_speed', Example((5.5, 5.5, 0.0), {'angle': -180.0})),
    TrajectoryKind(
        'follow_path', 'follow_path', 'turtle_traj_interfaces/srv/FollowPath',
        'drive through points in order (x,y x,y ...)',
        (Field('points', f'points as x,y pairs (at most {MAX_POINTS})', 'm', type=POINTS,
               default=None, positional=True),
         Field('closed', 'return to the first point', type=BOOL, default=False),
         Field('theta', 'final heading (default: none)', 'deg', default=None,
               given='use_theta', low=-180.0, high=180.0, menu=False),
         CORNER_ANGLE, LINEAR_SPEED, CORNER_TOLERANCE),
        ('follow-path',), Example((2.5, 2.5, 0.0), {
            'points': [(8.5, 2.5), (8.5, 8.5), (5.5, 5.5), (2.5, 8.5)], 'closed': True})),
)
BY_NAME = {trajectory.name: trajectory for trajectory in TRAJECTORIES}
# Kinds that move the turtle without drawing a picture: a fleet has nothing to share in them.
NOT_DRAWINGS = frozenset({'go_to', 'move', 'rotate'})

"""What a fleet's request and the coordinator's parameters must be: checked before a turtle
moves."""

from __future__ import annotations

import itertools
import math
import re

from rcl_interfaces.msg import SetParametersResult
from rclpy.parameter import Parameter

from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import pen_color_problem
from turtle_traj.core.registry import NOT_DRAWINGS

_TURTLE_NAME = re.compile(r'[A-Za-z][A-Za-z0-9_]*')


def colors(text: str) -> list[str]:
    """The colours of `turtle_colors` (comma-separated)."""
    return [color.strip() for color in text.split(',') if color.strip()]


def colors_problem(parameters: list[Parameter]) -> SetParametersResult:
    """A `turtle_colors` that names something not a colour is refused, saying which."""
    for parameter in parameters:
        if parameter.name == 'turtle_colors':
            for color in colors(parameter.value):
                if problem := pen_color_problem(color):
                    return SetParametersResult(successful=False, reason=problem)
    return SetParametersResult(successful=True)


def too_close(turtles: list[tuple[str, Pose2D]], clearance: float) -> str:
    """Why the turtles cannot start apart: two already stand closer than the clearance."""
    for (first, a), (second, b) in itertools.combinations(turtles, 2):
        if (gap := math.hypot(a.x - b.x, a.y - b.y)) < clearance:
            return (f'{first} and {second} stand {gap:.2f} m apart, closer than the clearance '
                    f'({clearance:g} m): move one away first')
    return ''


def names_problem(names: list[str], trajectory: str) -> str:
    """Why a goal's trajectory and turtles cannot be drawn ('' if they can)."""
    if trajectory in NOT_DRAWINGS:
        return (f'{trajectory!r} is not a drawing: a fleet draws shapes, curves, text, svg '
                'and paths')
    if not names:
        return 'no turtle: name some, or start trajectory nodes in turtles\' namespaces'
    bad = [name for name in names if not _TURTLE_NAME.fullmatch(name)]
    if bad:
        return f'not a turtle name: {bad[0]!r}'
    if len(set(names)) != len(names):
        return 'a turtle is named twice'
    return ''

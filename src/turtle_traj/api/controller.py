"""Everything a controller of your own needs, from one module: the documented API.

A controller follows one stroke at a time: `start(stroke, limits)` as a stroke begins, then
`command(state)` every control period, answering a `Command` or None once the stroke's end is
reached (the node checks that claim: the stroke driven in order, the robot at its end).
Numbers it can be tuned by are `Tunable` class attributes, served by the node as the ROS
parameters `<controller>.<name>`. See the tutorial "Write your own controller".
"""

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.controller import Controller, Limits, State, Stroke
from turtle_traj.core.control.prediction import Prediction
from turtle_traj.core.control.tuning import Tunable
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Pose2D

__all__ = ['Command', 'Controller', 'Limits', 'Pose2D', 'Prediction', 'State', 'Stroke',
           'Tunable', 'wrap_angle']

"""The trajectory node's service names (private, `<node>/<name>`) and their types."""

from std_srvs.srv import Trigger
from turtle_traj_interfaces.srv import DrawShape, FollowPath, GoTo, Move

from turtle_traj.planning import SHAPES

TRAJECTORY_SERVICES = {
    **{f'draw_{shape}': DrawShape for shape in SHAPES},
    'go_to': GoTo, 'move': Move, 'rotate': Move, 'follow_path': FollowPath,
}
SERVICE_TYPES = {**TRAJECTORY_SERVICES, 'stop': Trigger, 'reset': Trigger}

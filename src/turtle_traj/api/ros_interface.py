"""The trajectory node's ROS interface: a service per registry entry, their types, and requests
made from values as entered.

The node's services are private (`<node>/<service>`); besides one per trajectory it has `stop`
and `reset` (std_srvs/srv/Trigger). Its action `<node>/draw` runs any trajectory as a goal.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from geometry_msgs.msg import Point

from turtle_traj.core.fields import POINTS
from turtle_traj.core.registry import TRAJECTORIES, TrajectoryKind
from turtle_traj.rosutils.interfaces import interface


def service_type(trajectory: TrajectoryKind) -> type:
    return interface(trajectory.service_type)


def _message_values(trajectory: TrajectoryKind, given: Mapping[str, Any]) -> dict[str, Any]:
    values = trajectory.request_values(given)
    for item in trajectory.fields:
        if item.type == POINTS and item.name in values:
            values[item.name] = [Point(x=float(x), y=float(y)) for x, y in values[item.name]]
    return values


def make_request(trajectory: TrajectoryKind, given: Mapping[str, Any]):
    """The service request for values as entered (see `TrajectoryKind.request_values`)."""
    return service_type(trajectory).Request(**_message_values(trajectory, given))


def make_goal(trajectory: TrajectoryKind, given: Mapping[str, Any]):
    """The draw action's goal for values as entered: the same fields as the service request."""
    return interface(DRAW_ACTION_TYPE).Goal(trajectory=trajectory.name,
                                            **_message_values(trajectory, given))


def make_fleet_goal(trajectory: TrajectoryKind, given: Mapping[str, Any], turtles: list[str]):
    """The fleet coordinator's goal: the same drawing, drawn by `turtles` together."""
    return interface(FLEET_ACTION_TYPE).Goal(
        drawing=interface(DRAWING_TYPE)(trajectory=trajectory.name,
                                        **_message_values(trajectory, given)),
        turtles=turtles)


DRAW_ACTION, DRAW_ACTION_TYPE = 'draw', 'turtle_traj_interfaces/action/Draw'
# The fleet coordinator (`up --turtles N`) serves its own draw action: FleetDraw, whose goal
# carries a Drawing (Draw's goal, field for field).
FLEET_NODE, FLEET_ACTION_TYPE = '/fleet', 'turtle_traj_interfaces/action/FleetDraw'
DRAWING_TYPE = 'turtle_traj_interfaces/msg/Drawing'
COMMAND_SERVICES = {'stop': 'std_srvs/srv/Trigger', 'reset': 'std_srvs/srv/Trigger'}
SERVICE_TYPES: dict[str, type] = {
    **{trajectory.service: service_type(trajectory) for trajectory in TRAJECTORIES},
    **{name: interface(type_name) for name, type_name in COMMAND_SERVICES.items()}}

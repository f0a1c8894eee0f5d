"""A draw goal's handle when its answer was lost, and how a goal ended.

rclpy gives a `ClientGoalHandle` only with the answer to the goal request; when DDS loses that
answer (see `turtle_traj.client.answers`) the request is sent again under the same goal id, and
the action server rejects an id it already has. The goal runs all the same, so the client
follows it by its id: `known_goal` builds the handle rclpy would have built from an accepted
answer (rclpy has no public way to adopt a goal by id; its own futures can also be lost,
ros2/rclpy#1123). Pinned by tests/test_client.py, which drops the first answer.
"""

from __future__ import annotations

from dataclasses import dataclass

from rclpy.action import ActionClient
from rclpy.action.client import ClientGoalHandle
from unique_identifier_msgs.msg import UUID

from turtle_traj.api.ros_interface import DRAW_ACTION_TYPE
from turtle_traj.rosutils.interfaces import interface


@dataclass(frozen=True)
class DrawOutcome:
    """How a draw goal ended: its result (Draw.Result), its GoalStatus, and, when this client
    cancelled it, why."""

    result: object
    status: int
    cancelled: str = ''


def known_goal(action: ActionClient, goal_id: UUID) -> ClientGoalHandle:
    """A handle for a goal the server has under this id, though its answer never came."""
    accepted = interface(DRAW_ACTION_TYPE).Impl.SendGoalService.Response(accepted=True)
    return ClientGoalHandle(action, goal_id, accepted)


def goal_handle(action: ActionClient, goal_id: UUID, answer: ClientGoalHandle,
                repeated: bool) -> ClientGoalHandle:
    """The handle of the goal sent. A repeated request carries the same goal id, and an action
    server rejects an id it already has: the first request got through and its answer was
    lost, so the goal runs and is followed by its id."""
    if answer.accepted or not repeated:
        return answer
    return known_goal(action, goal_id)

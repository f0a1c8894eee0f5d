"""The trajectory node's services, one per registry entry (`~/draw_square`, `~/go_to`, ...):
each request is refused at once or driven to its end, and its response filled either way."""

from __future__ import annotations

from functools import partial

from rclpy.callback_groups import CallbackGroup
from rclpy.node import Node

from turtle_traj.api.ros_interface import service_type
from turtle_traj.core.registry import TRAJECTORIES, TrajectoryKind
from turtle_traj.node.async_service import create_async_service
from turtle_traj.node.outcomes import RunRefused, fill_response
from turtle_traj.node.running import RunningNode
from turtle_traj.node.waiting import completion


class TrajectoryServices:
    """The services of `node`, driving through `runs`; their handlers in `group` (they await
    the run's end)."""

    def __init__(self, node: Node, runs: RunningNode, group: CallbackGroup) -> None:
        self._node, self._runs = node, runs
        for kind in TRAJECTORIES:
            create_async_service(node, service_type(kind), f'~/{kind.service}',
                                 partial(self._execute, kind), callback_group=group)

    async def _execute(self, kind: TrajectoryKind, request, response):
        runs = self._runs
        try:
            _run, finished = await runs.start_run(kind, request)
        except RunRefused as refusal:
            return fill_response(response, refusal.outcome(runs.pose))
        return fill_response(response, await completion(self._node, finished))

"""The Draw action of the trajectory node: any trajectory by name, with feedback.

Every goal is accepted (rclpy's default goal callback): one that cannot run ends ABORTED with
the reason in its result, which any action client can read. A goal id the server already knows
is rejected by rclpy, which makes a client's repeat of an unanswered request harmless
(`client/goals.py`).
"""

from __future__ import annotations

import math

from rclpy.action import ActionServer, CancelResponse
from rclpy.action.server import ServerGoalHandle
from rclpy.callback_groups import CallbackGroup
from rclpy.node import Node
from turtle_traj_interfaces.action import Draw

from turtle_traj.api.ros_interface import DRAW_ACTION
from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.supervisor import Outcome, RunSupervisor
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.registry import BY_NAME
from turtle_traj.node.outcomes import RunRefused, fill_response
from turtle_traj.node.running import RunningNode
from turtle_traj.node.waiting import completion

FEEDBACK_PERIOD_S = 0.1  # node clock: 10 Hz


class DrawActionServer:
    """`~/draw` on `node`: starts runs through `runs` and reports on them."""

    def __init__(self, node: Node, runs: RunningNode, callback_group: CallbackGroup) -> None:
        self._runs, self._ros = runs, node
        self._goals: dict[bytes, RunSupervisor] = {}  # goals running, by goal id
        self.name = f'{node.get_fully_qualified_name()}/{DRAW_ACTION}'
        self._server = ActionServer(node, Draw, f'~/{DRAW_ACTION}', self._execute,
                                    cancel_callback=self._on_cancel,
                                    callback_group=callback_group)

    def destroy(self) -> None:
        """Destroy the action server (rclpy's destroy_node leaves a node's actions alive)."""
        self._server.destroy()

    def _on_cancel(self, goal_handle: ServerGoalHandle) -> CancelResponse:
        """Stop this goal's run at once (not another's); the goal then ends CANCELED."""
        goal_id = bytes(goal_handle.goal_id.uuid)
        run = self._goals.get(goal_id)
        if run is not None:
            self._runs.stop_run(run, Ending.CANCELLED)
        else:  # its plan may be being made
            self._runs.stop_planning(goal_handle.request, Ending.CANCELLED)
        return CancelResponse.ACCEPT

    async def _execute(self, goal_handle: ServerGoalHandle) -> Draw.Result:
        runs, goal = self._runs, goal_handle.request
        if goal_handle.is_cancel_requested:  # cancelled before it started
            goal_handle.canceled()
            return fill_response(Draw.Result(), Outcome(
                False, 'cancelled before it started', Ending.CANCELLED, runs.pose))
        try:
            kind = BY_NAME.get(goal.trajectory)
            if kind is None:
                raise runs.refuse(f'unknown trajectory {goal.trajectory!r}; known: '
                                  f'{", ".join(BY_NAME)}', Ending.INVALID_REQUEST)
            run, finished = await runs.start_run(kind, goal)
        except RunRefused as refusal:  # busy, bad numbers, no simulator, cancelled meanwhile
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
            else:
                goal_handle.abort()
            return fill_response(Draw.Result(), refusal.outcome(runs.pose))
        goal_id = bytes(goal_handle.goal_id.uuid)
        self._goals[goal_id] = run
        feedback = self._ros.create_timer(
            FEEDBACK_PERIOD_S, lambda: goal_handle.publish_feedback(self._feedback(run)))
        try:
            outcome = await completion(self._ros, finished)
        finally:
            self._ros.destroy_timer(feedback)
            del self._goals[goal_id]
        # the last feedback is the run as it ended (a timer's last one may come up to its
        # period before the end, or a step's pose behind on a loaded machine)
        goal_handle.publish_feedback(self._feedback(run))
        if goal_handle.is_cancel_requested:
            goal_handle.canceled()
        elif outcome.success:
            goal_handle.succeed()
        else:
            goal_handle.abort()
        return fill_response(Draw.Result(), outcome)

    def _feedback(self, run: RunSupervisor) -> Draw.Feedback:
        runs = self._runs
        pose = runs.pose or Pose2D(math.nan, math.nan, math.nan)
        return Draw.Feedback(
            progress=run.progress(runs.settings.control), distance=run.distance,
            elapsed=runs.now_s() - run.started_s, deviation=run.deviation,
            x=pose.x, y=pose.y, theta=pose.theta)

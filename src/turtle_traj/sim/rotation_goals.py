"""turtlesim's rotate_absolute action for every turtle: goals in, the world's rotation events
out as feedback and results."""

from __future__ import annotations

from rclpy.action import CancelResponse
from rclpy.node import Node
from rclpy.task import Future
from turtlesim.action import RotateAbsolute

from turtle_traj.sim.physics import World
from turtle_traj.sim.state import RotationEnd, RotationEvent, SimulationError


class Rotation:
    """A rotate_absolute goal handle and the future its execute callback awaits (the world's
    token for the goal)."""

    def __init__(self, handle) -> None:
        self.handle = handle
        self.finished = Future()


class RotationGoals:
    """Runs rotate_absolute goals on `world`, as turtlesim does, logging in turtlesim's words."""

    def __init__(self, node: Node, world: World) -> None:
        self._logger = node.get_logger()
        self._world = world

    async def execute(self, name: str, goal_handle) -> RotateAbsolute.Result:
        rotation = Rotation(goal_handle)
        try:
            replaced = self._world.start_rotation(name, rotation, goal_handle.request.theta)
        except SimulationError as error:
            self._logger.error(f'Rotation goal refused: {error}')
            self.finish(rotation, RotationEnd.ABORTED, 0.0)
        else:
            if replaced is not None:
                self._logger.warning(
                    'Rotation goal received before a previous goal finished. '
                    'Aborting previous goal')
                self.finish(replaced.token, RotationEnd.ABORTED, replaced.delta_rad)
        return await rotation.finished

    def accept_cancel(self, name: str, goal_handle) -> CancelResponse:
        turtle = self._world.turtles.get(name)
        if turtle is not None and turtle.rotation is not None \
                and turtle.rotation.token.handle is goal_handle:
            self._world.cancel_rotation(name, turtle.rotation.token)
        return CancelResponse.ACCEPT

    def on_event(self, event: RotationEvent) -> None:
        """Feedback, or the goal's end, from a world step."""
        if event.status is None:
            event.token.handle.publish_feedback(
                RotateAbsolute.Feedback(remaining=event.remaining_rad))
        else:
            if event.status is RotationEnd.CANCELED:
                self._logger.info('Rotation goal canceled')
            elif event.status is RotationEnd.SUCCEEDED:
                self._logger.info('Rotation goal completed successfully')
            self.finish(event.token, event.status, event.delta_rad)

    def finish(self, rotation: Rotation, status: RotationEnd, delta_rad: float) -> None:
        """End the goal (once) and release its awaiting execute callback."""
        handle = rotation.handle
        if rotation.finished.done():
            return
        if not handle.is_active:
            pass  # already ended by rclpy; still release the awaiting execute callback
        elif status is RotationEnd.SUCCEEDED:
            handle.succeed()
        elif status is RotationEnd.CANCELED and handle.is_cancel_requested:
            handle.canceled()
        else:
            handle.abort()
        rotation.finished.set_result(RotateAbsolute.Result(delta=delta_rad))

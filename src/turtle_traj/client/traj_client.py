"""Script-side client of the trajectory node: it owns a private node and spins it itself.

Not for use inside another node's callbacks (it spins); that is what async clients are for.
"""

from __future__ import annotations

import itertools
import os
import time
import uuid
from collections.abc import Callable

import rclpy
from action_msgs.msg import GoalStatus
from rclpy.action import ActionClient
from rclpy.context import Context
from rclpy.node import Node
from rclpy.parameter_client import AsyncParameterClient
from rclpy.task import Future
from rclpy.wait_for_message import wait_for_message
from turtle_traj_interfaces.srv import SaveImage
from turtlesim.msg import Pose
from unique_identifier_msgs.msg import UUID

from turtle_traj.api.ros_interface import (
    COMMAND_SERVICES,
    DRAW_ACTION,
    DRAW_ACTION_TYPE,
    SERVICE_TYPES,
)
from turtle_traj.client.answers import (
    ANSWER_WAIT_S,
    REQUEST_ATTEMPTS,
    TrajClientError,
    first_answer,
)
from turtle_traj.client.goals import DrawOutcome, goal_handle, known_goal
from turtle_traj.client.liveness import Liveness
from turtle_traj.client.remote_parameters import RemoteParameters, UnknownParameter
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.turtlesim_contract import turtle_topic
from turtle_traj.rosutils.interfaces import interface
from turtle_traj.rosutils.runtime import events_executor, process_context, spin_until


class Interrupted(TrajClientError):
    """Ctrl-C came before anything was started."""


class GoalRejected(TrajClientError):
    """The action server rejected the goal (a trajectory node never does: it accepts every goal
    and ends one that cannot run as ABORTED, with the reason in its result)."""


_START_ONE = ('start one with `python -m turtle_traj --with-sim` (or `turtle-traj up`), and '
              'check ROS_DOMAIN_ID')
INTERRUPTED = 'interrupted'  # why a goal was cancelled on Ctrl-C
_CLIENT_NUMBERS = itertools.count()
# The node's services that may be sent twice (`_answer`): its commands, reset and stop (a second
# ends where the first did). A trajectory's request may not: a second one would be refused as
# busy, or draw twice.
_SAFE_TO_REPEAT = frozenset(COMMAND_SERVICES)
_ENDED = (GoalStatus.STATUS_SUCCEEDED, GoalStatus.STATUS_CANCELED, GoalStatus.STATUS_ABORTED)


def seen_in_graph(graph: Node, node_name: str, service: str) -> str:
    """What `graph` (a node) sees of the node `node_name` it waited for: the node and its
    `service` (they then never matched), or the other nodes (a wrong name, namespace or domain
    shows there)."""
    namespace, _, name = node_name.rpartition('/')
    namespace = namespace or '/'
    others = [(other, where) for other, where in graph.get_node_names_and_namespaces()
              if other != graph.get_name()]
    if (name, namespace) in others:
        servers = graph.get_service_names_and_types_by_node(name, namespace)
        if any(server == service for server, _ in servers):
            return f'; {node_name} is seen serving {service}, but never matched this client'
        return f'; {node_name} is seen, without {service}'
    names = sorted(f"{where.rstrip('/')}/{other}" for other, where in others)
    return f'; nodes seen: {", ".join(names)}' if names else '; no other node seen'


class TrajClient:
    """Calls the services and runs the draw action of one trajectory node (default
    `/turtle_traj`)."""

    def __init__(self, *, node: str = '/turtle_traj', connect_timeout_s: float = 3.0,
                 context: Context | None = None, action_type: str = DRAW_ACTION_TYPE) -> None:
        """
        :param action_type: the type of the node's `draw` action (the fleet coordinator's is
            FleetDraw's).
        :param context: the rclpy context to use; by default the process's own
            (`runtime.process_context`), initialised here if no one did and then shut down by
            `close`.
        """
        self.node_name = node if node.startswith('/') else f'/{node}'
        self.connect_timeout_s = connect_timeout_s
        if context is None:
            context, self._owns_context = process_context()
        else:
            self._owns_context = False
        self._context = context
        # A name of its own in the process: several clients may be open at once.
        self._node = rclpy.create_node(f'turtle_traj_cli_{os.getpid()}_{next(_CLIENT_NUMBERS)}',
                                       context=self._context)
        self._executor = events_executor(context=self._context)
        self._executor.add_node(self._node)
        self._action: ActionClient | None = None
        self._action_type = action_type
        self._parameters: RemoteParameters | None = None

    def __enter__(self) -> TrajClient:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def call(self, service: str, request=None, *, timeout_s: float = 30.0):
        """Call `<node>/<service>` and return its response (for trajectories, `draw` does more:
        progress, cancel, a vanished node noticed).

        :raises TrajClientError: when no node answers or the call outlives `timeout_s`.
        """
        try:
            service_type = SERVICE_TYPES[service]
        except KeyError:
            raise TrajClientError(f'unknown service {service!r}; known: '
                                  f'{", ".join(SERVICE_TYPES)}') from None
        return self._call(service_type, f'{self.node_name}/{service}',
                          request if request is not None else service_type.Request(),
                          timeout_s, missing=f'no trajectory node answers on {{name}} (waited '
                                             f'{self.connect_timeout_s:g} s): {_START_ONE}',
                          repeatable=service in _SAFE_TO_REPEAT)

    def save_canvas(self, filename: str):
        """Ask our simulator (beside the node, in its namespace) to save its canvas as PNG."""
        namespace = self.node_name.rsplit('/', 1)[0]
        return self._call(SaveImage, f'{namespace}/turtlesim/save_image',
                          SaveImage.Request(filename=filename), 30.0,
                          missing='no simulator answers on {name}: it is a service of our '
                                  'simulator (the real turtlesim has none); is it running?')

    def _call(self, service_type: type, name: str, request, timeout_s: float, missing: str,
              repeatable: bool = False):
        """Call a service once; a `repeatable` one again while unanswered (see `_answer`)."""
        client = self._node.create_client(service_type, name)
        try:
            if not self._discovered(client.service_is_ready):
                raise TrajClientError(missing.format(name=name)
                                      + seen_in_graph(self._node, self.node_name, name))
            if repeatable:
                return self._answer(lambda: client.call_async(request), name,
                                    timeout_s=timeout_s)
            return self._wait(client.call_async(request), name, timeout_s)
        finally:
            self._node.destroy_client(client)

    def draw(self, goal, *, on_feedback: Callable[[object], None] | None = None,
             timeout_s: float | None = None, what: str | None = None) -> DrawOutcome:
        """Run a goal of the node's draw action to its end and return how it ended.

        Ctrl-C (KeyboardInterrupt) while it runs, or `timeout_s` wall seconds, cancel the goal:
        the turtle stops and the outcome says why it was cancelled.

        :param on_feedback: called with each Draw.Feedback (at least 5 Hz of the node's clock).
        :param what: the goal's name in messages (default: its trajectory).
        :raises TrajClientError: no node, the goal rejected (a trajectory node accepts every goal:
            the node's reason for one that cannot run is in the outcome's result), or the
            node gone mid-run (noticed within about `FEEDBACK_SILENCE_S + PROBE_TIMEOUT_S`).
        """
        action = self._draw_action()
        try:
            found = self._discovered(action.server_is_ready)
        except KeyboardInterrupt:
            raise Interrupted('interrupted before the goal was sent: nothing runs') from None
        if not found:
            goals = f'{self.node_name}/{DRAW_ACTION}/_action/send_goal'
            raise TrajClientError(
                f'no trajectory node answers on {self.node_name}/{DRAW_ACTION} (waited '
                f'{self.connect_timeout_s:g} s): {_START_ONE}'
                f'{seen_in_graph(self._node, self.node_name, goals)}')
        liveness = Liveness(self._node, self.node_name)

        def feedback(message) -> None:
            liveness.heard()
            if on_feedback is not None:
                on_feedback(message.feedback)
        goal_id = UUID(uuid=list(uuid.uuid4().bytes))
        sent: list[Future] = []
        try:
            handle = self._answer(
                lambda: action.send_goal_async(goal, feedback_callback=feedback,
                                               goal_uuid=goal_id), 'the draw action', sent)
            handle = goal_handle(action, goal_id, handle, repeated=len(sent) > 1)
            if not handle.accepted:
                raise GoalRejected(f'{self.node_name} rejected the goal')
            liveness.heard()  # the acceptance: the silence counts from here, not the request
            result = self._follow(what or goal.trajectory, handle, liveness, timeout_s)
        except KeyboardInterrupt:
            return self._cancel(action, goal_id, sent, INTERRUPTED)
        except TimeoutError:
            return self._cancel(action, goal_id, sent, f'not done within {timeout_s:g} s')
        if result.status == GoalStatus.STATUS_UNKNOWN:  # a repeat rejected by a foreign server
            raise GoalRejected(f'{self.node_name} does not know the goal it was sent')
        return DrawOutcome(result.result, result.status)

    def _answer(self, send: Callable[[], Future], what: str, sent: list[Future] | None = None,
                *, timeout_s: float = REQUEST_ATTEMPTS * ANSWER_WAIT_S):
        return first_answer(self._executor, send, what, sent, timeout_s=timeout_s)

    def _follow(self, name: str, handle, liveness: Liveness, timeout_s: float | None):
        """Spin until the goal's result arrives and return it; TimeoutError after `timeout_s`;
        TrajClientError when the node vanished."""
        start = time.monotonic()
        result, asked_at = handle.get_result_async(), start
        while not result.done():
            self._executor.spin_once(timeout_sec=0.1)
            now = time.monotonic()
            if timeout_s is not None and now - start > timeout_s:
                raise TimeoutError
            # A goal followed by its id alone (its answer was lost) never hears its status:
            # its result is asked for again as well, which the server answers once it ends.
            ended = handle.status in _ENDED or handle.status == GoalStatus.STATUS_UNKNOWN
            if ended and now - asked_at > ANSWER_WAIT_S:
                result, asked_at = handle.get_result_async(), now  # that request was lost
            if not self._draw_action().server_is_ready():
                raise TrajClientError(f'{self.node_name} left during the {name}: it was shut '
                                      'down')
            if liveness.gone():
                raise TrajClientError(
                    f'{self.node_name} stopped answering during the {name} (no feedback for '
                    f'{liveness.silence_s():.0f} s, no reply to parameter requests): it was '
                    "probably killed. The turtle stops 1 s after the node's last command "
                    f"(turtlesim's command timeout); {_START_ONE}")
        return result.result()

    def _cancel(self, action: ActionClient, goal_id: UUID, sent: list[Future],
                why: str) -> DrawOutcome:
        """Cancel the goal sent and wait for its end; a goal never answered is cancelled by its
        id all the same, in case the request got through."""
        spin_until(self._executor, lambda: any(future.done() for future in sent),
                   timeout_s=ANSWER_WAIT_S)
        answers = [future.result() for future in sent if future.done()]
        if not answers:
            known_goal(action, goal_id).cancel_goal_async()
            raise Interrupted(f'{why} before the node answered the goal: it was cancelled')
        handle = goal_handle(action, goal_id, answers[0], repeated=len(sent) > 1)
        if not handle.accepted:
            raise Interrupted(f'{why}; the goal had been rejected: nothing runs')
        self._answer(handle.cancel_goal_async, 'the cancel request')
        result = self._answer(handle.get_result_async, 'the cancelled goal')
        return DrawOutcome(result.result, result.status, cancelled=why)

    def _draw_action(self) -> ActionClient:
        if self._action is None:
            self._action = ActionClient(self._node, interface(self._action_type),
                                        f'{self.node_name}/{DRAW_ACTION}')
        return self._action

    def _discovered(self, ready: Callable[[], bool]) -> bool:
        """Wait up to `connect_timeout_s` for `ready()`, looking every 10 ms (rclpy's own
        wait_for_service looks every 250 ms: a quarter second lost on every command)."""
        return spin_until(self._executor, ready, timeout_s=self.connect_timeout_s)

    def _wait(self, future, what: str, timeout_s: float = 5.0):
        if not spin_until(self._executor, future.done, timeout_s=timeout_s):
            raise TrajClientError(f'{what} did not answer within {timeout_s:g} s')
        return future.result()

    def _remote_parameters(self) -> RemoteParameters:
        """The node's parameters, through one parameter client made on first use. Its requests
        go through `_answer`: a new client's first request can lose its answer (see there)."""
        if self._parameters is None:
            client = AsyncParameterClient(self._node, self.node_name)
            if not self._discovered(client.services_are_ready):
                raise TrajClientError(f'no node {self.node_name} answers parameter requests')
            self._parameters = RemoteParameters(client, self.node_name, self._answer)
        return self._parameters

    def parameters(self, names: list[str] | None = None) -> dict[str, object]:
        """Parameters of the node with their current values (all, sorted by name, by default).

        :raises TrajClientError: naming a parameter the node does not have.
        """
        try:
            return self._remote_parameters().get(names)
        except UnknownParameter as error:
            raise TrajClientError(str(error)) from None

    def set_parameter(self, name: str, text: str) -> str | None:
        """Set a parameter from text, converted to the type the node declared it with (`2` to a
        double is 2.0, `1e-9` a number); the refusal, or None when it is set.

        :raises TrajClientError: naming a parameter the node does not have.
        """
        try:
            return self._remote_parameters().set(name, text)
        except UnknownParameter as error:
            raise TrajClientError(str(error)) from None

    def turtle_pose(self, values: dict[str, object] | None = None) -> Pose2D | None:
        """The driven turtle's pose (None if none arrives within a second).

        :param values: the node's parameters, if already fetched (for its turtle_name).
        """
        values = values if values is not None else self.parameters()
        namespace = self.node_name.rsplit('/', 1)[0]
        topic = turtle_topic(values['turtle_name'], 'pose')
        found, pose = wait_for_message(Pose, self._node, f'{namespace}/{topic}',
                                       time_to_wait=1.0)
        return Pose2D(pose.x, pose.y, pose.theta) if found else None

    def close(self) -> None:
        """Destroy what this client made, in order; shut the context down if it started it."""
        self._executor.shutdown()
        if self._action is not None:
            self._action.destroy()
        self._node.destroy_node()
        if self._owns_context:
            rclpy.try_shutdown()


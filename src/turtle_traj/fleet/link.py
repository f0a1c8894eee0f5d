"""The coordinator's line to one turtle: its pose, its pen, and its trajectory node's Draw action.

A move is driven as one Draw goal: a travel as a go-to that ends facing the piece (pen up), a
piece as a follow-path through its points (pen down in the drawing's pen). Each step answers
through a future's callback; nothing here waits.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from action_msgs.msg import GoalStatus
from geometry_msgs.msg import Point, Twist
from rcl_interfaces.srv import GetParameters
from rclpy.action import ActionClient
from rclpy.node import Node
from rclpy.task import Future
from std_msgs.msg import Empty
from turtle_traj_interfaces.action import Draw
from turtlesim.msg import Pose
from turtlesim.srv import SetPen, TeleportAbsolute

from turtle_traj.api.ros_interface import DRAW_ACTION
from turtle_traj.client.liveness import Liveness
from turtle_traj.core.fleet.timing import Move
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.table import PARAMETER
from turtle_traj.core.turtlesim_contract import PenStyle
from turtle_traj.node.lease import LEASE_QOS, LEASE_TOPIC
from turtle_traj.rosutils.clock_read import now_ns
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS

TRAVEL_TOLERANCE_M = 0.001  # a travel's go-to arrives this near its piece (the least it takes)
# a travel turns in place to face its way, however little (as the plan times it): steering onto
# it instead, from up to the node's corner angle off, the turtle arrives beside its end
TRAVEL_CORNER_ANGLE = PARAMETER['corner_angle'].low


@dataclass(frozen=True)
class MoveEnd:
    """How a move ended: whether as planned, its deviation, and if not, why."""

    ok: bool
    deviation: float = 0.0
    why: str = ''


def node_of(turtle: str) -> str:
    """The trajectory node that drives `turtle` in a fleet."""
    return f'/{turtle}/turtle_traj'


class TurtleLink:
    """One turtle, seen and driven from the coordinator `node`."""

    def __init__(self, node: Node, name: str) -> None:
        self.name, self._node = name, node
        self.pose: Pose2D | None = None
        self.moving = False  # its last pose had a velocity
        self.heard_s = -math.inf  # when its last pose came (node clock)
        self.on_pose: Callable[[], None] = lambda: None
        self._poses = node.create_subscription(Pose, f'/{name}/pose', self._pose,
                                               TURTLE_TOPIC_QOS)
        # its node's commands: while it drives a move, they come every control period
        self.commanded_s = -math.inf  # when its node last commanded it (node clock)
        self._commands = node.create_subscription(
            Twist, f'/{name}/cmd_vel', lambda _: self._commanded(), TURTLE_TOPIC_QOS)
        self._stop = node.create_publisher(Twist, f'/{name}/cmd_vel', TURTLE_TOPIC_QOS)
        self._pen = node.create_client(SetPen, f'/{name}/set_pen')
        self._teleport = node.create_client(TeleportAbsolute, f'/{name}/teleport_absolute')
        self._draw = ActionClient(node, Draw, f'{node_of(name)}/{DRAW_ACTION}')
        self._parameters = node.create_client(GetParameters, f'{node_of(name)}/get_parameters')
        self.liveness = Liveness(node, node_of(name), now=self._now_s)
        self._goal = None  # the Draw goal it drives
        self._accepted_s = 0.0  # when that goal was accepted (node clock)
        self._lease = None  # our hold on its node's lease, while we draw with it
        self._pen_down: bool | None = None  # as last set (None: not set yet)
        self._cancelled = False

    def _commanded(self) -> None:
        self.commanded_s = self._now_s()

    def silent_s(self) -> float:
        """How long its node has sent no command while it drives a move: since its last, once
        the move's first has come (0 before: a turtle not yet commanded stands, and a node
        that dies then is found by its liveness)."""
        if self._goal is None or self.commanded_s <= self._accepted_s:
            return 0.0
        return self._now_s() - self.commanded_s

    def halt(self) -> None:
        """Stop it where it is and lift its pen, at once (its node no longer commands it)."""
        self._stop.publish(Twist())
        self._pen_down = False
        self._pen.call_async(SetPen.Request(off=1))

    def _now_s(self) -> float:
        return now_ns(self._node.get_clock()) * 1e-9

    def _pose(self, message: Pose) -> None:
        self.pose = Pose2D(message.x, message.y, message.theta)
        self.heard_s = self._now_s()
        self.moving = message.linear_velocity != 0.0 or message.angular_velocity != 0.0
        self.on_pose()

    def hold(self) -> None:
        """Hold its node's lease: should this program die, its node stops its run."""
        if self._lease is None:
            self._lease = self._node.create_publisher(Empty, f'{node_of(self.name)}/'
                                                      f'{LEASE_TOPIC}', LEASE_QOS)

    @property
    def held(self) -> bool:
        """Its node has matched our hold on its lease."""
        return self._lease is not None and self._lease.get_subscription_count() > 0

    def assert_hold(self) -> None:
        """Show its node that we live: a hold never heard from is never seen to lapse (our
        participant asserts it only every fraction of the lease)."""
        if self._lease is not None:
            self._lease.publish(Empty())

    def release(self) -> None:
        if self._lease is not None:
            self._node.destroy_publisher(self._lease)
            self._lease = None

    def present(self) -> bool:
        """Its turtle stands in the simulator (its pose has come, its pen answers)."""
        return self.pose is not None and self._pen.service_is_ready()

    def serves(self) -> bool:
        """Its node's Draw action and its pen are there, and its pose comes."""
        return (self.pose is not None and self._draw.server_is_ready()
                and self._pen.service_is_ready())

    def parameters(self, names: list[str]) -> Future:
        """Its node's values of the parameters `names` (a GetParameters answer)."""
        return self._parameters.call_async(GetParameters.Request(names=names))

    def forget(self, asked: Future) -> None:
        """Give up a parameters request left unanswered."""
        self._parameters.remove_pending_request(asked)

    def drive(self, move: Move, pen: PenStyle, linear_speed: float,
              done: Callable[[MoveEnd], None]) -> None:
        """Set the pen for `move`, then drive it as a Draw goal; `done` is called once, with
        how it ended."""
        self._cancelled = False
        self.liveness.heard()
        goal = _goal(move, linear_speed)
        if self._pen_down == move.pen:
            self._send(goal, done)
            return
        self._pen_down = move.pen
        request = SetPen.Request(r=pen.r, g=pen.g, b=pen.b, width=pen.width,
                                 off=0 if move.pen else 1)
        self._pen.call_async(request).add_done_callback(lambda _: self._send(goal, done))

    def _send(self, goal: Draw.Goal, done: Callable[[MoveEnd], None]) -> None:
        if self._cancelled:
            done(MoveEnd(False, why='cancelled'))
            return
        future = self._draw.send_goal_async(goal,
                                            feedback_callback=lambda _: self.liveness.heard())
        future.add_done_callback(lambda sent: self._accepted(sent, done))

    def _accepted(self, sent: Future, done: Callable[[MoveEnd], None]) -> None:
        handle = sent.result()
        if handle is None or not handle.accepted:
            done(MoveEnd(False, why='its node refused the move'))
            return
        self._goal, self._accepted_s = handle, self._now_s()
        if self._cancelled:
            handle.cancel_goal_async()
        handle.get_result_async().add_done_callback(lambda answer: self._ended(answer, done))

    def _ended(self, answer: Future, done: Callable[[MoveEnd], None]) -> None:
        self._goal = None
        response = answer.result()
        result = response.result
        if response.status == GoalStatus.STATUS_SUCCEEDED and result.success:
            done(MoveEnd(True, result.max_deviation))
        else:
            done(MoveEnd(False, result.max_deviation,
                         f'{result.ending.label}: {result.message}' if result.message
                         else 'its move did not end'))

    def carry(self, to: Pose2D, done: Callable[[], None]) -> None:
        """Lift its pen and put it at `to` (turtlesim's teleport: it is not driven there); then
        `done`. A simulator without teleport leaves it where it stands."""
        if not self._teleport.service_is_ready():
            done()
            return
        self._pen_down = False
        lifted = self._pen.call_async(SetPen.Request(off=1))
        lifted.add_done_callback(lambda _: self._teleport.call_async(TeleportAbsolute.Request(
            x=to.x, y=to.y, theta=to.theta)).add_done_callback(lambda _: done()))

    def cancel(self) -> None:
        """Stop the move it drives (its goal is cancelled: the turtle stops at once)."""
        self._cancelled = True
        if self._goal is not None:
            self._goal.cancel_goal_async()

    def destroy(self) -> None:
        self.release()
        self._draw.destroy()
        self._node.destroy_subscription(self._poses)
        self._node.destroy_subscription(self._commands)
        self._node.destroy_publisher(self._stop)
        self._node.destroy_client(self._pen)
        self._node.destroy_client(self._teleport)
        self._node.destroy_client(self._parameters)


def _goal(move: Move, linear_speed: float) -> Draw.Goal:
    """The Draw goal that drives `move`: a piece's follow-path, or a travel's go-to."""
    if move.pieces:
        return Draw.Goal(trajectory='follow_path', linear_speed=linear_speed, points=[
            Point(x=float(x), y=float(y)) for x, y in move.points],
            corner_angle=move.corner_angle)
    x, y = move.end
    return Draw.Goal(trajectory='go_to', x=x, y=y, use_theta=True,
                     theta=math.remainder(move.heading, 2 * math.pi),
                     tolerance=TRAVEL_TOLERANCE_M, linear_speed=linear_speed,
                     corner_angle=TRAVEL_CORNER_ANGLE)

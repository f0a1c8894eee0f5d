"""The simulator's part of the live view: a frame per step out to the pages, and the pages'
keys in, sent as turtle_teleop_key sends them (cmd_vel, rotate_absolute). Plain turtlesim
traffic: it knows no trajectories.

Keys arrive on the web thread; they are queued, and a timer of this node takes them every
REQUEST_PERIOD_S on the ROS thread (rclpy's EventsExecutor has no guard conditions to wake it
at once).
"""

from __future__ import annotations

import io
import time
from typing import Any

from geometry_msgs.msg import Twist
from rclpy.action import ActionClient
from rclpy.node import Node
from rclpy.task import Future
from turtlesim.action import RotateAbsolute

from turtle_traj.core.teleop_keys import ARROWS, CANCEL_KEY, ROTATIONS, velocity
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.sim import live_messages
from turtle_traj.sim.canvas import turtle_icon
from turtle_traj.sim.node import SimNode
from turtle_traj.web.frames import Frame
from turtle_traj.web.messages import QueuedPart, error_text, text
from turtle_traj.web.server import WebServer

STATS_PERIOD_S = 1.0
REQUEST_PERIOD_S = 0.02  # a key press waits at most this long
IDLE_FRAME_PERIOD_S = 1.0  # while nothing changes, a frame this often (the page sees it live)
KEY_WAIT_S = 2.0  # for a turtle's cmd_vel or rotate_absolute to connect, at the first press


def turtle_icon_png() -> bytes:
    """The simulator's turtle as PNG, for the page's sprites."""
    encoded = io.BytesIO()
    turtle_icon().save(encoded, format='PNG')
    return encoded.getvalue()


class SimLiveView(QueuedPart, Node):
    """Shows `sim` on `server`'s pages and drives its turtles with the pages' keys (unless
    `watch_only`).

    `sim` is a SimNode, or anything with its `canvas`, `background`, `world` (its turtles and
    time) and `step_listeners` (the physics base's `apps.base_view.BaseScene`)."""

    checkers = live_messages.CHECKERS
    hello_fields = staticmethod(live_messages.hello)

    def __init__(self, sim: SimNode, server: WebServer, *, watch_only: bool = False,
                 **kwargs) -> None:
        super().__init__('turtlesim_web', **kwargs)
        self._sim, self._server = sim, server
        self._watch_only = watch_only  # the pages' keys are refused (a run being graded)
        self.create_timer(REQUEST_PERIOD_S, self._handle_keys)
        self._seq = 0
        self._shown: tuple | None = None  # background and poses of the last frame sent
        self._sent_wall_s = 0.0
        self._cmd_vel: dict[str, Any] = {}  # publishers by turtle
        self._rotations: dict[str, ActionClient] = {}
        self._rotation_goal = None  # the last accepted rotate_absolute goal handle
        self._keys: list[tuple[int, str, str, float]] = []  # pressed, not yet sent
        self.create_timer(STATS_PERIOD_S, self._send_stats)
        sim.step_listeners.append(self._on_step)
        server.add(self)

    def destroy_node(self) -> None:
        self._server.stop()  # the page server lives as long as the view of the simulator
        if self._on_step in self._sim.step_listeners:
            self._sim.step_listeners.remove(self._on_step)
        for action in self._rotations.values():  # destroy_node leaves them
            action.destroy()
        super().destroy_node()

    # -- out: a frame per simulator step ------------------------------------------------------

    def _on_step(self) -> None:
        canvas = self._sim.canvas
        if not self._server.page_count:
            canvas.tracking = False  # nobody watches: nothing kept (a new page gets it all)
            return
        cleared, patches = canvas.take_changes()
        snapshot = None
        if self._server.snapshot_wanted:
            self._server.snapshot_wanted = False
            snapshot = canvas.trails.copy()
        shown = (self._sim.background, [(t.name, t.x, t.y, t.theta) for t in self._sim.world])
        now = time.time()
        if (not cleared and not patches and snapshot is None and shown == self._shown
                and now - self._sent_wall_s < IDLE_FRAME_PERIOD_S):
            return  # nothing changed: a standing world costs a frame a second, not 62
        self._shown, self._sent_wall_s = shown, now
        self._seq += 1
        self._server.broadcast(Frame(self._seq, self._sim.world.time_s, now, *shown,
                                     cleared, patches, snapshot))

    def _send_stats(self) -> None:
        if self._server.page_count:
            self._server.send(None, text('stats', dropped=self._server.frames_dropped))

    # -- in: the pages' keys ------------------------------------------------------------------

    def _handle_keys(self) -> None:
        for page, request in self.inbox.take():
            if self._watch_only:
                self._server.send(page, error_text('this view only watches: the run is being '
                                                   'graded, and only its program drives'))
                continue
            turtle = request['turtle']
            if turtle not in self._sim.world.turtles:
                self._server.send(page, error_text(
                    f'no turtle {turtle!r}; there are: {", ".join(self._sim.world.turtles)}'))
                continue
            self._keys.append((page, turtle, request['key'], time.monotonic()))
        if self._keys:
            self._send_keys()

    def _send_keys(self) -> None:
        """Act on the keys pressed, each once its turtle's topic or action is connected (the
        first press for a turtle creates them)."""
        waiting = []
        for page, turtle, key, pressed in self._keys:
            if not self._key_ready(turtle, key):
                if time.monotonic() - pressed < KEY_WAIT_S:
                    waiting.append((page, turtle, key, pressed))
                else:
                    self._server.send(page, error_text(
                        f'{turtle} did not connect within {KEY_WAIT_S:g} s: is it still there?'))
            elif key in ARROWS:
                twist = Twist()
                twist.linear.x, twist.angular.z = velocity(key)
                self._cmd_vel[turtle].publish(twist)
            elif key == CANCEL_KEY:
                if self._rotation_goal is not None:
                    self._rotation_goal.cancel_goal_async()
            else:
                self._rotations[turtle].send_goal_async(
                    RotateAbsolute.Goal(theta=ROTATIONS[key])).add_done_callback(
                        self._rotation_accepted)
        self._keys = waiting

    def _key_ready(self, turtle: str, key: str) -> bool:
        if key in ARROWS:
            if turtle not in self._cmd_vel:
                self._cmd_vel[turtle] = self.create_publisher(Twist, f'{turtle}/cmd_vel',
                                                              TURTLE_TOPIC_QOS)
            return self._cmd_vel[turtle].get_subscription_count() > 0
        if key == CANCEL_KEY:
            return True
        if turtle not in self._rotations:
            self._rotations[turtle] = ActionClient(self, RotateAbsolute,
                                                   f'{turtle}/rotate_absolute')
        return self._rotations[turtle].server_is_ready()

    def _rotation_accepted(self, future: Future) -> None:
        handle = future.result()
        if handle.accepted:
            self._rotation_goal = handle

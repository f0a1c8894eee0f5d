"""turtlesim's `set_pen` for one turtle, as the trajectory node calls it: one call tracked at a
time, given up when the simulator does not answer."""

from __future__ import annotations

import time
from collections.abc import Callable

from rclpy.callback_groups import CallbackGroup
from rclpy.node import Node
from rclpy.task import Future
from turtlesim.srv import SetPen

from turtle_traj.core.turtlesim_contract import PenStyle, turtle_topic

SET_PEN_TIMEOUT_S = 2.0  # wall clock: a simulator that does not answer set_pen has vanished


class PenClient:
    """Sets the pen of one turtle; `busy` while a call is on its way."""

    def __init__(self, node: Node, turtle: str, *, callback_group: CallbackGroup | None = None,
                 timeout_s: float = SET_PEN_TIMEOUT_S) -> None:
        self._client = node.create_client(SetPen, turtle_topic(turtle, 'set_pen'),
                                          callback_group=callback_group)
        self.timeout_s = timeout_s
        self._call: Future | None = None
        self._sent_wall_s = 0.0

    @property
    def service_name(self) -> str:
        return self._client.srv_name

    @property
    def ready(self) -> bool:
        """The simulator's set_pen is found."""
        return self._client.service_is_ready()

    @property
    def busy(self) -> bool:
        return self._call is not None

    def set(self, pen: PenStyle, *, down: bool, then: Callable[[bool], None]) -> None:
        """Ask for this pen; `then(answered)` runs once the simulator answers (True) or the
        call is given up (False, see `give_up_if_late`). A newer call replaces the tracked one."""
        request = SetPen.Request(r=pen.r, g=pen.g, b=pen.b, width=pen.width, off=not down)
        call = self._client.call_async(request)
        self._call, self._sent_wall_s = call, time.monotonic()

        def finished(future: Future) -> None:
            if future is self._call:
                self._call = None
            then(not future.cancelled())
        call.add_done_callback(finished)

    def give_up_if_late(self) -> bool:
        """Cancel the tracked call once it has waited `timeout_s` (wall clock); True if so."""
        if self._call is None or time.monotonic() - self._sent_wall_s <= self.timeout_s:
            return False
        call, self._call = self._call, None
        call.cancel()
        return True

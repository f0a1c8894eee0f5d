"""One page connected to the live view: its socket, what waits to go to it, and its share of
requests. Lives on the web thread."""

from __future__ import annotations

import asyncio
import math
from dataclasses import dataclass, field

from aiohttp import web

FRAME_QUEUE = 30  # frames a page may be behind (about half a second) before it loses them
REPLY_QUEUE = 256  # replies waiting for a page, at most
REQUESTS_PER_S = 50.0  # a page sending more (a key held down sends about 30) is refused


@dataclass(eq=False)
class Page:
    """One connected page: its socket and what waits to go to it."""

    ident: int
    socket: web.WebSocketResponse
    frames: asyncio.Queue = field(default_factory=lambda: asyncio.Queue(FRAME_QUEUE))
    replies: asyncio.Queue = field(default_factory=lambda: asyncio.Queue(REPLY_QUEUE))
    wake: asyncio.Event = field(default_factory=asyncio.Event)
    allowance: float = 0.0  # requests it may still send now (refilled at REQUESTS_PER_S)
    allowance_at: float = 0.0
    told_too_many_at: float = -math.inf
    in_sync: bool = False  # has had a snapshot, and every frame since
    behind: bool = False  # lost a frame, and waits for the next snapshot
    frames_sent: int = 0

    def take_request(self, now: float) -> tuple[bool, bool]:
        """Whether a request arriving `now` is within the page's rate, and (when not) whether
        to tell the page so (once a second at most)."""
        self.allowance = min(self.allowance + (now - self.allowance_at) * REQUESTS_PER_S,
                             REQUESTS_PER_S)
        self.allowance_at = now
        if self.allowance < 1.0:
            tell = now - self.told_too_many_at > 1.0
            if tell:
                self.told_too_many_at = now
            return False, tell
        self.allowance -= 1.0
        return True, False

    def clear_frames(self) -> None:
        while not self.frames.empty():
            self.frames.get_nowait()

"""The live view's web server: the page, its static files and one WebSocket per page.

It knows no simulator and no trajectory: the parts of the page (`PagePart`: the simulator's
view, the trajectory panel) are added by the program that composes them. aiohttp runs on its
own thread and event loop, so rclpy and the server never wait for each other: the ROS side
hands over frames and replies with `broadcast` and `send` (thread-safe, they never block), and
hears requests through each part's `request`, called on the web thread (it must only queue
them). Each page has a bounded queue: a page that falls behind loses frames (counted) and then
gets the whole canvas again.
"""

from __future__ import annotations

import asyncio
import logging
import threading
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, Protocol

from aiohttp import WSMsgType, web

from turtle_traj.web import messages
from turtle_traj.web.frames import Frame, frame_text, snapshot_text
from turtle_traj.web.messages import Checker, ProtocolError
from turtle_traj.web.pages import REQUESTS_PER_S, Page
from turtle_traj.web.security import LOCAL_HOSTS, host_refusal, origin_refusal

STATIC = Path(__file__).with_name('static')
FAN_OUT_PERIOD_S = 0.016  # the simulator's step: frames leave at its rate
MAX_FRAME_BACKLOG = 120  # frames waiting for the web thread at all, before all pages resync
_log = logging.getLogger(__name__)


class PagePart(Protocol):
    """A part of the page: what it adds to the hello, and the requests it handles."""

    checkers: Mapping[str, Checker]  # request type -> its checker

    def hello(self) -> dict[str, Any]: ...

    def request(self, page: int, request: dict[str, Any]) -> None:
        """A checked request from `page`, on the web thread: queue it, do not act on it."""


class WebServer:
    """Serves the page on http://host:port/ (or on a Unix socket) and streams frames to every
    page."""

    def __init__(self, host: str, port: int, icon_png: Callable[[], bytes], *,
                 unix_socket: str | None = None) -> None:
        self.host, self.port = host, port
        self.unix_socket = unix_socket  # served there instead of host:port (a forwarder's)
        self._icon = icon_png
        self._parts: list[PagePart] = []
        self._handlers: dict[str, PagePart] = {}
        self._checkers: dict[str, Checker] = {}
        self._pages: dict[int, Page] = {}
        self._next_ident = 1
        self._loop: asyncio.AbstractEventLoop | None = None
        self._runner: web.AppRunner | None = None
        self._thread: threading.Thread | None = None
        self._backlog: list[Frame] = []  # handed over by the ROS thread, not yet fanned out
        self._backlog_lock = threading.Lock()
        self._resync_all = False
        self._fanning_out = False  # the periodic fan-out runs (while pages are connected)
        self.snapshot_wanted = False  # a page needs the whole canvas (read by the ROS side)
        self.frames_dropped = 0
        self.requests_refused = 0
        self._icon_png: bytes | None = None

    def add(self, part: PagePart) -> None:
        """A part of the page, added before `start`."""
        self._parts.append(part)
        for kind, checker in part.checkers.items():
            self._handlers[kind], self._checkers[kind] = part, checker

    # -- life --------------------------------------------------------------------------------

    @property
    def url(self) -> str:
        host = f'[{self.host}]' if ':' in self.host else self.host
        return f'http://{host}:{self.port}/'

    def start(self) -> str:
        """Bind and serve on a thread of its own; the URL. OSError when the port is taken."""
        started: dict[str, Any] = {}
        ready = threading.Event()

        def serve() -> None:
            loop = asyncio.new_event_loop()
            asyncio.set_event_loop(loop)
            try:
                loop.run_until_complete(self._bind())
                self._loop = loop
            except Exception as error:  # noqa: BLE001 - reported to the starting thread
                started['error'] = error
                ready.set()
                loop.close()
                return
            ready.set()
            try:
                loop.run_forever()
            finally:
                loop.run_until_complete(self._runner.cleanup())
                loop.close()

        self._thread = threading.Thread(target=serve, name='turtle_traj web', daemon=True)
        self._thread.start()
        ready.wait()
        if 'error' in started:
            raise started['error']
        if self.host not in LOCAL_HOSTS:
            _log.warning('the live view listens on %s: anyone who can reach this address can '
                         'watch and drive the turtles', self.host)
        return self.url

    async def _bind(self) -> None:
        app = web.Application(middlewares=[self._check_host], client_max_size=64 * 1024)
        app.router.add_get('/', self._index)
        app.router.add_get('/ws', self._websocket)
        app.router.add_get('/turtle.png', self._turtle_icon)
        app.router.add_static('/static/', STATIC, follow_symlinks=False, show_index=False)
        self._runner = web.AppRunner(app, access_log=None)
        await self._runner.setup()
        site = (web.UnixSite(self._runner, self.unix_socket) if self.unix_socket
                else web.TCPSite(self._runner, self.host, self.port))
        await site.start()
        if self.unix_socket:
            return
        if self.port == 0:  # the port the system chose
            self.port = self._runner.addresses[0][1]

    def stop(self) -> None:
        if self._loop is not None and self._loop.is_running():
            self._loop.call_soon_threadsafe(self._loop.stop)
        if self._thread is not None:
            self._thread.join(timeout=5.0)

    @property
    def page_count(self) -> int:
        return len(self._pages)

    # -- from the ROS thread ------------------------------------------------------------------

    def broadcast(self, frame: Frame) -> None:
        """Hand a frame to every page (never blocks; drops all when the web thread is stuck).

        The web thread takes the frames every FAN_OUT_PERIOD_S: waking it for each one costs
        both threads more than the frame itself.
        """
        with self._backlog_lock:
            if len(self._backlog) >= MAX_FRAME_BACKLOG:  # every page starts over
                self.frames_dropped += len(self._backlog) * max(self.page_count, 1)
                self._backlog.clear()
                self._resync_all = self.snapshot_wanted = True
            self._backlog.append(frame)

    def send(self, page: int | None, text: str) -> None:
        """A reply to one page (None: to every page)."""
        if self._loop is not None and self._loop.is_running():
            self._loop.call_soon_threadsafe(self._reply, page, text)

    # -- on the web thread --------------------------------------------------------------------

    def _fan_out_every_period(self) -> None:
        """Take the frames handed over, while pages are connected."""
        self._fan_out()
        if self._pages:
            self._loop.call_later(FAN_OUT_PERIOD_S, self._fan_out_every_period)
        else:
            self._fanning_out = False

    def _fan_out(self) -> None:
        with self._backlog_lock:
            frames, self._backlog = self._backlog, []
            resync, self._resync_all = self._resync_all, False
        if resync:
            for page in self._pages.values():
                page.in_sync, page.behind = False, True
        for frame in frames:
            delta = snapshot = None
            for page in list(self._pages.values()):
                if not page.in_sync:
                    if frame.snapshot is None:
                        self.snapshot_wanted = True
                        self.frames_dropped += page.behind
                        continue
                    snapshot = snapshot or snapshot_text(frame)
                    page.clear_frames()
                    page.frames.put_nowait(snapshot)
                    page.in_sync, page.behind = True, False
                elif page.frames.full():
                    self.frames_dropped += 1
                    page.in_sync, page.behind = False, True
                    self.snapshot_wanted = True
                    continue
                else:
                    delta = delta or frame_text(frame)
                    page.frames.put_nowait(delta)
                page.wake.set()

    def _reply(self, ident: int | None, text: str) -> None:
        pages = self._pages.values() if ident is None else [self._pages.get(ident)]
        for page in pages:
            if page is None:
                continue
            if page.replies.full():
                page.replies.get_nowait()  # the oldest reply goes
            page.replies.put_nowait(text)
            page.wake.set()

    @web.middleware
    async def _check_host(self, request: web.Request, handler):
        refusal = host_refusal(request, self.host)
        if refusal is not None:
            return web.Response(status=403, text=refusal)
        return await handler(request)

    async def _index(self, request: web.Request) -> web.FileResponse:
        return web.FileResponse(STATIC / 'index.html')

    async def _turtle_icon(self, request: web.Request) -> web.Response:
        """The simulator's own turtle, facing up (the page turns it to each heading)."""
        if self._icon_png is None:
            self._icon_png = self._icon()
        return web.Response(body=self._icon_png, content_type='image/png')

    async def _websocket(self, request: web.Request) -> web.StreamResponse:
        refusal = origin_refusal(request)
        if refusal is not None:
            _log.warning('live view: %s', refusal)
            return web.Response(status=403, text=refusal)
        # No per-message deflate: frames are small, and compressing 62 a second per page
        # cost more CPU than everything else the view does.
        socket = web.WebSocketResponse(max_msg_size=4 * messages.MAX_MESSAGE_CHARS,
                                       heartbeat=10.0, compress=False)
        await socket.prepare(request)
        page = Page(self._next_ident, socket)
        self._next_ident += 1
        self._pages[page.ident] = page
        self.snapshot_wanted = True
        if not self._fanning_out:
            self._fanning_out = True
            self._loop.call_soon(self._fan_out_every_period)
        page.replies.put_nowait(self._hello_text())
        sender = asyncio.create_task(self._send(page))
        try:
            async for message in socket:
                if message.type == WSMsgType.TEXT:
                    self._receive(page, message.data)
                elif message.type == WSMsgType.BINARY:
                    self._refuse(page, 'binary messages are not understood: send JSON text')
        finally:
            del self._pages[page.ident]
            sender.cancel()
        return socket

    def _receive(self, page: Page, raw: str) -> None:
        allowed, tell = page.take_request(time.monotonic())
        if not allowed:  # said once a second at most: a flood gets no flood back
            self.requests_refused += 1
            if tell:
                self._reply(page.ident, messages.error_text(
                    f'too many requests: at most {REQUESTS_PER_S:g} a second'))
            return
        try:
            request = messages.parse(raw, self._checkers)
        except ProtocolError as error:
            self._refuse(page, str(error))
            return
        try:
            self._handlers[request['type']].request(page.ident, request)
        except Exception as error:  # noqa: BLE001 - a page must never take the server down
            _log.exception('live view request failed')
            self._refuse(page, f'request failed: {error}')

    def _refuse(self, page: Page, reason: str) -> None:
        self.requests_refused += 1
        self._reply(page.ident, messages.error_text(reason))

    def _hello_text(self) -> str:
        hello: dict[str, Any] = {}
        for part in self._parts:
            hello.update(part.hello())
        return messages.text('hello', **hello)

    async def _send(self, page: Page) -> None:
        """Replies first, then frames, as fast as the page takes them."""
        try:
            while not page.socket.closed:
                await page.wake.wait()
                page.wake.clear()
                while not page.replies.empty() or not page.frames.empty():
                    queue = page.replies if not page.replies.empty() else page.frames
                    await page.socket.send_str(queue.get_nowait())
                    page.frames_sent += queue is page.frames
        except (ConnectionError, RuntimeError):
            pass  # the page went away; its handler cleans up

"""The way into a room's live view: a run's network namespace has only its own loopback, so the
room serves its simulator's live view on a Unix socket in the run's folder, and this forwards
connections to it from 127.0.0.1:PORT on the grader's machine (the bytes as they are: the page,
its WebSocket). Only this machine can connect; only the room's view is reached.
"""

from __future__ import annotations

import asyncio
import contextlib
import threading
from pathlib import Path

CONNECT_WAIT_S = 30.0  # a page opened before the room's view is up waits this long for it
_RETRY_S = 0.1
_CHUNK = 65536


class UnixForwarder:
    """Forwards 127.0.0.1:`port` to the Unix socket `path`, on a thread of its own."""

    def __init__(self, path: Path, port: int) -> None:
        self.path, self.port = path, port
        self._loop = asyncio.new_event_loop()
        self._thread: threading.Thread | None = None
        self._server: asyncio.AbstractServer | None = None

    @property
    def url(self) -> str:
        return f'http://127.0.0.1:{self.port}/'

    def start(self) -> str:
        """Listen; the URL. OSError when the port is taken."""
        self._server = self._loop.run_until_complete(asyncio.start_server(
            self._serve, '127.0.0.1', self.port))
        self.port = self._server.sockets[0].getsockname()[1]
        self._thread = threading.Thread(target=self._loop.run_forever, name='live view forward',
                                        daemon=True)
        self._thread.start()
        return self.url

    def stop(self) -> None:
        if self._thread is None:
            return
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join(timeout=5.0)
        self._server.close()
        self._loop.close()
        self._thread = None

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        room = await self._connect()
        if room is None:
            writer.close()
            return
        room_reader, room_writer = room
        await asyncio.gather(_pipe(reader, room_writer), _pipe(room_reader, writer))

    async def _connect(self) -> tuple[asyncio.StreamReader, asyncio.StreamWriter] | None:
        for _attempt in range(round(CONNECT_WAIT_S / _RETRY_S)):
            with contextlib.suppress(OSError):
                return await asyncio.open_unix_connection(str(self.path))
            await asyncio.sleep(_RETRY_S)
        return None


async def _pipe(source: asyncio.StreamReader, sink: asyncio.StreamWriter) -> None:
    """Copy until either side ends, then close the sink."""
    with contextlib.suppress(OSError, ConnectionError):
        while data := await source.read(_CHUNK):
            sink.write(data)
            await sink.drain()
    with contextlib.suppress(OSError, ConnectionError):
        sink.close()

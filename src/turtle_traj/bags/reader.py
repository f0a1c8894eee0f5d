"""Reading rosbag2 bags (any rosbag2 version rosbags reads, MCAP or SQLite3), refusing a folder
that is missing, incomplete or corrupt with what is wrong."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml
from rosbags.rosbag2 import Reader, ReaderError

from turtle_traj.bags.types import UnknownType, typestore_for
from turtle_traj.bags.writer import BagError


@dataclass(frozen=True)
class Message:
    topic: str
    typename: str
    time_ns: int
    raw: bytes
    value: Any = None  # deserialized (rosbags' dataclasses), when asked for


def _check_folder(path: Path) -> None:
    if not path.exists():
        raise BagError(f'no bag at {path}')
    if not path.is_dir():
        raise BagError(f'{path} is not a bag folder (a rosbag2 bag is a folder with '
                       'metadata.yaml)')
    if not (path / 'metadata.yaml').is_file():
        raise BagError(f'{path} has no metadata.yaml: not a rosbag2 bag, or its recording did '
                       'not finish')


def _custom_data(path: Path) -> dict[str, str]:
    """The metadata's custom_data (rosbag2 version 9; what the recorder noted)."""
    try:
        info = yaml.safe_load((path / 'metadata.yaml').read_text())['rosbag2_bagfile_information']
    except (yaml.YAMLError, KeyError, TypeError) as error:
        raise BagError(f'{path}/metadata.yaml is not rosbag2 metadata: {error}') from None
    return {str(k): str(v) for k, v in (info.get('custom_data') or {}).items()}


# What a damaged file makes the reader raise; a record whose length field is garbage asks for
# more memory than there is (MemoryError) or than an index holds (OverflowError).
_UNREADABLE = (ReaderError, OSError, ValueError, KeyError, IndexError, MemoryError, OverflowError)


def _why(error: BaseException) -> str:
    if isinstance(error, (MemoryError, OverflowError)):
        return 'a record claims more bytes than the file could hold'
    return str(error)


class Bag:
    """An open bag: its topics and their messages in time order."""

    def __init__(self, path: Path) -> None:
        """:raises BagError: missing, not a bag, incomplete or corrupt."""
        self.path = Path(path)
        _check_folder(self.path)
        try:
            self._reader = Reader(self.path)
            self._reader.open()
        except _UNREADABLE as error:
            raise BagError(f'{self.path} is not a readable bag: {_why(error)}') from None
        self.topics = {c.topic: c.msgtype for c in self._reader.connections}
        self.custom_data = _custom_data(self.path)
        self.counts = {c.topic: c.msgcount for c in self._reader.connections}

    def offered_qos(self, topic: str) -> list:
        """The QoS profiles the topic's publishers offered when it was recorded."""
        for connection in self._reader.connections:
            if connection.topic == topic:
                return list(getattr(connection.ext, 'offered_qos_profiles', []) or [])
        return []

    @property
    def start_ns(self) -> int:
        return self._reader.start_time

    def messages(self, topics: Sequence[str] | None = None, *,
                 deserialize: bool = False) -> Iterator[Message]:
        """The messages of `topics` (all by default) in time order.

        :raises BagError: a topic the bag does not have, or a corrupt file.
        """
        unknown = sorted(set(topics or ()) - set(self.topics))
        if unknown:
            raise BagError(f'{self.path} has no topic {", ".join(unknown)}; it has: '
                           f'{", ".join(sorted(self.topics))}')
        connections = [c for c in self._reader.connections
                       if topics is None or c.topic in topics]
        store = None
        if deserialize:
            try:
                store = typestore_for(tuple(sorted({c.msgtype for c in connections})))
            except UnknownType as error:
                raise BagError(f'{self.path}: {error}') from None
        try:
            for connection, time_ns, raw in self._reader.messages(connections=connections):
                value = store.deserialize_cdr(raw, connection.msgtype) if store else None
                yield Message(connection.topic, connection.msgtype, time_ns, bytes(raw), value)
        except _UNREADABLE as error:
            raise BagError(f'{self.path} is corrupt: {_why(error)}') from None

    def close(self) -> None:
        self._reader.close()

    def __enter__(self) -> Bag:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

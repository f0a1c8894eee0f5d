"""Writing a rosbag2 bag (version 9, MCAP storage) with rosbags: what Jazzy's `ros2 bag record`
writes, readable by `ros2 bag info` and `ros2 bag play`.

rosbags' writer is the pure-Python one of the well-kept choices, and it writes the rosbag2
layer itself (metadata.yaml with each topic's type, offered QoS profiles and type hash) over
an MCAP file with a `ros2msg` schema and `cdr` encoding per channel, a statistics record and a
summary section, which rosbag2's MCAP reader needs. `mcap` with `mcap-ros2-support` writes only
the MCAP file, so the rosbag2 metadata would be ours to write: tests read our files with those
instead, as an independent reader.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from rosbags.rosbag2 import StoragePlugin, Writer, WriterError
from rosbags.rosbag2.metadata import Qos

from turtle_traj.bags.types import message_definition, typestore_for


class BagError(RuntimeError):
    """A bag that cannot be written or read; the message says what is wrong."""


@dataclass(frozen=True)
class Topic:
    """A topic as recorded: its name, type, the QoS its publishers offered, its type hash."""

    name: str
    typename: str
    offered_qos: tuple[Qos, ...] = ()
    type_hash: str = ''  # RIHS01_..., as the publishers report it


class BagWriter:
    """One bag being written; `close` (always: a `with` block) writes its metadata."""

    def __init__(self, path: Path, topics: list[Topic], *,
                 custom_data: dict[str, str] | None = None) -> None:
        """:raises BagError: the path exists (nothing is overwritten) or cannot be written."""
        self.path = Path(path)
        if self.path.exists():
            raise BagError(f'{self.path} exists: a bag is never written over (choose another '
                           'name, or remove it first)')
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._writer = Writer(self.path, version=9, storage_plugin=StoragePlugin.MCAP)
            self._writer.open()
        except (OSError, WriterError) as error:
            raise BagError(f'cannot write a bag at {self.path}: {error}') from None
        store = typestore_for(tuple(sorted({topic.typename for topic in topics})))
        self._connections = {
            topic.name: self._writer.add_connection(
                topic.name, topic.typename, msgdef=message_definition(store, topic.typename),
                rihs01=topic.type_hash or None, typestore=store,  # (works out a hash not given)
                offered_qos_profiles=list(topic.offered_qos))
            for topic in topics}
        for key, value in (custom_data or {}).items():
            self._writer.set_custom_data(key, value)
        self.counts = dict.fromkeys(self._connections, 0)
        self.error: str | None = None  # why writing stopped early, if it did

    def write(self, topic: str, time_ns: int, serialized: bytes) -> bool:
        """Add one CDR-serialized message; False once writing failed (a full disk): what was
        written before is kept when the bag is closed."""
        if self.error is not None:
            return False
        try:
            self._writer.write(self._connections[topic], time_ns, serialized)
        except (OSError, WriterError) as error:
            self.error = f'writing {self.path} failed: {error}'
            return False
        self.counts[topic] += 1
        return True

    def close(self) -> None:
        """Finish the file and write metadata.yaml (BagError when even that fails)."""
        try:
            self._writer.close()
        except (OSError, WriterError) as error:
            raise BagError(f'{self.path} could not be finished: {error}') from None

    def __enter__(self) -> BagWriter:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

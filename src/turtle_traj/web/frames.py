"""What a page is shown of the world: frames (each step's poses and changed trail pixels) and
snapshots (the whole trail layer), encoded as JSON text. Pure Python."""

from __future__ import annotations

import base64
import json
from dataclasses import dataclass, field

import numpy as np

_COMPACT = (',', ':')


@dataclass
class Frame:
    """What one simulator step changed, taken on the ROS side and encoded on the web side.

    :ivar patches: (row, column, RGBA pixels now) of each rectangle strokes touched.
    :ivar snapshot: the whole RGBA trail layer, when a page asked for it.
    """

    seq: int
    time_s: float  # simulated
    wall_s: float  # time.time() when taken, for the page's latency figure
    background: tuple[int, int, int]
    turtles: list[tuple[str, float, float, float]]
    cleared: bool = False
    patches: list[tuple[int, int, np.ndarray]] = field(default_factory=list)
    snapshot: np.ndarray | None = None


def _pixels(array: np.ndarray) -> str:
    return base64.b64encode(np.ascontiguousarray(array).tobytes()).decode('ascii')


def _turtles(frame: Frame) -> list[list]:
    return [[name, round(x, 5), round(y, 5), round(theta, 5)]
            for name, x, y, theta in frame.turtles]


def frame_text(frame: Frame) -> str:
    return json.dumps({
        'type': 'frame', 'seq': frame.seq, 't': round(frame.time_s, 4), 'wall': frame.wall_s,
        'background': frame.background, 'turtles': _turtles(frame),
        'clear': frame.cleared,
        'patches': [[row, column, int(pixels.shape[0]), int(pixels.shape[1]), _pixels(pixels)]
                    for row, column, pixels in frame.patches]}, separators=_COMPACT)


def snapshot_text(frame: Frame) -> str:
    """The whole trail layer as of `frame` (which must carry one), then its poses."""
    height, width = frame.snapshot.shape[:2]
    return json.dumps({
        'type': 'snapshot', 'seq': frame.seq, 'width': width, 'height': height,
        'background': list(frame.background), 'turtles': _turtles(frame),
        'pixels': _pixels(frame.snapshot)})

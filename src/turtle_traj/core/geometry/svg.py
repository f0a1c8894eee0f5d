"""SVG path data and files as strokes, parsed by svgelements.

Every subpath becomes a stroke; curves (cubic and quadratic Béziers, arcs) are sampled until
the midpoint of every sample interval lies within the requested tolerance of its chord, so
the polyline stays that close to the true curve. The SVG's y axis points down; strokes come
out with y up, in the SVG's own units.
"""

from __future__ import annotations

import io
import math
import re
from pathlib import Path

import numpy as np
import svgelements

from turtle_traj.core.geometry.shapes import ShapeError

_ARITY = {'m': 2, 'l': 2, 't': 2, 'h': 1, 'v': 1, 'c': 6, 's': 4, 'q': 4, 'a': 7, 'z': 0}
_TOKEN = re.compile(r'(?P<command>[MmLlHhVvCcSsQqTtAaZz])|'
                    r'(?P<number>[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)')
_SEPARATORS = re.compile(r'[\s,]*')
MAX_SAMPLES_PER_SEGMENT = 4096
MAX_INPUT_CHARACTERS = 200_000  # path data or file: far more than a turtle can draw
LISTED_FILES = 20  # a refusal for a missing file names at most this many that exist


def check_path_data(data: str) -> None:
    """ShapeError naming the first problem of SVG path data (svgelements' own errors do not):
    an unexpected character, a number that is not finite, a command with the wrong count of
    numbers, no moveto first, too long a text."""
    if not data.strip():
        raise ShapeError('the SVG path data is empty')
    if len(data) > MAX_INPUT_CHARACTERS:
        raise ShapeError(f'the SVG path data has {len(data)} characters; at most '
                         f'{MAX_INPUT_CHARACTERS}')
    command, start, numbers = None, 0, 0

    def close_command() -> None:
        arity = _ARITY[command.lower()]
        if (arity == 0 and numbers) or (arity and (numbers == 0 or numbers % arity)):
            wanted = f'{arity} numbers (or a multiple)' if arity else 'no numbers'
            raise ShapeError(f'SVG path data: the {command} command at character {start + 1} '
                             f'takes {wanted}, got {numbers}')
    position = _SEPARATORS.match(data).end()
    while position < len(data):
        match = _TOKEN.match(data, position)
        if match is None:
            raise ShapeError(f'SVG path data: unexpected {data[position]!r} at character '
                             f'{position + 1}')
        if match.group('command'):
            if command is None and match.group('command') not in 'Mm':
                raise ShapeError('SVG path data must start with a moveto (M or m), not '
                                 f'{match.group("command")!r}')
            if command is not None:
                close_command()
            command, start, numbers = match.group('command'), position, 0
        elif command is None:
            raise ShapeError('SVG path data must start with a moveto (M or m), not a number')
        elif not math.isfinite(float(match.group('number'))):
            raise ShapeError(f'SVG path data: the number {match.group("number")} at character '
                             f'{position + 1} is not finite')
        else:
            numbers += 1
        position = _SEPARATORS.match(data, match.end()).end()
    close_command()


def _segment_points(segment, tolerance: float, spacing: float) -> np.ndarray:
    """Points along one segment, from its start to its end, within `tolerance` of it and at
    most about `spacing` apart (the follower reads curvature from the points)."""
    if isinstance(segment, (svgelements.Line, svgelements.Close)):
        return np.array([[segment.start.x, segment.start.y], [segment.end.x, segment.end.y]])
    rough = np.asarray(segment.npoint(np.linspace(0.0, 1.0, 65)), dtype=float)
    length = float(np.hypot(*np.diff(rough, axis=0).T).sum())
    count = min(max(8, int(math.ceil(length / spacing))), MAX_SAMPLES_PER_SEGMENT)
    while True:
        t = np.linspace(0.0, 1.0, count + 1)
        points = np.asarray(segment.npoint(t), dtype=float)
        middles = np.asarray(segment.npoint(0.5 * (t[:-1] + t[1:])), dtype=float)
        chords = points[1:] - points[:-1]
        offsets = middles - points[:-1]
        cross = np.abs(chords[:, 0] * offsets[:, 1] - chords[:, 1] * offsets[:, 0])
        lengths = np.hypot(*chords.T)
        error = np.where(lengths > 1e-12, cross / np.maximum(lengths, 1e-12),
                         np.hypot(*offsets.T))
        if error.max() <= tolerance or count >= MAX_SAMPLES_PER_SEGMENT:
            return points
        count *= 2


def path_strokes(path: svgelements.Path, tolerance: float, spacing: float) -> list[np.ndarray]:
    """One stroke per subpath of `path` (y up), curves sampled within `tolerance` and about
    `spacing` apart (in the path's units)."""
    strokes = []
    for subpath in path.as_subpaths():
        parts = [_segment_points(segment, tolerance, spacing) for segment in subpath
                 if not isinstance(segment, svgelements.Move) and segment.start is not None]
        if parts:
            points = np.concatenate([parts[0]] + [part[1:] for part in parts[1:]])
            strokes.append(points * (1.0, -1.0))
    return strokes


def parse_path_data(data: str) -> svgelements.Path:
    check_path_data(data)
    try:
        return svgelements.Path(data)
    except (ValueError, AttributeError, IndexError) as error:  # what check_path_data missed
        raise ShapeError(f'SVG path data could not be read: {error or type(error).__name__}') \
            from None


def parse_file(root: Path, name: str) -> svgelements.Path:
    """Every shape of the SVG file `name` under `root` (transforms applied), as one path.

    Refuses names outside `root` (absolute, or escaping with ..), missing files (listing the
    ones there are), files over MAX_INPUT_CHARACTERS bytes and documents with nothing to draw.
    """
    root = root.resolve()
    if not name:
        raise ShapeError('give path_data or a file')
    if Path(name).is_absolute():
        raise ShapeError(f'file {name!r} must be relative to the SVG folder {root}')
    target = (root / name).resolve()
    if not target.is_relative_to(root):
        raise ShapeError(f'file {name!r} is outside the SVG folder {root}')
    if not target.is_file():
        available = sorted(str(p.relative_to(root)) for p in root.rglob('*.svg')) \
            if root.is_dir() else []
        listed = ', '.join(available[:LISTED_FILES]) or 'none'
        more = f' and {len(available) - LISTED_FILES} more' if len(available) > LISTED_FILES \
            else ''
        raise ShapeError(f'no SVG file {name!r} in {root}; there are: {listed}{more}')
    if target.stat().st_size > MAX_INPUT_CHARACTERS:
        raise ShapeError(f'{name} is larger than {MAX_INPUT_CHARACTERS // 1000} kB')
    try:
        document = svgelements.SVG.parse(io.StringIO(target.read_text()))
    except Exception as error:  # noqa: BLE001 - svgelements raises XML and value errors alike
        raise ShapeError(f'{name} is not a readable SVG document: {error}') from None
    path = svgelements.Path()
    for element in document.elements():
        if isinstance(element, svgelements.Shape):  # (text is not a shape)
            shape = svgelements.Path(element)
            if len(shape):
                path += shape
    if not len(path):
        raise ShapeError(f'{name} has no shapes to draw (paths, lines, polygons, rectangles, '
                         'circles, ellipses)')
    return path


def bounding_box(path: svgelements.Path) -> tuple[float, float, float, float]:
    """x_min, y_min, x_max, y_max in the path's units (y down), or ShapeError if empty."""
    box = path.bbox()
    if box is None or not np.isfinite(box).all():
        raise ShapeError('the SVG has nothing to draw, or coordinates that are not finite')
    return box

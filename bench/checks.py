"""The tests' independent geometry, for the benchmarks (one copy: tests/geometry_checks.py)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.geometry_checks import (  # noqa: E402
    distance_to_polyline,
    drawn_strokes,
    ink_at,
    pen_up_moves,
    resampled,
)

__all__ = ['distance_to_polyline', 'drawn_strokes', 'ink_at', 'pen_up_moves', 'resampled']

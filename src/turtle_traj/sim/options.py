"""How to run the simulator, as data: its command-line flags and what they mean."""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path


class SimUnavailable(RuntimeError):
    """The simulator cannot start as asked (its window cannot open); the message says why."""


def add_sim_options(parser: argparse.ArgumentParser, prefix: str = '') -> None:
    """The simulator options people give wherever it runs (here, and beside the node)."""
    parser.add_argument('--time-scale', type=float, default=None, metavar='FACTOR',
                        help=f'{prefix}run FACTOR times faster than real time and publish '
                             '/clock (nodes follow it with use_sim_time:=true)')
    parser.add_argument('--gui', action='store_true',
                        help=f'{prefix}show the canvas in a live window (needs pygame and a '
                             'display)')
    parser.add_argument('--snapshot', type=Path, metavar='PNG',
                        help=f'{prefix}save the canvas to this PNG file on exit')


@dataclass(frozen=True)
class SimOptions:
    """How to run the simulator: what its command-line flags say."""

    time_scale: float | None = None
    holonomic: bool = False
    gui: bool = False
    snapshot: Path | None = None
    output_dir: Path | None = None

    def problem(self) -> str | None:
        """Why these options cannot run, or None."""
        if self.time_scale is not None and not 0.1 <= self.time_scale <= 1000.0:
            return f'--time-scale must be within 0.1 and 1000, got {self.time_scale}'
        if self.snapshot is not None and self.snapshot.suffix.lower() != '.png':
            return f'--snapshot must name a .png file, got {self.snapshot}'
        return None


def options_from(parsed: argparse.Namespace) -> SimOptions:
    """SimOptions from parsed options (those `add_sim_options` added, and any others)."""
    return SimOptions(time_scale=parsed.time_scale, gui=parsed.gui, snapshot=parsed.snapshot,
                      holonomic=getattr(parsed, 'holonomic', False),
                      output_dir=getattr(parsed, 'output_dir', None))

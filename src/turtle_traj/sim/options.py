"""How to run the simulator, as data: its command-line flags and what they mean."""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

WEB_HOST, WEB_PORT = '127.0.0.1', 8080
MAX_TURTLES = 20  # at the start, on rings 3 and 4.5 m round turtle1: 1.5 m apart at least


class SimUnavailable(RuntimeError):
    """The simulator cannot start as asked (its window cannot open); the message says why."""


def add_sim_options(parser: argparse.ArgumentParser, prefix: str = '') -> None:
    """The simulator options people give wherever it runs (here, and beside the node)."""
    parser.add_argument('--time-scale', type=float, default=None, metavar='FACTOR',
                        help=f'{prefix}run FACTOR times faster than real time and publish '
                             '/clock (nodes follow it with use_sim_time:=true)')
    parser.add_argument('--gui', action=argparse.BooleanOptionalAction, default=False,
                        help=f'{prefix}show the canvas in a live window (needs pygame and a '
                             'display)')
    parser.add_argument('--web', action=argparse.BooleanOptionalAction, default=False,
                        help=f'{prefix}serve the live canvas, with keys, trajectories and '
                             'parameters, to a browser')
    parser.add_argument('--web-host', default=WEB_HOST, metavar='HOST',
                        help=f'{prefix}address the live view listens on (default {WEB_HOST}: '
                             'this machine only)')
    parser.add_argument('--web-port', type=int, default=WEB_PORT, metavar='PORT',
                        help=f'{prefix}its port (default {WEB_PORT}; 0: any free one)')
    parser.add_argument('--snapshot', type=Path, metavar='PNG',
                        help=f'{prefix}save the canvas to this PNG file on exit')
    parser.add_argument('--record', type=Path, metavar='JSON',
                        help=f"{prefix}save what the simulator saw (every turtle's poses, the "
                             "pen's segments, the teleports, clears, resets, spawns and kills "
                             'called) to this JSON file on exit, for a grader')
    parser.add_argument('--turtles', type=int, default=1, metavar='N',
                        help=f'{prefix}start with N turtles, turtle1 to turtleN, placed apart '
                             f'(1 to {MAX_TURTLES}); beside the node, a trajectory node drives '
                             'each from its namespace (/turtle2/turtle_traj)')


@dataclass(frozen=True)
class SimOptions:
    """How to run the simulator: what its command-line flags say."""

    time_scale: float | None = None
    holonomic: bool = False
    gui: bool = False
    snapshot: Path | None = None
    record: Path | None = None  # what the simulator saw, saved as JSON on exit
    output_dir: Path | None = None
    web: bool = False
    web_host: str = WEB_HOST
    web_port: int = WEB_PORT
    turtles: int = 1  # turtle1 to turtleN at the start

    def problem(self) -> str | None:
        """Why these options cannot run, or None."""
        if self.time_scale is not None and not 0.1 <= self.time_scale <= 1000.0:
            return f'--time-scale must be within 0.1 and 1000, got {self.time_scale}'
        if self.snapshot is not None and self.snapshot.suffix.lower() != '.png':
            return f'--snapshot must name a .png file, got {self.snapshot}'
        if self.record is not None and self.record.suffix.lower() != '.json':
            return f'--record must name a .json file, got {self.record}'
        if not 0 <= self.web_port <= 65535:
            return f'--web-port must be within 0 and 65535, got {self.web_port}'
        if not self.web and (self.web_host, self.web_port) != (WEB_HOST, WEB_PORT):
            return '--web-host and --web-port need --web'
        if not 1 <= self.turtles <= MAX_TURTLES:
            return f'--turtles must be within 1 and {MAX_TURTLES}, got {self.turtles}'
        return None

    @property
    def turtle_names(self) -> list[str]:
        """The turtles at the start, by name."""
        return [f'turtle{number}' for number in range(1, self.turtles + 1)]


def options_from(parsed: argparse.Namespace) -> SimOptions:
    """SimOptions from parsed options (those `add_sim_options` added, and any others)."""
    return SimOptions(time_scale=parsed.time_scale, gui=parsed.gui, snapshot=parsed.snapshot,
                      record=getattr(parsed, 'record', None),
                      holonomic=getattr(parsed, 'holonomic', False),
                      output_dir=getattr(parsed, 'output_dir', None), web=parsed.web,
                      web_host=parsed.web_host, web_port=parsed.web_port,
                      turtles=getattr(parsed, 'turtles', 1))

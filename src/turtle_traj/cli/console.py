"""What the command line and the menu print about a run: a progress line fed by the draw
action's feedback, and the report of its result."""

from __future__ import annotations

import math
import sys
import time
from typing import TextIO

BAR_WIDTH = 24


def progress_text(name: str, feedback, *, endless: bool) -> str:
    """One line for a Draw.Feedback (bar, percent, distance, elapsed, deviation), or a
    FleetDraw.Feedback (bar, percent, elapsed, turtles driving, closest two)."""
    filled = round(feedback.progress * BAR_WIDTH)
    bar = '#' * filled + '-' * (BAR_WIDTH - filled)
    lap = ' lap' if endless else ''
    text = f'{name}{lap} [{bar}] {feedback.progress * 100:3.0f}%  '
    if hasattr(feedback, 'turtles'):
        driving = sum(state == 'driving' for state in feedback.state)
        closest = (f'closest {feedback.min_distance:.2f} m' if math.isfinite(feedback.min_distance)
                   else '')
        return (text + f'{feedback.elapsed:6.1f} s  {driving} of {len(feedback.turtles)} '
                       f'turtles driving  {closest}')
    text += (f'{feedback.distance:6.2f} m  {feedback.elapsed:6.1f} s  deviation '
             f'{feedback.deviation * 1000:5.1f} mm')
    return text + ('  (Ctrl-C stops it)' if endless else '')


class ProgressLine:
    """A line rewritten in place on a terminal, at most ten times a second; silent when the
    stream is not a terminal (a pipe or a log file gets only the report)."""

    def __init__(self, name: str, *, endless: bool = False, stream: TextIO | None = None) -> None:
        self.name, self.endless = name, endless
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = self.stream.isatty()
        self._shown_at = -math.inf

    def show(self, feedback) -> None:
        now = time.monotonic()
        if self.enabled and now - self._shown_at >= 0.1:
            self._shown_at = now
            self.stream.write('\r\x1b[K' + progress_text(self.name, feedback,
                                                         endless=self.endless))
            self.stream.flush()

    def clear(self) -> None:
        if self.enabled and self._shown_at > -math.inf:
            self.stream.write('\r\x1b[K')
            self.stream.flush()
            self._shown_at = -math.inf


def report(result, cancelled: str = '') -> str:
    """Human-readable result of a trajectory (a service response or a Draw.Result)."""
    verdict = (f'cancelled ({cancelled}): ' if cancelled
               else 'done: ' if result.success else 'failed: ')
    lines = [verdict + result.message]
    if hasattr(result, 'final_x'):
        lines.append(f'  final pose  x={result.final_x:.3f} m  y={result.final_y:.3f} m  '
                     f'theta={math.degrees(result.final_theta):.1f} deg')
        lines.append(f'  elapsed {result.elapsed:.2f} s, path {result.path_length:.2f} m '
                     f'({result.driven_length:.2f} m driven), '
                     f'max deviation {result.max_deviation:.4f} m, final error '
                     f'{result.final_error:.4f} m, heading error '
                     f'{math.degrees(result.final_heading_error):.2f} deg')
    if hasattr(result, 'makespan') and result.turtles:  # a fleet's
        lines.append(f'  makespan {result.makespan:.2f} s (planned {result.planned_makespan:.2f} '
                     f's, lower bound {result.lower_bound:.2f} s), closest two turtles '
                     f'{result.min_distance:.3f} m')
        lines += [f'  {name}: {pieces} pieces, max deviation {deviation:.4f} m'
                  + (f', lost: {lost}' if lost else '')
                  for name, pieces, deviation, lost in zip(
                      result.turtles, result.pieces, result.max_deviation, result.lost,
                      strict=True)]
    if getattr(result, 'pen_up_length', 0.0) > 0.0:
        lines.append(f'  pen up {result.pen_up_length:.2f} m between strokes (in the order '
                     f'given: {result.pen_up_unordered:.2f} m)')
    return '\n'.join(lines)

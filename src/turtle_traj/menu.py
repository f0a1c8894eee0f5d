"""`turtle-traj menu`: an interactive menu over the trajectory registry.

Every field is asked with its default and the range valid from where the turtle stands (a size
up to the largest that fits); a bad answer is asked again, and Ctrl-D or Ctrl-C at a prompt
leaves the menu cleanly. Enter on a field backed by a node parameter sends 0, "use your
parameter", and the prompt shows that parameter's live value. A trajectory runs as a goal of
the node's draw action with a progress line; Ctrl-C while it runs cancels it (the turtle
stops) and comes back to the menu.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any

from turtle_traj.client import GoalRejected, TrajClient, TrajClientError
from turtle_traj.console import ProgressLine, report
from turtle_traj.geometry.path import Pose2D
from turtle_traj.planning import largest_size
from turtle_traj.services import make_goal
from turtle_traj.settings import Settings, settings_from_values
from turtle_traj.trajectories import BOOL, INT, POINTS, STRING, TRAJECTORIES, Field, TrajectoryKind

RESET_KEY, EXIT_KEY = 'r', '0'
CHOICES: dict[str, TrajectoryKind] = {str(index): trajectory
                                  for index, trajectory in enumerate(TRAJECTORIES, start=1)}


class _Leave(Exception):
    """The user closed the input (Ctrl-D) or interrupted it (Ctrl-C)."""


@dataclass(frozen=True)
class Live:
    """What the node says now: its parameters, the settings they make, the turtle's pose."""

    parameters: dict[str, object]
    settings: Settings
    pose: Pose2D | None


def _read(ask: Callable[[str], str], text: str) -> str:
    try:
        return ask(text).strip()
    except (EOFError, KeyboardInterrupt):
        raise _Leave from None


def field_range(trajectory: TrajectoryKind, item: Field, answers: dict[str, Any],
                live: Live) -> tuple[float, float]:
    """The values a person may enter now; a size only up to what fits from the turtle's pose."""
    low, high = item.bounds(live.settings)
    if item.fits and live.pose is not None:
        request = SimpleNamespace(**trajectory.request_values({**answers, item.name: None}))
        largest = largest_size(trajectory.name, request, live.pose, live.settings)
        if largest is not None:
            high = min(high, math.floor(largest * 100) / 100)  # shown rounded: stay inside
    return low, high


def _enter_keeps(item: Field, live: Live) -> str:
    if item.parameter:
        value = live.parameters.get(item.parameter)
        return f"the node's {item.parameter}" + (f' = {value:g}' if value is not None else '')
    return 'none' if item.default is None else f'{item.default:g}'


def _parse_points(answer: str) -> list[tuple[float, float]]:
    points = []
    for pair in answer.replace(';', ' ').split():
        x, y = (float(part) for part in pair.split(','))
        points.append((x, y))
    return points


def ask_field(trajectory: TrajectoryKind, item: Field, answers: dict[str, Any], live: Live,
              ask: Callable[[str], str], say: Callable[[str], None]) -> Any:
    """Ask until the answer is valid; Enter returns None (the field's default)."""
    if item.type == BOOL:
        shown = 'y/N' if not item.default else 'Y/n'
        while True:
            answer = _read(ask, f'  {item.help}? [{shown}]: ').lower()
            if answer in ('', 'n', 'no', 'y', 'yes'):
                return None if not answer else answer in ('y', 'yes')
            say('  please answer y or n')
    if item.type == STRING:
        return _read(ask, f'  {item.help} (Enter = none): ') or None
    if item.type == POINTS:
        while True:
            answer = _read(ask, f'  {item.help}, e.g. 2,2 8,2 8,8: ')
            try:
                points = _parse_points(answer)
            except ValueError:
                points = []
            if points:
                return points
            say(f'  {answer!r} is not a list of points x,y')
    low, high = field_range(trajectory, item, answers, live)
    unit = f' in {item.unit}' if item.unit else ''
    while True:
        answer = _read(ask, f'  {item.help}{unit} ({low:g} to {high:g}, Enter = '
                            f'{_enter_keeps(item, live)}): ')
        if not answer:
            return None
        try:
            value = int(answer) if item.type == INT else float(answer)
        except ValueError:
            say(f'  {answer!r} is not a{" whole" if item.type == INT else ""} number')
            continue
        if not (math.isfinite(value) and low <= value <= high):
            say(f'  {answer} is outside {low:g} to {high:g}')
            continue
        return value


def _live(client: TrajClient) -> Live:
    parameters = client.parameters()
    return Live(parameters, settings_from_values(parameters), client.turtle_pose(parameters))


def _say_call(client: TrajClient, service: str, say: Callable[[str], None]) -> None:
    try:
        say(report(client.call(service)))
    except TrajClientError as error:
        say(f'  error: {error}')


def _run(client: TrajClient, trajectory: TrajectoryKind, ask: Callable[[str], str],
         say: Callable[[str], None]) -> None:
    """Ask a trajectory's fields and run it as a draw goal; Ctrl-C while it runs cancels it."""
    live, answers = _live(client), {}
    for item in trajectory.fields:
        if item.menu and item.name not in trajectory.excluded(answers):
            answers[item.name] = ask_field(trajectory, item, answers, live, ask, say)
    goal = make_goal(trajectory, answers)
    line = ProgressLine(trajectory.name, endless=goal.forever)
    try:
        outcome = client.draw(goal, on_feedback=line.show)
    except GoalRejected as refusal:
        say(f'  refused: {refusal}')
        return
    except TrajClientError as error:
        say(f'  error: {error}')
        return
    finally:
        line.clear()
    say(report(outcome.result, outcome.cancelled))


def run_menu(client: TrajClient, ask: Callable[[str], str] = input,
             say: Callable[[str], None] = print) -> int:
    """The menu loop; returns the exit code."""
    listing = '  '.join(f'{key} {trajectory.name.replace("_", " ")}'
                        for key, trajectory in CHOICES.items())
    try:
        while True:
            say(f'\n{listing}  {RESET_KEY} reset  {EXIT_KEY} exit')
            key = _read(ask, 'choice: ')
            if key == EXIT_KEY:
                return 0
            if key == RESET_KEY:
                _say_call(client, 'reset', say)
            elif key in CHOICES:
                _run(client, CHOICES[key], ask, say)
            else:
                say(f'  unknown choice {key!r}')
    except (_Leave, KeyboardInterrupt):  # Ctrl-D or Ctrl-C at a prompt, or twice in a run
        say('\nbye')
        return 0

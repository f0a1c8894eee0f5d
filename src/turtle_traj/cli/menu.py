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

from turtle_traj.api.ros_interface import make_goal
from turtle_traj.cli.console import ProgressLine, report
from turtle_traj.client.traj_client import GoalRejected, TrajClient, TrajClientError
from turtle_traj.core.fields import BOOL, FLOAT, INT, POINTS, STRING, Field, FieldError
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import Settings, settings_from_values
from turtle_traj.core.planning.planner import largest_size
from turtle_traj.core.registry import TRAJECTORIES, TrajectoryKind

RESET_KEY, EXIT_KEY = 'r', '0'
CHOICES: dict[str, TrajectoryKind] = {str(index): trajectory
                                  for index, trajectory in enumerate(TRAJECTORIES, start=1)}


class _Leave(Exception):
    """The user closed the input (Ctrl-D) or interrupted it (Ctrl-C)."""


@dataclass(frozen=True)
class NodeSnapshot:
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
                live: NodeSnapshot) -> tuple[float, float]:
    """The values a person may enter now; a size only up to what fits from the turtle's pose."""
    low, high = item.bounds(live.settings)
    if item.fits and live.pose is not None:
        request = SimpleNamespace(**trajectory.request_values({**answers, item.name: None}))
        largest = largest_size(trajectory.name, request, live.pose, live.settings)
        if largest is not None:
            high = min(high, math.floor(largest * 100) / 100)  # shown rounded: stay inside
    return low, high


def _enter_keeps(item: Field, live: NodeSnapshot) -> str:
    if item.parameter:
        value = live.parameters.get(item.parameter)
        return f"the node's {item.parameter}" + (f' = {value:g}' if value is not None else '')
    return 'none' if item.default is None else f'{item.default:g}'


def ask_field(trajectory: TrajectoryKind, item: Field, answers: dict[str, Any], live: NodeSnapshot,
              ask: Callable[[str], str], say: Callable[[str], None]) -> Any:
    """Ask until the answer is valid (parsed by the field's own parser); Enter returns None
    (the field's default)."""
    if item.type == BOOL:
        prompt = f'  {item.help}? [{"Y/n" if item.default else "y/N"}]: '
    elif item.type == STRING:
        prompt = f'  {item.help} (Enter = none): '
    elif item.type == POINTS:
        prompt = f'  {item.help}, e.g. 2,2 8,2 8,8: '
    else:
        low, high = field_range(trajectory, item, answers, live)
        unit = f' in {item.unit}' if item.unit else ''
        prompt = (f'  {item.help}{unit} ({low:g} to {high:g}, Enter = '
                  f'{_enter_keeps(item, live)}): ')
    while True:
        answer = _read(ask, prompt)
        if not answer and item.type != POINTS:
            return None
        try:
            value = item.parse(answer)
        except FieldError as error:
            say(f'  {error}')
            continue
        if item.type == POINTS and not value:
            say(f'  {answer!r} is not a list of points x,y')
        elif item.type in (FLOAT, INT) and not low <= value <= high:
            say(f'  {answer} is outside {low:g} to {high:g}')
        else:
            return value


def _live(client: TrajClient) -> NodeSnapshot:
    parameters = client.parameters()
    return NodeSnapshot(parameters, settings_from_values(parameters),
                        client.turtle_pose(parameters))


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

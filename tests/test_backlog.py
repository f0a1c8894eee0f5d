"""A queue of commands at turtlesim, filled by a burst, is drained (pure: no ROS).

The link below is a reliable topic on a lossy network: a lost command holds back the ones after
it until its repair, then all arrive together. turtlesim's subscription keeps the last 7 and
its step takes the oldest; a step with none keeps the last velocity (sim.physics.World).
"""

from collections import deque

import numpy as np

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.loop import ControlLoop
from turtle_traj.core.control.robot_model import RobotModel
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.turtlesim_contract import STEP_S, TOPIC_QOS_DEPTH
from turtle_traj.sim.physics import World
from turtle_traj.testing.geometry import distance_to_polyline, regular_polygon
from turtle_traj.testing.pure_loop import shape

SETTINGS = DEFAULT_SETTINGS
STALLS_END = 420  # the last stall's end, and a few periods
SETTLE = 20  # the last periods of a run: standing still, nothing queued


def _square(stalls: dict[int, int]) -> tuple[np.ndarray, list[int], list[int]]:
    """Drive a 2 m square; the link stalls for `stalls[step]` periods from `step`. The turtle's
    positions, the queue's length at each step and the commands in flight the node counted."""
    world = World()
    turtle = world.spawn(5.5, 5.5, 0.0, 'turtle1')
    control = ControlLoop(STEP_S)
    control.observe(Pose2D(5.5, 5.5, 0.0), 0.0, 0.0)
    plan = planning.plan('square', shape(size=2.0), Pose2D(5.5, 5.5, 0.0), SETTINGS)
    run = control.start(plan, arena=SETTINGS.arena, now_s=0.0)
    held_back: list[Command] = []
    queue: deque[Command] = deque(maxlen=TOPIC_QOS_DEPTH)
    stalled_until, positions, queued, in_flight = -1, [], [], []
    for step in range(20_000):
        positions.append((turtle.x, turtle.y))
        control.observe(Pose2D(turtle.x, turtle.y, turtle.theta),
                        float(np.float32(turtle.linear_speed)), float(np.float32(turtle.omega)))
        in_flight.append(control.model.in_flight)
        command = control.command(SETTINGS.control, SETTINGS.arena, step * STEP_S)
        if run.ending is not None:
            return np.array(positions), queued, in_flight
        stalled_until = max(stalled_until, step + stalls.get(step, 0))
        if command is not None:
            control.sent(command, step * STEP_S)
            held_back.append(command)
        if step >= stalled_until:  # the repair: everything held back arrives at once
            queue.extend(held_back)
            held_back.clear()
        queued.append(len(queue))
        if queue:
            taken = queue.popleft()
            world.command('turtle1', taken.linear, 0.0, taken.angular)
        world.step()
    raise AssertionError('the run never ended')


CORNERS = regular_polygon(5.5, 5.5, 0.0, 4, 2.0, False)
# periods, amid the first, second and third side: a stall while the turtle brakes for a corner
# leaves it on the last command, and no controller can stop it
STALLS = {60: 10, 220: 10, 400: 10}


def test_without_the_drain_a_burst_fills_the_queue_for_good(monkeypatch):
    # the node as it was: every period a command, whatever is queued; identical commands
    monkeypatch.setattr(RobotModel, 'excess', property(lambda _self: 0))
    monkeypatch.setattr(RobotModel, 'distinct', lambda _self, command: command)
    positions, queued, _ = _square(STALLS)
    assert max(queued) == TOPIC_QOS_DEPTH
    assert min(queued[STALLS_END:-SETTLE]) == TOPIC_QOS_DEPTH  # one sent, one taken: full
    # the straight line's commands are all alike, so the echo could not tell the node how
    # many were queued: it braked 6 periods late, and overshot each corner
    assert distance_to_polyline(positions, CORNERS).max() > 0.05


def test_the_node_sends_nothing_while_commands_wait_and_the_square_stays_exact():
    steady, queued_steady, _ = _square({})
    assert max(queued_steady) == 1  # one command per step: it acts at the next
    stalled, queued, in_flight = _square(STALLS)
    # the echoes show commands not taking effect: the node stops adding to them
    assert max(queued) <= 3
    assert max(queued[STALLS_END:]) <= 2 and max(in_flight[STALLS_END:]) <= 1
    # the last stall's repair leaves one command waiting amid a braking, where holding the
    # last command a step longer would shift it: it stays (the latency's floor takes it in, and
    # the prediction with it), one at most, and the corner is as exact
    assert max(queued[STALLS_END + 40:]) == 2 and max(in_flight[STALLS_END + 40:]) == 1
    assert distance_to_polyline(steady, CORNERS).max() < 1e-4
    assert distance_to_polyline(stalled, CORNERS).max() < 1e-3
    # a stall is not jitter: the square takes no longer for them (the turtle drives on)
    assert len(stalled) <= len(steady) + 2


def test_excess_counts_the_commands_overdue_beyond_the_jitter():
    model = RobotModel(STEP_S)
    commands = [Command(0.01 * k, 0.0) for k in range(1, 30)]  # all distinct
    for step, command in enumerate(commands[:10]):
        model.sent(command, step * STEP_S)
        model.observe(*_echo(command))  # in effect at the next step: a latency of one
    assert model.excess == 0
    for step, command in enumerate(commands[10:15], start=10):  # the link stalls
        model.sent(command, step * STEP_S)
        model.observe(*_echo(commands[9]))
        # each was due at the robot the step after it was sent: all are overdue
        assert model.in_flight == model.excess == step - 9
    for step, command in enumerate(commands[10:15], start=15):  # back: one taken a step
        model.observe(*_echo(command))
        assert model.excess == 19 - step


def _echo(command: Command) -> tuple[float, float]:
    return float(np.float32(abs(command.linear))), float(np.float32(command.angular))

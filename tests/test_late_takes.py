"""Commands that act a step late on a base with inertia (pure: no ROS).

A busy simulator steps before a command that was on its way arrives, and takes it at the next
step: the command before acts a step longer. On a base braking for a corner at its deceleration
limit, that shifts the rest of the braking by a step, and the base stops that step past the
corner; holding back the next command to drain the one left waiting would shift it by another.
The node drains such a command only where holding the last one costs nothing, and its braking
allows for a late step once it has seen one.
"""

from collections import deque

import numpy as np

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.loop import ControlLoop
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import settings_from_values
from turtle_traj.core.parameters.table import DEFAULTS
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.turtlesim_contract import STEP_S, TOPIC_QOS_DEPTH
from turtle_traj.sim.physics import Inertia, World
from turtle_traj.testing.geometry import distance_to_polyline

# The DWPP paper's base and its 90 degree step: three 3 m legs
LIMITS = {'linear_speed': 0.5, 'angular_speed': 1.0, 'max_linear_accel': 0.5,
          'max_angular_accel': 1.0}
SETTINGS = settings_from_values({**DEFAULTS, **LIMITS, 'arena_min_x': -100.0,
                                 'arena_min_y': -100.0, 'arena_max_x': 100.0,
                                 'arena_max_y': 100.0})
STEP_PATH = np.array([(1.0, 1.5), (4.0, 1.5), (4.0, 4.5), (7.0, 4.5)])
# Cruising on the first leg (the model learns that commands can be late), then amid the
# braking for the first corner, at about 0.3 m/s.
CRUISING = (100, 150, 200)
BRAKING = 410


def _follow(late: set[int]) -> tuple[np.ndarray, list[int], list[float], list[int]]:
    """follow_path along STEP_PATH on the base; each command sent at a step of `late` arrives
    after the robot's next step. Per step: the position, the commands waiting at the robot as
    it steps, and its speed; and the steps at which the node sent nothing."""
    start = Pose2D(*STEP_PATH[0], 0.0)
    world = World(inertia=Inertia(LIMITS['max_linear_accel'], LIMITS['max_angular_accel']))
    turtle = world.spawn(start.x, start.y, start.theta, 'turtle1')
    control = ControlLoop(STEP_S)
    control.observe(start, 0.0, 0.0)
    plan = planning.plan('follow_path', _follow_request(STEP_PATH), start, SETTINGS)
    run = control.start(plan, arena=SETTINGS.arena, now_s=0.0)
    queue: deque[Command] = deque(maxlen=TOPIC_QOS_DEPTH)
    positions, queued, speeds, held = [], [], [], []
    for step in range(5_000):
        positions.append((turtle.x, turtle.y))
        speeds.append(turtle.linear_speed)
        control.observe(Pose2D(turtle.x, turtle.y, turtle.theta),
                        float(np.float32(turtle.linear_speed)), float(np.float32(turtle.omega)))
        command = control.command(SETTINGS.control, SETTINGS.arena, step * STEP_S)
        if run.ending is not None:
            assert run.ending[0], run.ending[1]
            return np.array(positions), queued, speeds, held
        if command is None:
            held.append(step)
        else:
            control.sent(command, step * STEP_S)
            if step not in late:
                queue.append(command)
        queued.append(len(queue))
        if queue:
            taken = queue.popleft()
            world.command('turtle1', taken.linear, 0.0, taken.angular)
        if command is not None and step in late:  # on its way as the robot stepped
            queue.append(command)
        world.step()
    raise AssertionError('the run never ended')


def _follow_request(points: np.ndarray):
    from turtle_traj.apps.score.courses import follow_request

    return follow_request(points)


def test_the_late_take_falls_amid_the_braking_for_the_first_corner():
    positions, queued, speeds, held = _follow(set())
    assert 0.2 < speeds[BRAKING] < 0.45 and speeds[BRAKING + 1] < speeds[BRAKING]
    assert set(queued) == {1} and held == []  # each command acts at the step after it
    assert distance_to_polyline(positions, STEP_PATH).max() < 1e-4


def test_a_late_take_while_braking_at_the_limit_still_stops_on_the_corner():
    positions, queued, _, _ = _follow({*CRUISING, BRAKING})
    corner_miss = distance_to_polyline(positions, STEP_PATH).max()
    # one step at the speed of the late take is 0.3 m/s * 16 ms, 5 mm past the corner
    assert corner_miss < 1e-3, f'{corner_miss * 1e3:.2f} mm from the path'
    # the late command waits at the robot while it brakes: one, never more
    assert queued[BRAKING] == 0 and max(queued[BRAKING + 1:]) <= 2


def test_a_command_left_waiting_is_drained_where_holding_costs_nothing():
    """Cruising, the command held in place of the next is alike it: the node sends nothing
    for one period, and the robot, taking the late one then, takes each later command at the
    step after it was sent again, at its top speed throughout."""
    _, queued, speeds, held = _follow(set(CRUISING))
    assert held == [step + 1 for step in CRUISING]
    for step in CRUISING:
        assert queued[step] == 0  # the late command not there yet: the last one acts on
        assert queued[step + 1] == 1  # the late one, and nothing sent after it
        assert set(queued[step + 2:step + 40]) == {1}
        # at top speed throughout, but for the float32 steps that tell the commands apart
        assert np.allclose(speeds[step - 5:step + 5], LIMITS['linear_speed'], rtol=1e-5)

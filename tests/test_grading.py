"""A lab's drawing judged from what the simulator recorded (pure Python): open-loop square
scripts driven on our simulator's physics, right, almost right, never stopping, cheating and
hitting the wall, judged against the task; task files refused by the field that is wrong."""

import math
import re

import numpy as np
import pytest
import yaml

from turtle_traj.core.grading.judge import Record, fit, judge
from turtle_traj.core.grading.task import TaskError, read_task, reference
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M, STEP_S
from turtle_traj.sim.physics import World

SQUARE_TASK = yaml.safe_load('''
name: square
run: {script: square.py, time_limit: 40}
expected: {shape: square, size: 2.0, tolerance: 0.1}
checks: {shape: 4, sides: 3, closure: 1, stops: 1, in_bounds: 1, no_teleport: 1}
''')


def open_loop(moves, start=(SPAWN_XY_M, SPAWN_XY_M, 0.0), settle_s=0.5, stop=True) -> Record:
    """What our simulator records of an open-loop script: each (linear, angular, seconds)
    sent every step for that long (as a script that publishes and sleeps; its turns are a
    little off, as a script's are, since the steps do not divide the seconds), then a stop
    (unless not `stop`) and nothing for `settle_s`."""
    world = World()
    turtle = world.spawn(*start, 'turtle1')
    poses, trace = [], [(turtle.x, turtle.y)]
    ending = [(0.0, 0.0, STEP_S)] if stop else []
    for linear, angular, seconds in [*moves, *ending, (None, None, settle_s)]:
        for _ in range(round(seconds / STEP_S)):
            if linear is not None:
                world.command('turtle1', linear, 0.0, angular)
            world.step()
            trace.append((turtle.x, turtle.y))
            poses.append((world.time_s, turtle.x, turtle.y, turtle.theta,
                          turtle.linear_speed, turtle.omega))
    return Record(np.array(poses), [np.array(trace)])


def square_moves(sides=(2.0, 2.0, 2.0, 2.0), turn=math.pi / 2):
    moves = []
    for side in sides:
        moves += [(1.0, 0.0, side), (0.0, turn, 1.0)]
    return moves


def scores(task, record):
    return {check.name: (check.score, check.message) for check in judge(task, record)}


def test_a_right_square_gets_every_point():
    task = read_task(SQUARE_TASK)
    checks = judge(task, open_loop(square_moves()))
    assert all(check.passed for check in checks), [check.message for check in checks]
    assert sum(check.score for check in checks) == task.max_score == 11


def test_an_almost_right_square_is_told_which_side_is_off():
    judged = scores(read_task(SQUARE_TASK), open_loop(square_moves((2.0, 2.0, 1.62, 2.0))))
    assert judged['sides'] == (0.0, 'side 3 is 1.62 m, expected 2.00 ± 0.10 m')
    assert judged['shape'][0] == 0.0 and 'beyond the tolerance 0.1 m' in judged['shape'][1]
    assert judged['stops'][0] == 1 and judged['no_teleport'][0] == 1


def test_the_drawing_may_lie_anywhere_turned_and_mirrored_as_the_task_allows():
    clockwise = open_loop(square_moves(turn=-math.pi / 2), start=(4.0, 7.0, math.radians(30)))
    allowed = read_task(SQUARE_TASK)
    assert scores(allowed, clockwise)['shape'][0] == 4
    fixed = read_task({**SQUARE_TASK, 'expected': {**SQUARE_TASK['expected'], 'allow': []}})
    assert scores(fixed, clockwise)['shape'][0] == 0  # where it must be, it is not
    # an L (not symmetric as a square is): drawn turning right, it fits only mirrored
    ell = read_task({'run': {'script': 'l.py'}, 'checks': {'shape': 1},
                     'expected': {'shape': 'points', 'points': [[0, 0], [2, 0], [2, 1]],
                                  'tolerance': 0.1}})
    right_turn = open_loop([(1.0, 0.0, 2.0), (0.0, -math.pi / 2, 1.0), (1.0, 0.0, 1.0)])
    placed = fit(ell.expected, np.concatenate(right_turn.strokes))
    assert placed.transform['mirror'] and placed.distance < 0.1
    unmirrored = read_task({'run': {'script': 'l.py'}, 'checks': {'shape': 1},
                            'expected': {'shape': 'points', 'points': [[0, 0], [2, 0], [2, 1]],
                                         'tolerance': 0.1, 'allow': ['position', 'orientation']}})
    assert not judge(unmirrored, right_turn)[0].passed


def test_a_turtle_that_never_stops_is_told_how_it_moves():
    record = open_loop([*square_moves(), (0.0, math.pi / 2, 5.0)], settle_s=0.0, stop=False)
    stops = scores(read_task(SQUARE_TASK), record)['stops']
    assert stops[0] == 0.0
    assert stops[1] == f'the turtle never stopped: still turning at 1.57 rad/s after ' \
                       f'{record.poses[-1, 0]:.1f} s'


def test_a_teleport_or_a_clear_the_run_called_costs_its_points():
    record = open_loop(square_moves())
    cheat = Record(record.poses, record.strokes, [(3.2, 'teleport_absolute')])
    assert scores(read_task(SQUARE_TASK), cheat)['no_teleport'] == (
        0.0, 'the run called teleport_absolute after 3.2 s: the drawing must be driven')


def test_a_square_driven_into_the_wall_is_out_of_bounds():
    into_wall = open_loop(square_moves((2.0, 2.0, 2.0, 2.0)), start=(9.5, 5.0, 0.0))
    judged = scores(read_task(SQUARE_TASK), into_wall)
    assert judged['in_bounds'][0] == 0.0 and 'of the wall at' in judged['in_bounds'][1]


def test_a_circle_is_judged_against_a_circle():
    task = read_task({'run': {'script': 'circle.py'},
                      'expected': {'shape': 'circle', 'size': 1.0, 'tolerance': 0.05},
                      'checks': {'shape': 2, 'closure': 1}})
    circle = open_loop([(1.0, 1.0, 2.0 * math.pi)])
    assert all(check.passed for check in judge(task, circle))
    too_big = open_loop([(1.2, 1.0, 2.0 * math.pi)])
    assert not judge(task, too_big)[0].passed


def test_standing_still_scores_nothing():
    """A program that never moves the turtle (it crashed at its start) earns no point, not
    even for standing still at the end or staying off the walls."""
    task = read_task(SQUARE_TASK)
    still = open_loop([])
    assert set(scores(task, still).values()) == {(0.0, 'the turtle never moved')}


def test_moving_with_the_pen_up_draws_nothing():
    task = read_task(SQUARE_TASK)
    driven = open_loop([(1.0, 0.0, 2.0)])
    judged = scores(task, Record(driven.poses, []))
    assert judged['shape'] == (0.0, 'nothing was drawn: the pen left no line')
    assert judged['stops'][0] == 1 and judged['in_bounds'][0] == 1


@pytest.mark.parametrize(('change', 'said'), [
    ({'run': {}}, 'run: give a script, an entry_point (package/executable), or both'),
    ({'run': {'entry_point': 'lab'}}, "run.entry_point 'lab' must be package/executable"),
    ({'expected': {'shape': 'hexagram', 'size': 1.0}}, "expected.shape 'hexagram' is not one"),
    ({'expected': {'shape': 'square', 'size': math.nan}}, 'expected.size must be a number'),
    ({'checks': {'beauty': 3}}, 'checks: beauty is not a check'),
    ({'expected': {'shape': 'circle', 'size': 1.0}}, 'checks.sides needs a square or a polygon'),
    ({'run': {'script': 'a.py', 'time_limit': 1e6}}, 'run.time_limit must be a number within'),
])
def test_a_task_file_that_cannot_be_used_is_refused_naming_the_field(change, said):
    with pytest.raises(TaskError) as refused:
        read_task({**SQUARE_TASK, **change})
    assert said in str(refused.value)


def test_a_goal_is_judged_from_where_the_turtle_ended():
    task = read_task({'run': {'script': 'go.py'}, 'expected': {'goal': [7.0, 5.0],
                                                               'tolerance': 0.05},
                      'checks': {'goal': 4, 'stops': 1}})
    assert task.expected.shape == 'none'
    there = scores(task, open_loop([(1.0, 0.0, 1.0)], start=(6.0, 5.0, 0.0)))
    assert there['goal'][0] == 4 and there['goal'][1].startswith(
        'the turtle ended 0.0')
    short = scores(task, open_loop([(1.0, 0.0, 0.8)], start=(6.0, 5.0, 0.0)))
    x_end = 6.0 + round(0.8 / STEP_S) * STEP_S  # where 0.8 s at 1 m/s leaves it
    assert short['goal'] == (0.0, f'the turtle ended {7.0 - x_end:.3f} m from the goal '
                             '(7.00, 5.00) after 1.3 s (beyond 0.05 m)')


def test_a_spiral_reference_winds_out_to_its_size():
    task = read_task({'run': {'script': 's.py'},
                      'expected': {'shape': 'spiral', 'size': 2.0, 'turns': 3},
                      'checks': {'shape': 1}})
    points = np.array(reference(task.expected))
    radii = np.hypot(*points.T)
    angles = np.unwrap(np.arctan2(points[1:, 1], points[1:, 0]))
    assert radii[0] == 0.0 and math.isclose(radii[-1], 2.0)
    assert np.all(np.diff(radii) > 0)  # it only winds out
    assert math.isclose(angles[-1], 6 * math.pi, rel_tol=1e-6)  # three turns
    # driven as a script would: 1 rad/s, the speed b sqrt(1 + theta^2) step by step
    pitch, moves = 2.0 / (6 * math.pi), []
    for step in range(round(6 * math.pi / STEP_S)):
        theta = (step + 0.5) * STEP_S
        moves.append((pitch * math.sqrt(1 + theta * theta), 1.0, STEP_S))
    assert judge(task, open_loop(moves))[0].passed


@pytest.mark.parametrize(('expected', 'checks', 'said'), [
    ({'goal': [1, 1]}, {'shape': 1}, 'checks.shape needs an expected.shape'),
    ({'shape': 'circle', 'size': 1}, {'goal': 1}, 'checks.goal needs an expected.goal'),
    ({'goal': [1]}, {'goal': 1}, 'expected.goal must be [x, y], not [1]'),
])
def test_goal_and_shape_checks_need_what_they_judge(expected, checks, said):
    with pytest.raises(TaskError, match=re.escape(said)):
        read_task({'run': {'script': 'a.py'}, 'expected': expected, 'checks': checks})

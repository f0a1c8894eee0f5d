"""The trajectory registry and the planner, without ROS: requests to plans or refusals."""

import math
from types import SimpleNamespace

import pytest

from turtle_traj.core.fields import POINTS
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS, arena_problem
from turtle_traj.core.parameters.table import DEFAULTS, PARAMETERS
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.planning.planner import PlanError
from turtle_traj.core.registry import BY_NAME, TRAJECTORIES
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M, WORLD_SIZE_M

SPAWN = Pose2D(SPAWN_XY_M, SPAWN_XY_M, 0.0)
# Room from the spawn point to the right and top edges, after the default 0.3 m wall margin.
ROOM = WORLD_SIZE_M - 0.3 - SPAWN_XY_M


def request(name: str, **given) -> SimpleNamespace:
    """A request as the command line makes it: the registry's defaults, then `given`."""
    values = BY_NAME[name].request_values(given)
    if 'points' in values:
        values['points'] = [SimpleNamespace(x=x, y=y) for x, y in values['points']]
    return SimpleNamespace(**values)


def plan(name: str, start: Pose2D = SPAWN, **given):
    return planning.plan(name, request(name, **given), start, DEFAULT_SETTINGS)


def test_names_services_and_commands_are_unique():
    for key in ('name', 'service', 'command'):
        values = [getattr(trajectory, key) for trajectory in TRAJECTORIES]
        assert len(values) == len(set(values)), key


@pytest.mark.parametrize('trajectory', TRAJECTORIES, ids=lambda t: t.name)
def test_every_example_plans_inside_the_arena_from_its_start(trajectory):
    example = trajectory.example
    start = Pose2D(*example.start)
    result = plan(trajectory.name, start, **example.given)
    assert result.trajectory == trajectory.name
    assert result.path.legs
    assert result.lower_bound_s(DEFAULT_SETTINGS.control) > 0.0
    points = result.path.points()
    assert DEFAULT_SETTINGS.arena.contains(points[1:]) or len(points) == 1


@pytest.mark.parametrize('trajectory', TRAJECTORIES, ids=lambda t: t.name)
def test_a_sketch_reads_only_the_fields_its_entry_lists(trajectory):
    """The registry's fields are the request: planning from them alone never misses one."""
    given = {item.name: [(8.0, 8.0)] for item in trajectory.fields if item.type == POINTS}
    try:
        plan(trajectory.name, **given)
    except PlanError:
        pass  # a refusal is fine; an AttributeError would not be


def test_defaults_in_degrees_are_sent_in_radians():
    assert BY_NAME['rotate'].request_values({})['angle'] == pytest.approx(math.pi / 2)
    assert BY_NAME['lissajous'].request_values({})['phase'] == pytest.approx(math.pi / 2)


def test_a_circle_is_one_turn_unless_forever_is_asked_for():
    one = planning.plan('circle', SimpleNamespace(**{**vars(request('circle', size=1.0)),
                                                   'turns': 0.0}), SPAWN, DEFAULT_SETTINGS)
    assert not one.path.endless and one.path.length == pytest.approx(2 * math.pi, rel=1e-4)
    assert plan('circle', size=1.0, turns=2.5).path.length == pytest.approx(5 * math.pi, rel=1e-4)
    assert plan('circle', size=1.0, forever=True).path.endless  # --forever sends no turns
    with pytest.raises(PlanError, match='turns 2 and forever contradict'):
        plan('circle', size=1.0, turns=2.0, forever=True)


def test_every_parameter_backed_field_takes_its_unit_and_range_from_the_table():
    specs = {spec.name: spec for spec in PARAMETERS}
    for trajectory in TRAJECTORIES:
        for item in trajectory.fields:
            if item.parameter:
                spec = specs[item.parameter]
                assert (item.unit, item.low, item.high) == (spec.unit, spec.low, spec.high)


@pytest.mark.parametrize(('name', 'given', 'reason'), [
    ('square', dict(size=math.nan), 'size must be a finite number'),
    ('circle', dict(size=-1.0), 'size must be at least 0.001 m'),
    ('circle', dict(size=1e308), f'the largest that fits from here is {ROOM / 2:.2f}'),
    ('square', dict(size=5e-324), 'size must be at least'),
    ('polygon', dict(sides=2), 'needs 3 to'),
    ('polygon', dict(sides=4_000_000_000), 'needs 3 to'),
    ('hexagon', dict(linear_speed=-1.0), 'linear_speed must be 0 (the default) or within'),
    ('sine', dict(angular_speed=math.inf), 'angular_speed must be a finite'),
    ('sine', dict(frequency=25.0), 'frequency 25 cycles/m is too large'),
    ('square', dict(size=6.0), f'the largest that fits from here is {ROOM:.2f}'),
    ('circle', dict(size=3.0), f'the largest that fits from here is {ROOM / 2:.2f}'),
    ('go_to', dict(x=12.0, y=5.0), 'outside the arena'),
    ('go_to', dict(x=math.inf, y=5.0), 'x must be a finite number'),
    ('go_to', dict(x=8.0, y=8.0, theta=math.nan), 'theta must be a finite number'),
    ('move', dict(distance=0.0), 'distance must be at least'),
    ('move', dict(distance=9.0), f'the largest that fits from here is {ROOM:.2f}'),
    ('move', dict(distance=20.0), f'the largest that fits from here is {ROOM:.2f}'),
    ('square', dict(size=20.0), f'the largest that fits from here is {ROOM:.2f}'),
    ('spiral', dict(growth=1.0, turns=20.0), '5.1 turns fit from here'),
    ('rotate', dict(angle=math.nan), 'angle must be a finite number'),
    ('rotate', dict(angle=1e9), 'more than 100 turns'),
    ('follow_path', dict(points=[]), 'points is empty'),
    ('follow_path', dict(points=[(SPAWN_XY_M, SPAWN_XY_M)]), 'already there'),
    ('follow_path', dict(points=[(5.0, 5.0), (11.0, 5.0)]), 'points[1] = (11, 5) is outside'),
])
def test_bad_requests_are_refused_with_the_reason(name, given, reason):
    with pytest.raises(PlanError) as refused:
        plan(name, **given)
    assert reason in str(refused.value)


@pytest.mark.parametrize(('name', 'largest'), [
    ('square', ROOM), ('triangle', ROOM), ('circle', ROOM / 2),
    ('move', ROOM)])
def test_the_largest_size_is_the_one_that_just_fits(name, largest):
    found = planning.largest_size(name, request(name), SPAWN, DEFAULT_SETTINGS)
    assert found == pytest.approx(largest, abs=1e-6)
    plan(name, size=found * 0.999, distance=found * 0.999)  # each reads the field it has
    with pytest.raises(PlanError):
        plan(name, size=found * 1.001, distance=found * 1.001)


def test_nothing_scales_in_a_rotation_or_a_go_to():
    for name in ('rotate', 'go_to'):
        assert planning.largest_size(name, request(name), SPAWN, DEFAULT_SETTINGS) is None


def test_a_zero_field_stands_for_the_parameter():
    square = plan('square', size=0.0)
    assert square.path.length == pytest.approx(4 * DEFAULTS['default_side_length'])
    assert square.linear_speed is None  # the node's live linear_speed
    fast = plan('go_to', x=8.0, y=8.0, linear_speed=2.0)
    assert fast.linear_speed == 2.0 and fast.end_tolerance == DEFAULTS['goal_tolerance']


@pytest.mark.parametrize(('changes', 'problem'), [
    ({}, None),
    ({'wall_margin': 5.5}, 'arena_max_x - arena_min_x must exceed 2 * wall_margin + 0.1 m'),
    ({'arena_max_y': 0.5}, 'arena_max_y - arena_min_y must exceed'),
    ({'arena_min_x': 3.0, 'arena_max_x': 4.0}, None),
])
def test_arena_parameters_must_leave_room(changes, problem):
    found = arena_problem({**DEFAULTS, **changes})
    assert (found is None) if problem is None else (problem in found)


def test_an_arena_must_keep_the_turtle_inside():
    smaller = {**DEFAULTS, 'arena_max_x': 5.0}
    assert arena_problem(smaller) is None
    assert 'the turtle stands at (5.54, 5.54), outside' in arena_problem(smaller, SPAWN)
    assert arena_problem(smaller, Pose2D(4.0, 5.5, 0.0)) is None


def test_every_kind_in_the_registry_has_a_sketch_and_nothing_else_has():
    assert set(planning.SKETCHES) == {trajectory.name for trajectory in TRAJECTORIES}

"""Property-based tests of the pure core: planning, geometry and the follower (hypothesis)."""

import math
from dataclasses import replace
from functools import partial
from types import SimpleNamespace

import numpy as np
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from turtle_traj.core.control.controllers.catalogue import ControllerChoice
from turtle_traj.core.geometry import shapes
from turtle_traj.core.geometry.angles import shortest_angular_distance, wrap_angle
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.shapes import Arena
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.planning.planner import PlanError
from turtle_traj.core.registry import BY_NAME
from turtle_traj.core.turtlesim_contract import WORLD_SIZE_M

ARENA = Arena(0.0, 0.0, WORLD_SIZE_M, WORLD_SIZE_M, 0.3)
SHAPES = [name for name, trajectory in BY_NAME.items() if trajectory.command[0] == 'draw']
SETTINGS = settings(max_examples=60, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])

angles = st.floats(-4 * math.pi, 4 * math.pi)
near_pi = st.sampled_from([math.pi, -math.pi, math.pi - 1e-9, -math.pi + 1e-9, 3 * math.pi])
starts = st.builds(Pose2D, st.floats(0.3, WORLD_SIZE_M - 0.3), st.floats(0.3, WORLD_SIZE_M - 0.3),
                   st.one_of(angles, near_pi))
shape_requests = st.builds(
    SimpleNamespace,
    sides=st.integers(3, 12), size=st.floats(0.0, 8.0), clockwise=st.booleans(),
    turns=st.floats(0.0, 3.0), growth=st.floats(0.0, 1.0), max_radius=st.floats(0.0, 6.0),
    frequency=st.floats(0.0, 3.0), length=st.floats(0.0, 10.0), linear_speed=st.just(0.0),
    angular_speed=st.just(0.0), forever=st.just(False), tips=st.integers(0, 12),
    inner_radius=st.floats(0.0, 3.0), petals=st.integers(0, 13), a=st.integers(0, 6),
    b=st.integers(0, 6), phase=st.floats(-7.0, 7.0), path_data=st.just(''),
    file=st.sampled_from(['', 'turtle.svg', 'wave.svg']), pen_color=st.just(''),
    pen_width=st.just(0))


def shape(**fields) -> SimpleNamespace:
    """A DrawShape, DrawCurve or DrawSvg request: the given fields, every other one 0 (the
    default)."""
    values = dict(sides=0, size=0.0, clockwise=False, turns=0.0, growth=0.0, max_radius=0.0,
                  frequency=0.0, length=0.0, linear_speed=0.0, angular_speed=0.0,
                  forever=False, tips=0, inner_radius=0.0, petals=0, a=0, b=0, phase=0.0,
                  path_data='', file='', pen_color='', pen_width=0)
    return SimpleNamespace(**{**values, **fields})


@given(angles)
def test_wrap_angle_is_half_open_and_equivalent(angle):
    wrapped = wrap_angle(angle)
    assert -math.pi <= wrapped < math.pi
    assert math.isclose(math.cos(wrapped), math.cos(angle), abs_tol=1e-9)
    assert math.isclose(math.sin(wrapped), math.sin(angle), abs_tol=1e-9)


@given(angles, angles)
def test_shortest_distance_turns_one_into_the_other(a, b):
    delta = shortest_angular_distance(a, b)
    assert abs(delta) <= math.pi
    assert math.isclose(math.cos(a + delta), math.cos(b), abs_tol=1e-9)


@SETTINGS
@given(st.sampled_from(SHAPES), shape_requests, starts)
def test_every_planned_shape_stays_in_the_arena_or_is_refused(name, request, start):
    try:
        path = planning.plan(name, request, start, DEFAULT_SETTINGS).path
    except PlanError as error:
        assert str(error)
        return
    points = path.points()
    away = np.hypot(points[:, 0] - start.x, points[:, 1] - start.y) > 1e-9
    assert ARENA.contains(points[away])
    assert np.all(np.isfinite(points))


@SETTINGS
@given(st.integers(3, 60), st.floats(0.05, 2.0), st.booleans(), starts)
def test_polygon_sides_are_equal_and_it_closes(sides, side, clockwise, start):
    path = shapes.polygon(start, sides=sides, side_length=side, clockwise=clockwise)
    lengths = [leg.length for leg in path.legs if hasattr(leg, 'points')]
    assert len(lengths) == sides
    assert np.allclose(lengths, side)
    assert math.dist(path.end, (start.x, start.y)) < 1e-9
    turns = [leg.sweep_rad for leg in path.legs if hasattr(leg, 'sweep_rad')]
    assert np.allclose(np.abs(turns), 2 * math.pi / sides)


@SETTINGS
@given(st.floats(0.05, 2.5), st.booleans(), starts)
def test_circle_points_keep_the_radius(radius, clockwise, start):
    path = shapes.circle(start, radius=radius, clockwise=clockwise, turns=1.0)
    side = -1.0 if clockwise else 1.0
    center = (start.x - side * radius * math.sin(start.theta),
              start.y + side * radius * math.cos(start.theta))
    radii = np.hypot(*(path.points() - center).T)
    assert np.allclose(radii, radius)


poses_anywhere = st.builds(
    Pose2D, st.floats(0.0, WORLD_SIZE_M), st.floats(0.0, WORLD_SIZE_M),
    st.one_of(angles, near_pi))
configs = st.builds(partial(replace, DEFAULT_SETTINGS.control),
                    linear_speed=st.floats(0.01, 10.0), angular_speed=st.floats(0.01, 10.0),
                    max_linear_accel=st.sampled_from([0.0, 0.5, 3.0]),
                    max_angular_accel=st.sampled_from([0.0, 1.0, 6.0]))
gains = st.fixed_dictionaries({'heading_gain': st.floats(0.1, 50.0),
                               'cross_track_gain': st.floats(0.0, 50.0)})


@SETTINGS
@given(st.sampled_from([*SHAPES, 'go_to']), starts,
       st.lists(poses_anywhere, min_size=1, max_size=20), configs, gains)
@example('square', Pose2D(6.876953125, 5.66015625, -4.14453125),
         [Pose2D(5.23046875, 5.203125, 0.0)], replace(DEFAULT_SETTINGS.control, angular_speed=1.0),
         {'heading_gain': 1.0, 'cross_track_gain': 0.0})
def test_the_exact_follower_is_never_clamped(kind, start, poses, config, tuning):
    """It asks only for what the limits allow, from wherever the robot is: the walker, which
    clamps every controller's command to the limits and the reach of the one before, finds
    nothing to change in any of its commands, and it never claims a stroke's end from a pose
    far beside it (the example: 1.6 m beside the first side's end, level with it along the
    side)."""
    request = {'go_to': SimpleNamespace(x=5.0, y=5.0, use_theta=True, theta=1.0, tolerance=0.0,
                                        linear_speed=0.0)}.get(
        kind, shape(sides=5, size=0.5, turns=1.0))
    try:
        plan = planning.plan(kind, request, start, DEFAULT_SETTINGS)
    except PlanError:
        return
    # the exact follower, tuned
    follower = replace(ControllerChoice(), tuning=lambda: tuning).driver(plan, manage_pen=False)
    for pose in poses:
        follower.update(pose, config)
    assert follower.clamped == 0, f'{follower.clamped} of {follower.commands} clamped'


def test_the_exact_follower_drives_whole_courses_unclamped_at_the_papers_limits():
    """The same claim over whole runs on a base with inertia, where clamping would bind."""
    from turtle_traj.apps.score.courses import standard_courses
    from turtle_traj.apps.score.runner import run_course
    for course in standard_courses(('inertia',)):
        result = run_course(course, 'exact')
        assert result.success and result.clamped_pct == 0.0, course.name
        dwpp = run_course(course, 'pure_pursuit')
        assert dwpp.clamped_pct > 0.0  # the check can fail: a rival is clamped there


@SETTINGS
@given(st.floats(0.001, 7.0), st.floats(0.001, 20.0), st.floats(0.0, 100.0),
       st.floats(0.0, 15.0), starts)
def test_any_spiral_request_is_planned_with_bounded_work(size, growth, turns, max_radius, start):
    request = shape(size=size, growth=growth, turns=turns, max_radius=max_radius)
    try:
        path = planning.plan('spiral', request, start, DEFAULT_SETTINGS).path
    except PlanError:
        return
    # 100 turns of the largest radius that fits in the arena, at 2 cm spacing.
    assert len(path.points()) < 100 * 2 * math.pi * WORLD_SIZE_M / 0.02


@SETTINGS
@given(st.floats(0.05, 3.0), st.floats(0.01, 5.0), st.booleans(), starts)
def test_a_spiral_leaves_its_start_along_the_heading(radius, growth, clockwise, start):
    points = shapes.spiral_points(start, start_radius=radius, growth=growth,
                                  clockwise=clockwise, end_radius=radius + growth)
    first = points[1] - points[0]
    # The first chord turns from the tangent by about half the angle it subtends at the start
    # radius (a little more: the spiral curves harder than its start circle).
    chord_angle = math.hypot(*first) / radius
    assert np.allclose(points[0], (start.x, start.y))
    assert abs(shortest_angular_distance(start.theta, math.atan2(first[1], first[0]))) \
        <= chord_angle

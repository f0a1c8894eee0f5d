"""Every trajectory end to end: our simulator, the node, simulated time, geometry checks."""

import math

import numpy as np
import pytest
from geometry_msgs.msg import Point
from turtle_traj_interfaces.srv import DrawShape, FollowPath, GoTo, Move

from turtle_traj.core.turtlesim_contract import SPAWN_XY_M
from turtle_traj.testing.geometry import distance_to_polyline, regular_polygon, xy

START = (SPAWN_XY_M, SPAWN_XY_M, 0.0)


@pytest.mark.parametrize(('service', 'sides', 'side', 'clockwise'), [
    ('draw_square', 4, 2.0, False),
    ('draw_triangle', 3, 2.5, True),
    ('draw_hexagon', 6, 1.2, False),
    ('draw_polygon', 5, 1.5, True),
    ('draw_polygon', 18, 0.5, False),  # exterior angle below corner_angle: still sharp
])
def test_polygon_visits_every_vertex_and_closes(turtle_system, service, sides, side, clockwise):
    response = turtle_system.call(DrawShape, service, DrawShape.Request(
        sides=sides, size=side, clockwise=clockwise))
    assert response.success, response.message
    ideal = regular_polygon(*START, sides, side, clockwise)
    path = xy(turtle_system.poses)
    for vertex in ideal:  # every corner is visited to the millimetre
        assert np.min(np.linalg.norm(path - vertex, axis=1)) < 0.001
    assert distance_to_polyline(path, ideal).max() < 0.001
    assert math.dist((response.final_x, response.final_y), START[:2]) < 0.001
    assert response.final_error < 0.001
    assert response.path_length == pytest.approx(sides * side)
    assert response.max_deviation < 0.001
    # Within 10% of the kinematic bound at the default 1 m/s and 2 rad/s (one turn fewer than
    # sides: the last corner is not turned).
    bound = sides * side / 1.0 + (sides - 1) * (2 * math.pi / sides) / 2.0
    assert bound < response.elapsed <= 1.10 * bound


def test_circle_keeps_its_radius(turtle_system):
    response = turtle_system.call(DrawShape, 'draw_circle', DrawShape.Request(size=1.0, turns=1.0))
    assert response.success, response.message
    center = np.array([START[0], START[1] + 1.0])  # counter-clockwise: centre on the left
    radii = np.linalg.norm(xy(turtle_system.poses) - center, axis=1)
    assert np.all(np.abs(radii - 1.0) < 0.002)  # 0.2% of the radius
    angles = np.unwrap(np.arctan2(*(xy(turtle_system.poses) - center).T[::-1]))
    assert angles[-1] - angles[0] == pytest.approx(2 * math.pi, abs=0.05)
    assert response.final_error < 0.001


def test_clockwise_spiral_grows_by_its_growth_per_turn(turtle_system):
    response = turtle_system.call(DrawShape, 'draw_spiral', DrawShape.Request(
        size=0.5, growth=0.4, turns=2.0, clockwise=True, linear_speed=2.0))
    assert response.success, response.message
    # Clockwise: the centre is on the right, 0.5 m away, turned back by the angle at which an
    # Archimedean spiral leaves its start circle, so that the spiral leaves along the heading.
    outward = math.atan2(0.4 / (2 * math.pi), 0.5)
    center = np.array([START[0] - 0.5 * math.sin(outward), START[1] - 0.5 * math.cos(outward)])
    relative = xy(turtle_system.poses) - center
    radii = np.linalg.norm(relative, axis=1)
    start_angle = math.pi / 2 - outward
    turned = -(np.unwrap(np.arctan2(relative[:, 1], relative[:, 0])) - start_angle)
    assert turned[-1] == pytest.approx(4 * math.pi, abs=0.05)
    expected = 0.5 + 0.4 * turned / (2 * math.pi)
    assert np.abs(radii - expected).max() < 0.01


def test_sine_wave_follows_the_heading(turtle_system):
    response = turtle_system.call(DrawShape, 'draw_sine', DrawShape.Request(
        size=0.6, frequency=0.5, length=4.0))
    assert response.success, response.message
    moved = xy(turtle_system.poses) - START[:2]
    on_wave = moved[moved[:, 0] > 0.01]
    assert np.abs(on_wave[:, 1] - 0.6 * np.sin(math.pi * on_wave[:, 0])).max() < 0.005
    assert (response.final_x, response.final_y) == pytest.approx(
        (START[0] + 4.0, START[1]), abs=0.001)


def test_go_to_reaches_the_goal_and_heading(turtle_system):
    response = turtle_system.call(GoTo, 'go_to', GoTo.Request(
        x=2.0, y=8.0, use_theta=True, theta=-math.pi / 2, tolerance=0.02))
    assert response.success, response.message
    assert math.dist((response.final_x, response.final_y), (2.0, 8.0)) <= 0.02
    assert response.final_theta == pytest.approx(-math.pi / 2, abs=0.001)
    straight = np.array([START[:2], (2.0, 8.0)])
    assert distance_to_polyline(xy(turtle_system.poses), straight).max() < 0.001


def test_move_backwards_and_rotate_clockwise(turtle_system):
    response = turtle_system.call(Move, 'move', Move.Request(distance=-1.5))
    assert response.success, response.message
    assert (response.final_x, response.final_y) == pytest.approx(
        (START[0] - 1.5, START[1]), abs=0.001)
    assert abs(response.final_theta) < 0.001  # it drove backwards, it did not turn round
    response = turtle_system.call(Move, 'rotate', Move.Request(angle=-3 * math.pi / 2, speed=1.0))
    assert response.success, response.message
    assert response.final_theta == pytest.approx(math.pi / 2, abs=0.001)
    thetas = np.unwrap([p.theta for p in turtle_system.poses])
    assert thetas.min() < -math.pi  # it went the long, clockwise, way round as asked


def test_follow_path_through_points(turtle_system):
    points = [(7.0, 5.5), (7.0, 8.0), (4.0, 8.5), (3.0, 6.0)]
    response = turtle_system.call(FollowPath, 'follow_path', FollowPath.Request(
        points=[Point(x=x, y=y) for x, y in points], closed=True))
    assert response.success, response.message
    route = np.array([START[:2], *points, points[0]])
    # The first leg starts 1.8 degrees off the turtle's heading: it steers in while driving.
    assert distance_to_polyline(xy(turtle_system.poses), route).max() < 0.005
    assert math.dist((response.final_x, response.final_y), points[0]) < 0.001

"""Several turtles, a trajectory node each in the turtle's namespace, in one process."""

import itertools
import math

import numpy as np
import pytest
from rclpy.parameter import Parameter
from turtle_traj_interfaces.srv import DrawShape
from turtlesim.msg import Pose

from turtle_traj.apps.in_process import SIM_TIME, LockstepSim
from turtle_traj.apps.sim import starting_places
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M, WORLD_SIZE_M
from turtle_traj.node.trajectory_node import TrajectoryNode
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.sim.options import MAX_TURTLES, SimOptions
from turtle_traj.testing.geometry import distance_to_polyline, regular_polygon

CLEARANCE_M = 0.6  # about a turtle's size


@pytest.mark.parametrize('count', range(1, MAX_TURTLES + 1))
def test_the_turtles_start_apart_inside_the_arena(count):
    places = starting_places(count)
    assert len(places) == count and places[0] == (SPAWN_XY_M, SPAWN_XY_M, 0.0)
    assert all(1.0 < x < WORLD_SIZE_M - 1.0 and 1.0 < y < WORLD_SIZE_M - 1.0
               for x, y, _ in places)
    # up to 8 on one ring, with room to pass between them; beyond, on a second ring round it
    apart = 4.0 * CLEARANCE_M if count <= 8 else 2.0 * CLEARANCE_M
    assert all(math.dist(a[:2], b[:2]) > apart for a, b in itertools.combinations(places, 2))


def test_a_fleet_size_outside_its_range_is_refused():
    refused = f'--turtles must be within 1 and {MAX_TURTLES}, got 0'
    assert SimOptions(turtles=0).problem() == refused
    assert SimOptions(turtles=MAX_TURTLES + 1).problem() is not None
    assert SimOptions(turtles=3).turtle_names == ['turtle1', 'turtle2', 'turtle3']


def test_each_turtles_node_draws_its_own_turtle_at_the_same_time(rclpy_context, tmp_path):
    """Two nodes named alike, each in its turtle's namespace with its turtle left unnamed
    (`turtle_name` ''): each drives the turtle its namespace names, both at once, exactly."""
    system = LockstepSim(context=rclpy_context, output_dir=tmp_path)
    try:
        places = starting_places(2)
        system.sim.spawn_turtle('turtle2', *places[1])
        poses: dict[str, list[Pose]] = {'turtle1': [], 'turtle2': []}
        for name, log in poses.items():
            system.add_node(TrajectoryNode(
                context=rclpy_context, namespace=f'/{name}',
                parameter_overrides=[SIM_TIME, Parameter('turtle_name', value='')]))
            system.client.create_subscription(Pose, f'/{name}/pose', log.append,
                                              TURTLE_TOPIC_QOS)
        assert system.spin_until(lambda: all(poses.values()), timeout_s=60.0)
        for log in poses.values():
            log.clear()
        square = system.start(DrawShape, '/turtle1/turtle_traj/draw_square',
                              DrawShape.Request(size=1.0))
        triangle = system.start(DrawShape, '/turtle2/turtle_traj/draw_triangle',
                                DrawShape.Request(size=1.5))
        assert system.spin_until(lambda: square.done() and triangle.done(), timeout_s=60.0)
        assert square.result().success and triangle.result().success
        for (name, log), sides, size in zip(poses.items(), (4, 3), (1.0, 1.5), strict=True):
            x, y, theta = places[int(name[-1]) - 1]
            drawn = np.array([(pose.x, pose.y) for pose in log])
            assert distance_to_polyline(drawn, regular_polygon(x, y, theta, sides, size,
                                                               False)).max() < 1e-3
            assert math.dist(drawn[-1], (x, y)) < 1e-3  # back where it started
        # both drove in the same seconds: neither waited for the other
        moving = [[pose.linear_velocity != 0.0 for pose in log] for log in poses.values()]
        assert sum(a and b for a, b in zip(*moving, strict=False)) > 0.5 * min(map(sum, moving))
    finally:
        system.close()


def test_the_command_line_names_a_turtles_node_or_a_node_not_both(capsys):
    from turtle_traj.cli.main import build_parser, main

    with pytest.raises(SystemExit):
        main(['--turtle', 'turtle2', '--node', '/sim1/turtle_traj', 'stop'])
    assert 'give --turtle or --node, not both' in capsys.readouterr().err
    options = build_parser().parse_args(['--turtle', 'turtle2', 'stop'])
    assert options.turtle == 'turtle2'


def test_a_fleet_turtles_bag_records_its_namespaces_topics(monkeypatch):
    """`turtle-traj --turtle turtle2 record` records turtle2's topics and its node's."""
    from turtle_traj.apps import bags
    from turtle_traj.bags.recorder import default_topics
    from turtle_traj.cli.main import main

    asked = {}
    monkeypatch.setattr(bags, 'record', lambda output, topics, node, turtle, defaults:
                        asked.update(node=node, topics=defaults or default_topics(turtle, node))
                        or 0)
    assert main(['--turtle', 'turtle2', 'record']) == 0
    assert asked['node'] == '/turtle2/turtle_traj'
    assert asked['topics'][:4] == ['/turtle2/pose', '/turtle2/cmd_vel', '/turtle2/color_sensor',
                                   '/turtle2/turtle_traj/plan']


def test_turtles_on_the_command_line_ask_the_fleet_coordinator_for_the_same_drawing(capsys):
    from turtle_traj.api.ros_interface import make_goal
    from turtle_traj.cli.main import build_parser, main, to_goal
    from turtle_traj.core.registry import BY_NAME

    parser = build_parser()
    goal = to_goal(parser.parse_args(['write', 'ROS 2', '--height', '1', '--turtles', '3']))
    assert list(goal.turtles) == ['turtle1', 'turtle2', 'turtle3']
    alone = make_goal(BY_NAME['text'], {'text': 'ROS 2', 'height': 1.0})
    assert all(getattr(goal.drawing, name) == getattr(alone, name)
               for name in alone.get_fields_and_field_types())
    with pytest.raises(SystemExit):
        main(['write', 'ROS 2', '--turtles', '2', '--turtle', 'turtle2'])
    assert 'not with --turtle' in capsys.readouterr().err
    with pytest.raises(SystemExit):  # a go-to is not shared
        parser.parse_args(['go-to', '2', '2', '--turtles', '2'])
    with pytest.raises(SystemExit):
        parser.parse_args(['draw', 'star', '--turtles', str(MAX_TURTLES + 1)])


def test_a_fleets_bag_records_every_turtles_topics_and_the_coordinators(monkeypatch):
    """`turtle-traj record --turtles 3`: each turtle's topics and its node's, and the fleet's."""
    from turtle_traj.apps import bags
    from turtle_traj.cli.main import main

    asked = {}
    monkeypatch.setattr(bags, 'record', lambda output, topics, node, turtle, defaults:
                        asked.update(topics=topics, defaults=defaults, node=node) or 0)
    assert main(['record', '--turtles', '3']) == 0
    assert asked['topics'] == [] and asked['node'] == '/turtle1/turtle_traj'  # its limits
    for number in (1, 2, 3):
        assert {f'/turtle{number}/pose', f'/turtle{number}/cmd_vel',
                f'/turtle{number}/turtle_traj/plan'} <= set(asked['defaults'])
    assert '/fleet/draw/_action/feedback' in asked['defaults']
    assert len(asked['defaults']) == len(set(asked['defaults']))

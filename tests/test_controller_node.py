"""A controller chosen by the node's `controller` parameter, end to end through ROS (lock-step,
in-process): misbehaving controllers end their run with a message, the turtle stops, and the
node serves the next request; names that are not controllers are refused at start-up."""

import math
import re

import pytest
from geometry_msgs.msg import Twist
from rclpy.exceptions import InvalidParameterValueException
from rclpy.parameter import Parameter
from turtle_traj_interfaces.msg import Ending
from turtle_traj_interfaces.srv import DrawShape, Move

from turtle_traj.apps.in_process import InProcessSystem
from turtle_traj.node.trajectory_node import TrajectoryNode
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.testing.geometry import distance_to_polyline, regular_polygon

MODULE = 'tests.misbehaving_controllers'


@pytest.fixture
def system_with(rclpy_context, tmp_path):
    systems = []

    def make(controller: str) -> InProcessSystem:
        systems.append(InProcessSystem(context=rclpy_context, output_dir=tmp_path,
                                       controller=controller))
        return systems[-1]
    yield make
    for system in systems:
        system.close()


def _commands(system: InProcessSystem) -> list[Twist]:
    heard: list[Twist] = []
    system.client.create_subscription(Twist, '/turtle1/cmd_vel', heard.append, TURTLE_TOPIC_QOS)
    return heard


@pytest.mark.parametrize(('controller', 'said'), [
    ('Raises', "raised KeyError in command(): 'wheel'"),
    ('ReturnsNan', 'returned a non-finite command (nan m/s'),
    ('SleepsOneSecond', 'answered later than the control period (0.016 s) 3 times in a row, '
                        'the last after 1.0'),
])
def test_a_misbehaving_controller_is_stopped_and_the_node_serves_on(system_with, controller,
                                                                    said):
    system = system_with(f'{MODULE}:{controller}')
    commands = _commands(system)
    first = system.call(DrawShape, 'draw_square', DrawShape.Request(size=1.0))
    assert not first.success and first.ending.code == Ending.CONTROLLER_FAULT
    assert first.message.startswith('square aborted: ')
    assert f"controller '{MODULE}:{controller}' {said}" in first.message
    system.spin_sim_seconds(0.2)
    assert commands[-1] == Twist()  # the turtle was sent a stop
    assert system.poses[-1].linear_velocity == 0.0 and system.poses[-1].angular_velocity == 0.0
    start = system.poses[-1]
    second = system.call(DrawShape, 'draw_square', DrawShape.Request(size=1.0))
    assert second.success, second.message
    square = regular_polygon(start.x, start.y, start.theta, 4, 1.0, False)
    poses = [(p.x, p.y) for p in system.poses]
    # DWPP rounds the corners: near the square everywhere, by less than its look-ahead
    assert distance_to_polyline(poses, square).max() < 0.3


def test_commands_beyond_the_limits_are_clamped_counted_and_never_sent(system_with):
    system = system_with(f'{MODULE}:ExceedsTheLimits')
    system.node.set_parameters([Parameter('linear_speed', value=0.8),
                                Parameter('angular_speed', value=1.5)])
    commands = _commands(system)
    response = system.call(DrawShape, 'draw_square', DrawShape.Request(size=1.0))
    assert response.success, response.message
    found = re.search(r'\((\S+): (\d+) of (\d+) commands clamped to the limits\)',
                      response.message)
    assert found and found[1] == f'{MODULE}:ExceedsTheLimits' and int(found[2]) > 10
    assert system.node.last_outcome.clamped_percent == pytest.approx(
        100.0 * int(found[2]) / int(found[3]))  # the figure a client reads, not the text
    assert len(commands) >= int(found[3])  # every one was sent, clamped
    assert all(abs(c.linear.x) <= 0.8 + 1e-9 and abs(c.angular.z) <= 1.5 + 1e-9
               for c in commands)
    assert max(abs(c.linear.x) for c in commands) == pytest.approx(0.8)


def test_a_name_that_is_no_controller_is_refused_at_start(rclpy_context):
    with pytest.raises(InvalidParameterValueException, match="controller 'nope' is unknown: "
                       'choose one of exact, dwpp, pure_pursuit'):
        TrajectoryNode(context=rclpy_context,
                       parameter_overrides=[Parameter('controller', value='nope')])
    with pytest.raises(InvalidParameterValueException, match='has no start and no command method'):
        TrajectoryNode(context=rclpy_context, parameter_overrides=[
            Parameter('controller', value='turtle_traj.core.control.controller:Limits')])


def test_the_controller_is_read_only_while_the_node_runs(system_with):
    system = system_with('dwpp')
    result = system.node.set_parameters([Parameter('controller', value='exact')])[0]
    assert not result.successful and 'read-only' in result.reason
    assert system.node.get_parameter('controller').value == 'dwpp'


def test_an_end_claimed_before_the_path_is_driven_fails_the_request_with_the_figures(system_with):
    """The tutorial's slip (done within 1 cm of the stroke's last point): on a closed square
    that is true at the start. The node judges the end, so the square fails, the response says
    how much of the path was driven, and the node serves the next request."""
    system = system_with(f'{MODULE}:StopsNearTheLastPoint')
    start = system.poses[-1]
    square = system.call(DrawShape, 'draw_square', DrawShape.Request(size=2.0))
    assert not square.success and square.ending.code == Ending.CONTROLLER_FAULT
    assert (f"square aborted: controller '{MODULE}:StopsNearTheLastPoint' claimed the end "
            'after 0.00 m of 8.00 m') in square.message
    assert square.path_length == pytest.approx(8.0) and square.driven_length == 0.0
    moved = max(math.dist((p.x, p.y), (start.x, start.y)) for p in system.poses)
    assert moved < 1e-6  # the turtle never left its place
    move = system.call(Move, 'move', Move.Request(distance=1.0))
    assert move.success, move.message  # an open path ends away from its start
    assert move.driven_length == pytest.approx(move.path_length) == pytest.approx(1.0)
    end = system.poses[-1]
    assert math.dist((end.x, end.y), (start.x, start.y)) == pytest.approx(1.0, abs=0.02)

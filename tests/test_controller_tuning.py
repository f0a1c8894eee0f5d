"""A controller's tuning: declared on its class (`Tunable`), served by the node as the ROS
parameters `<controller>.<name>`, checked against their ranges and set live, taking effect from
the next stroke. The controller of the tutorial "Write your own controller", as written there."""

import math

import pytest
from rcl_interfaces.msg import Parameter as ParameterMsg
from rcl_interfaces.msg import ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from turtle_traj_interfaces.srv import Move

from tests.test_tutorials import TUTORIALS, tutorial_steps
from turtle_traj.apps.in_process import InProcessSystem
from turtle_traj.core.control.controllers.dwpp import Dwpp
from turtle_traj.core.control.controllers.pure_pursuit import PurePursuit
from turtle_traj.core.control.tuning import Tunable, tunables, tune

RPP_NAMES = {'lookahead_time', 'min_lookahead_dist', 'max_lookahead_dist',
             'regulated_linear_scaling_min_radius', 'regulated_linear_scaling_min_speed',
             'approach_velocity_scaling_dist', 'min_approach_linear_velocity',
             'rotate_to_heading_min_angle', 'goal_tolerance'}


def test_a_class_declares_its_tuning_and_a_subclass_hides_what_it_does_not_use():
    assert {spec.name for spec in tunables(PurePursuit)} == RPP_NAMES
    assert {spec.name for spec in tunables(Dwpp)} == RPP_NAMES - {
        'rotate_to_heading_min_angle', 'approach_velocity_scaling_dist',
        'min_approach_linear_velocity'}
    spec = {spec.name: spec for spec in tunables(PurePursuit)}['rotate_to_heading_min_angle']
    assert (spec.default, spec.unit, spec.low, spec.high) == (math.pi / 4, 'rad', 0.0, math.pi)


def test_an_instance_reads_the_default_until_tuned_and_only_itself_is_tuned():
    tuned, untouched = PurePursuit(), PurePursuit()
    assert tuned.lookahead_time == 1.5
    tune(tuned, {'lookahead_time': 0.5, 'not_a_tunable': 3.0})
    assert tuned.lookahead_time == 0.5 and untouched.lookahead_time == 1.5
    assert not hasattr(tuned, 'not_a_tunable')


def test_a_default_outside_its_range_is_refused_where_it_is_declared():
    with pytest.raises(ValueError, match='outside'):
        Tunable(5.0, 'a gain', '1/s', 0.0, 1.0)


@pytest.fixture
def tutorial_system(rclpy_context, tmp_path, monkeypatch):
    """The node driving with the tutorial's own my_controller.py."""
    page = TUTORIALS / 'write-a-controller.md'
    files = {name: text[0] for kind, name, text in tutorial_steps(page) if kind == 'file'}
    (tmp_path / 'my_controller.py').write_text(files['my_controller.py'])
    monkeypatch.syspath_prepend(str(tmp_path))
    system = InProcessSystem(context=rclpy_context, output_dir=tmp_path,
                             controller='my_controller:WaypointP')
    yield system
    system.close()


def _set(system: InProcessSystem, name: str, value: float):
    request = SetParameters.Request(parameters=[ParameterMsg(name=name, value=ParameterValue(
        type=ParameterType.PARAMETER_DOUBLE, double_value=value))])
    return system.call(SetParameters, '/turtle_traj/set_parameters', request).results[0]


def test_a_tutorial_controllers_tuning_set_live_changes_the_next_run(tutorial_system):
    system = tutorial_system
    node = system.node
    for name in ('WaypointP.speed_gain', 'WaypointP.turn_gain', 'pure_pursuit.lookahead_time',
                 'dwpp.max_lookahead_dist'):
        assert node.has_parameter(name), name
    described = node.describe_parameter('WaypointP.speed_gain')
    assert described.floating_point_range[0].to_value == 20.0
    # speed = speed_gain * the distance to the point: 2 m/s per metre is capped at 1 m/s
    first = system.call(Move, 'move', Move.Request(distance=1.0))
    assert first.success, first.message
    assert max(abs(p.linear_velocity) for p in system.poses) == pytest.approx(1.0)
    assert _set(system, 'WaypointP.speed_gain', 0.5).successful
    second = system.call(Move, 'move', Move.Request(distance=-1.0))
    assert second.success, second.message
    # 0.5 m/s per metre, 1 m away at the start: at most 0.5 m/s, and it reaches it
    assert max(abs(p.linear_velocity) for p in system.poses) == pytest.approx(0.5, abs=0.01)
    assert second.elapsed > 2 * first.elapsed
    refused = _set(system, 'WaypointP.speed_gain', 100.0)
    assert not refused.successful and refused.reason
    assert node.get_parameter('WaypointP.speed_gain').value == 0.5

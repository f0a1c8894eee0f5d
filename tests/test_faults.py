"""Faults and hostile input: the turtle killed, reset or raced for; the node keeps serving."""

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from rcl_interfaces.msg import Parameter as ParameterMsg
from rcl_interfaces.msg import ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from std_srvs.srv import Empty, Trigger
from turtle_traj_interfaces.msg import Ending
from turtle_traj_interfaces.srv import DrawShape, GoTo, Move
from turtlesim.srv import Kill, SetPen, Spawn, TeleportAbsolute

from turtle_traj.core.turtlesim_contract import SPAWN_XY_M


def _running(turtle_system, service_type, name, request):
    future = turtle_system.start(service_type, name, request)
    assert turtle_system.spin_until(lambda: turtle_system.node.busy)
    turtle_system.spin_sim_seconds(0.5)
    return future


def test_turtle_killed_mid_run_aborts_then_a_new_turtle1_is_driven(turtle_system):
    drawing = _running(turtle_system, DrawShape, 'draw_square', DrawShape.Request(size=2.0))
    turtle_system.call(Kill, '/kill', Kill.Request(name='turtle1'))
    # pose_timeout (0.5 s) of simulated time, then the next control tick: whatever the wall rate
    assert turtle_system.spin_until(drawing.done, timeout_s=0.6)
    assert not drawing.result().success and drawing.result().ending.code == Ending.POSE_LOST
    assert 'no pose on /turtle1/pose' in drawing.result().message
    spawned = turtle_system.call(Spawn, '/spawn', Spawn.Request(x=3.0, y=3.0, name='turtle1'))
    assert spawned.name == 'turtle1'
    assert turtle_system.spin_until(lambda: turtle_system.node.ready)
    assert turtle_system.call(Move, 'move', Move.Request(distance=1.0)).success


def test_simulator_reset_mid_run_aborts_as_a_jump(turtle_system):
    drawing = _running(turtle_system, GoTo, 'go_to', GoTo.Request(x=9.0, y=9.0))
    turtle_system.spin_sim_seconds(1.5)
    turtle_system.call(Empty, '/reset')
    assert turtle_system.spin_until(drawing.done, timeout_s=5.0)
    assert not drawing.result().success and drawing.result().ending.code == Ending.POSE_JUMPED
    assert 'jumped' in drawing.result().message
    assert turtle_system.call(Move, 'move', Move.Request(distance=1.0)).success


def test_two_clients_racing_get_one_run_and_one_busy_refusal(turtle_system):
    first = turtle_system.start(Move, 'move', Move.Request(distance=1.0))
    second = turtle_system.start(Move, 'rotate', Move.Request(angle=1.0))
    assert turtle_system.spin_until(lambda: first.done() and second.done(), timeout_s=30.0)
    results = sorted([first.result(), second.result()], key=lambda r: r.success)
    assert [r.success for r in results] == [False, True]
    assert results[0].ending.code == Ending.BUSY


def test_parameter_change_mid_run_takes_effect_and_the_run_succeeds(turtle_system):
    moving = _running(turtle_system, Move, 'move', Move.Request(distance=4.0))
    request = SetParameters.Request(parameters=[ParameterMsg(
        name='linear_speed',
        value=ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=2.0))])
    assert (
        turtle_system.call(SetParameters, '/turtle_traj/set_parameters', request)
        .results[0]
        .successful
    )
    assert turtle_system.spin_until(moving.done, timeout_s=30.0)
    assert moving.result().success
    assert max(p.linear_velocity for p in turtle_system.poses) == 2.0
    assert abs(moving.result().final_x - (SPAWN_XY_M + 4.0)) < 0.001


hostile_floats = st.sampled_from([math.nan, math.inf, -math.inf, 1e308, -1e308, -1.0, 5e-324])


@settings(
    max_examples=25,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(
    service=st.sampled_from(
        ['draw_square', 'draw_polygon', 'draw_circle', 'draw_spiral', 'draw_sine']
    ),
    size=hostile_floats,
    speed=hostile_floats,
    sides=st.integers(0, 2**32 - 1),
)
def test_hostile_shape_requests_are_answered_and_refused(
    turtle_system, service, size, speed, sides
):
    response = turtle_system.call(
        DrawShape,
        service,
        DrawShape.Request(size=size, linear_speed=speed, sides=sides, turns=size, growth=size),
    )
    assert not response.success, response.message
    assert response.ending.code == Ending.INVALID_REQUEST, response.message
    assert not turtle_system.node.busy


def test_hostile_simulator_requests_leave_it_working(turtle_system):
    for name in ['', 'x' * 10_000, 'bad name', '/abs/olute', '..', 'ünïcode', 'turtle1']:
        turtle_system.call(Spawn, '/spawn', Spawn.Request(x=1.0, y=1.0, name=name))
    turtle_system.call(Spawn, '/spawn', Spawn.Request(x=math.nan, y=math.inf, name='nanny'))
    turtle_system.call(
        TeleportAbsolute,
        '/turtle1/teleport_absolute',
        TeleportAbsolute.Request(x=math.inf, y=1.0, theta=0.0),
    )
    turtle_system.call(SetPen, '/turtle1/set_pen', SetPen.Request(r=255, width=255))
    turtle_system.call(Kill, '/kill', Kill.Request(name='y' * 10_000))
    assert 'nanny' not in turtle_system.sim.world.turtles
    pose = turtle_system.sim.world.turtles['turtle1']
    assert all(math.isfinite(v) for v in (pose.x, pose.y, pose.theta))
    assert turtle_system.call(Move, 'move', Move.Request(distance=1.0)).success


@pytest.mark.parametrize(
    ('service_type', 'name', 'request_fields'),
    [
        (Move, 'rotate', dict(angle=6.0)),  # in-place turn
        (DrawShape, 'draw_circle', dict(size=1.0, forever=True)),  # continuous curve (endless)
        (GoTo, 'go_to', dict(x=9.0, y=2.0)),  # turn, then straight
    ],
)
def test_stop_in_each_kind_of_phase_leaves_the_turtle_still(
    turtle_system, service_type, name, request_fields
):
    running = _running(turtle_system, service_type, name, service_type.Request(**request_fields))
    assert turtle_system.call(Trigger, '/turtle_traj/stop').success
    assert turtle_system.spin_until(running.done, timeout_s=5.0)
    turtle_system.spin_sim_seconds(0.2)
    last = turtle_system.poses[-1]
    assert (last.linear_velocity, last.angular_velocity) == (0.0, 0.0)
    assert not turtle_system.node.busy


@pytest.mark.system
def test_sigterm_mid_run_sends_a_final_stop_command(rclpy_context, tmp_path):
    """The node program is ended while it drives: the last cmd_vel it sends is all zero."""
    from geometry_msgs.msg import Twist
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from turtlesim.msg import Pose

    from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
    from turtle_traj.rosutils.runtime import spin_until
    from turtle_traj.testing.processes import program, terminate

    observer = Node('sigterm_observer', context=rclpy_context)
    executor = SingleThreadedExecutor(context=rclpy_context)
    executor.add_node(observer)
    commands: list[Twist] = []
    observer.create_subscription(Twist, 'turtle1/cmd_vel', commands.append, TURTLE_TOPIC_QOS)
    client = observer.create_client(DrawShape, '/turtle_traj/draw_circle')
    try:
        with program('turtle_traj', '--with-sim', cwd=tmp_path) as process:
            assert spin_until(executor, client.service_is_ready, timeout_s=10.0)
            # The node refuses requests until it has a pose: wait for the simulator to publish.
            poses = []
            observer.create_subscription(Pose, 'turtle1/pose', poses.append, TURTLE_TOPIC_QOS)
            assert spin_until(executor, lambda: len(poses) > 10, timeout_s=10.0)
            client.call_async(DrawShape.Request(size=1.0, forever=True))
            assert spin_until(
                executor, lambda: any(c.linear.x > 0 for c in commands), timeout_s=10.0
            )
            stderr = terminate(process)
            spin_until(executor, lambda: commands[-1].linear.x == 0.0, timeout_s=3.0)
        assert process.returncode == 0, stderr
        assert 'Traceback' not in stderr
        assert (commands[-1].linear.x, commands[-1].angular.z) == (0.0, 0.0)
    finally:
        executor.shutdown()
        observer.destroy_node()

"""Refusals, stop, live parameters, reset and a vanishing simulator: the node keeps serving."""

import math
import subprocess
import sys

import pytest
from geometry_msgs.msg import Point
from rcl_interfaces.msg import Parameter as ParameterMsg
from rcl_interfaces.msg import ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from rclpy.clock import ClockType
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.time import Time
from std_srvs.srv import Trigger
from turtle_traj_interfaces.msg import Ending
from turtle_traj_interfaces.srv import DrawShape, FollowPath, GoTo, Move

from turtle_traj.core.turtlesim_contract import SPAWN_XY_M, WORLD_SIZE_M
from turtle_traj.node.trajectory_node import TrajectoryNode
from turtle_traj.rosutils.runtime import spin_until
from turtle_traj.testing.processes import program, terminate

# Room from the start pose to the right and top edges, after the default 0.3 m wall margin.
ROOM = WORLD_SIZE_M - 0.3 - SPAWN_XY_M


def _double(value: float) -> ParameterValue:
    return ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=value)


def _set(turtle_system, **values):
    request = SetParameters.Request(parameters=[
        ParameterMsg(name=name, value=value) for name, value in values.items()])
    return turtle_system.call(SetParameters, '/turtle_traj/set_parameters', request).results


# One refusal per service type here, through ROS; every refusal is in test_planning.py.
@pytest.mark.parametrize(('service', 'service_type', 'fields', 'reason'), [
    ('draw_square', DrawShape, dict(size=6.0), f'the largest that fits from here is {ROOM:.2f}'),
    ('draw_polygon', DrawShape, dict(sides=4_000_000_000), 'needs 3 to'),
    ('go_to', GoTo, dict(x=math.inf, y=5.0), 'x must be a finite number'),
    ('rotate', Move, dict(angle=math.nan), 'angle must be a finite number'),
    ('follow_path', FollowPath, dict(points=[Point(x=SPAWN_XY_M, y=SPAWN_XY_M)]),
     'already there'),
])
def test_bad_requests_are_refused_and_the_node_still_works(turtle_system, service, service_type,
                                                            fields, reason):
    response = turtle_system.call(service_type, service, service_type.Request(**fields))
    assert not response.success and response.ending.code == Ending.INVALID_REQUEST
    assert reason in response.message
    assert not turtle_system.node.busy
    turtle_system.spin_sim_seconds(0.1)
    assert max(p.linear_velocity for p in turtle_system.poses) == 0.0  # refused before moving
    after = turtle_system.call(Move, 'rotate', Move.Request(angle=0.5))
    assert after.success, after.message


def test_busy_refusal_names_the_runner_and_stop_ends_it(turtle_system):
    circling = turtle_system.start(
        DrawShape, 'draw_circle', DrawShape.Request(size=1.0, forever=True)
    )
    assert turtle_system.spin_until(lambda: turtle_system.node.busy)
    turtle_system.spin_sim_seconds(2.0)
    busy = turtle_system.call(GoTo, 'go_to', GoTo.Request(x=2.0, y=2.0))
    assert not busy.success and busy.ending.code == Ending.BUSY
    assert 'busy: circle is running' in busy.message and '/turtle_traj/stop' in busy.message
    stopped = turtle_system.call(Trigger, '/turtle_traj/stop')
    assert stopped.success and stopped.message == 'stopped circle'
    assert turtle_system.spin_until(circling.done)
    result = circling.result()
    assert result.success  # an endless circle ends only by stop, which is its normal end
    assert result.ending.code == Ending.STOPPED
    assert turtle_system.spin_until(lambda: turtle_system.poses[-1].linear_velocity == 0.0)


def test_stop_aborts_a_finite_trajectory(turtle_system):
    drawing = turtle_system.start(DrawShape, 'draw_square', DrawShape.Request(size=2.0))
    assert turtle_system.spin_until(lambda: turtle_system.node.busy)
    turtle_system.spin_sim_seconds(1.0)
    turtle_system.call(Trigger, '/turtle_traj/stop')
    assert turtle_system.spin_until(drawing.done)
    assert not drawing.result().success and drawing.result().ending.code == Ending.STOPPED
    assert drawing.result().message == 'square stopped by request'
    assert turtle_system.call(Move, 'move', Move.Request(distance=0.5)).success


def test_live_parameters_change_speed_and_bad_values_are_refused(turtle_system):
    slow = turtle_system.call(Move, 'move', Move.Request(distance=1.0))
    results = _set(turtle_system, linear_speed=_double(2.0))
    assert results[0].successful
    fast = turtle_system.call(Move, 'move', Move.Request(distance=-1.0))
    assert fast.elapsed < 0.7 * slow.elapsed
    assert max(p.linear_velocity for p in turtle_system.poses) == pytest.approx(2.0, abs=1e-6)

    for name, value in [
        ('linear_speed', _double(-1.0)),
        ('linear_speed', _double(math.nan)),
        ('exact.heading_gain',
         ParameterValue(type=ParameterType.PARAMETER_STRING, string_value='fast')),
        ('control_rate', _double(100.0)),
        ('wall_margin', _double(5.4)),
    ]:
        result = _set(turtle_system, **{name: value})[0]
        assert not result.successful, name
        assert result.reason
    assert turtle_system.node.get_parameter('linear_speed').value == 2.0
    assert turtle_system.node.get_parameter('wall_margin').value == 0.3


def test_wall_margin_change_applies_to_the_next_plan(turtle_system):
    assert _set(turtle_system, wall_margin=_double(2.0))[0].successful
    refused = turtle_system.call(Move, 'move', Move.Request(distance=4.0))
    assert refused.ending.code == Ending.INVALID_REQUEST
    assert f'the largest that fits from here is {ROOM - 1.7:.2f}' in refused.message


def test_reset_returns_the_turtle_to_the_centre(turtle_system):
    assert turtle_system.call(Move, 'move', Move.Request(distance=2.0)).success
    response = turtle_system.call(Trigger, '/turtle_traj/reset')
    assert response.success, response.message
    assert turtle_system.spin_until(lambda: turtle_system.poses[-1].x == SPAWN_XY_M)


def test_vanishing_simulator_aborts_the_trajectory_and_node_keeps_serving(turtle_system):
    drawing = turtle_system.start(DrawShape, 'draw_square', DrawShape.Request(size=2.0))
    assert turtle_system.spin_until(lambda: turtle_system.node.busy)
    turtle_system.spin_sim_seconds(0.5)
    turtle_system.executor.remove_node(
        turtle_system.sim
    )  # the simulator stops: no more poses, no /clock
    assert turtle_system.spin_until(drawing.done, timeout_s=5.0)
    result = drawing.result()
    assert not result.success and result.ending.code == Ending.POSE_LOST
    assert 'no pose on /turtle1/pose' in result.message
    refused = turtle_system.call(Move, 'move', Move.Request(distance=1.0), timeout_s=5.0)
    assert not refused.success and refused.ending.code == Ending.POSE_LOST
    assert 'is the simulator running' in refused.message
    turtle_system.executor.add_node(turtle_system.sim)  # it comes back
    assert turtle_system.spin_until(lambda: turtle_system.node.ready)
    assert turtle_system.call(Move, 'move', Move.Request(distance=0.5)).success


def test_a_long_callback_in_the_lock_step_process_is_not_a_vanished_simulator(turtle_system):
    """Simulated time stands still while any callback of the process runs. One that takes
    longer than pose_timeout of wall time (the demo once read a 12 000-pose plan message in
    0.6 s) used to abort the run as if the simulator had gone."""
    import time

    timeout_s = turtle_system.node.settings.pose_timeout_s
    drawing = turtle_system.start(DrawShape, 'draw_square', DrawShape.Request(size=2.0))
    assert turtle_system.spin_until(lambda: turtle_system.node.busy)
    turtle_system.spin_sim_seconds(0.5)
    stall = turtle_system.client.create_timer(
        0.1, lambda: (stall.cancel(), time.sleep(2 * timeout_s))
    )
    assert turtle_system.spin_until(drawing.done, timeout_s=60.0)
    assert drawing.result().success, drawing.result().message


def test_a_node_that_falls_behind_reads_every_pose_it_missed(turtle_system):
    """A node process that does not run for a while (a starved machine) then reads the poses
    it missed, in order. With turtlesim's own history of 7 it read only the last 7 of 25 and
    aborted: the turtle seemed to jump 0.6 m."""
    drawing = turtle_system.start(
        DrawShape, 'draw_square', DrawShape.Request(size=4.0, linear_speed=2.0)
    )
    assert turtle_system.spin_until(lambda: turtle_system.node.busy)
    turtle_system.spin_sim_seconds(0.6)  # on the first side, at full speed
    turtle_system.executor.remove_node(turtle_system.node)
    turtle_system.spin_sim_seconds(0.4)  # 25 poses, 0.8 m, the last command still acting
    turtle_system.executor.add_node(turtle_system.node)
    assert turtle_system.spin_until(drawing.done)
    assert drawing.result().success, drawing.result().message


def test_a_node_that_falls_behind_past_pose_timeout_reads_its_poses_before_judging(
        turtle_system):
    """A node process that does not run for longer than pose_timeout of simulated time, the
    poses all waiting in its queue, rides it out: its watchdog reads them before it judges the
    silence, as its control tick does. Woken, the executor may update the node clock and run
    the watchdog before the subscription's callback."""
    timeout_s = turtle_system.node.settings.pose_timeout_s
    drawing = turtle_system.start(
        DrawShape, 'draw_square', DrawShape.Request(size=1.0, linear_speed=0.5)
    )
    assert turtle_system.spin_until(lambda: turtle_system.node.busy)
    turtle_system.spin_sim_seconds(0.6)  # on the first side
    turtle_system.executor.remove_node(turtle_system.node)
    turtle_system.spin_sim_seconds(timeout_s + 0.1)  # the poses wait in the node's queue
    # woken, the executor takes the clock's update, then the watchdog's beat, and only then
    # the poses: so here, by hand
    turtle_system.node.get_clock().set_ros_time_override(
        Time(nanoseconds=round(turtle_system.sim_time_s * 1e9), clock_type=ClockType.ROS_TIME))
    turtle_system.node._runs.on_watchdog()
    turtle_system.executor.add_node(turtle_system.node)
    assert turtle_system.spin_until(drawing.done)
    assert drawing.result().success, drawing.result().message


def test_node_without_simulator_refuses_at_once(rclpy_context):
    node = TrajectoryNode(context=rclpy_context)
    client_node = Node('lonely_client', context=rclpy_context)
    executor = SingleThreadedExecutor(context=rclpy_context)
    executor.add_node(node)
    executor.add_node(client_node)
    try:
        client = client_node.create_client(DrawShape, '/turtle_traj/draw_square')
        assert spin_until(executor, client.service_is_ready, timeout_s=10.0)
        future = client.call_async(DrawShape.Request())
        assert spin_until(executor, future.done, timeout_s=5.0)
        assert not future.result().success and future.result().ending.code == Ending.POSE_LOST
        assert 'no pose on /turtle1/pose (never)' in future.result().message
    finally:
        executor.shutdown()
        node.destroy_node()
        client_node.destroy_node()


@pytest.mark.system
def test_sigterm_ends_simulator_and_node_together_cleanly(tmp_path):
    """Both programs in one process (--with-sim), then SIGTERM: exit 0, no traceback."""
    with program('turtle_traj', '--with-sim', '--time-scale', '5', cwd=tmp_path) as process:
        stderr = terminate(process)
    assert process.returncode == 0, stderr
    assert 'Traceback' not in stderr



_STUCK_AT_EXIT = '''
import sys, time
from rclpy.node import Node
from turtle_traj.rosutils import runtime

runtime.SHUTDOWN_DEADLINE_S = 2.0
def nodes(stop):
    print('spinning', flush=True)
    return [Node('stuck_at_exit')]
sys.exit(runtime.run_nodes(nodes, on_exit=lambda: time.sleep(600)))
'''


@pytest.mark.system
def test_a_shutdown_that_hangs_ends_at_its_deadline_with_the_stacks():
    """A program whose shutdown never finishes (here its exit hook; in a loaded suite once, Fast
    DDS destroying the participant) ends at the deadline, with every thread's stack, instead of
    outliving whoever stopped it."""
    process = subprocess.Popen([sys.executable, '-c', _STUCK_AT_EXIT], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    try:
        assert process.stdout.readline() == 'spinning\n', process.communicate()[1]
        process.terminate()
        stderr = process.communicate(timeout=30)[1]
    finally:
        process.kill()
        process.wait()
    assert process.returncode == 1, stderr
    assert 'Timeout (0:00:02)!' in stderr
    assert 'in <lambda>' in stderr  # where it hung


_SOLVER_PROBE = '''
import sys, time
import rclpy
from rclpy.parameter import Parameter
from turtle_traj.node.trajectory_node import TrajectoryNode

def loaded_within(seconds):
    deadline = time.monotonic() + seconds
    while 'toppra.algorithm' not in sys.modules and time.monotonic() < deadline:
        time.sleep(0.05)
    return 'toppra.algorithm' in sys.modules

rclpy.init()
if sys.argv[1] == 'at start-up':
    node = TrajectoryNode(parameter_overrides=[Parameter('max_linear_accel', value=0.5)])
    print('limits at start-up', 'toppra.algorithm' in sys.modules)  # as it is made
else:
    node = TrajectoryNode()
    print('unlimited', loaded_within(0.5))
    node.set_parameters([Parameter('max_angular_accel', value=1.0)])
    print('limits set live', loaded_within(60.0))
node.destroy_node()
rclpy.shutdown()
'''


@pytest.mark.system
@pytest.mark.parametrize(('when', 'printed'), [
    ('at start-up', ['limits at start-up True']),
    ('live', ['unlimited False', 'limits set live True'])])
def test_limits_known_load_the_solver_before_a_run(when, printed):
    """TOPP-RA (2.4-2.7 s to import here) is imported as soon as acceleration limits are known:
    by a node given them at start-up before it serves, by one given them live beside its
    executor. In a run, a simulator on its own clock counted that time without progress and
    the run aborted; beside a run, the import held Python's lock from the node's callbacks
    and the run aborted for pose silence (each in its own interpreter, where nothing imported
    it before)."""
    done = subprocess.run([sys.executable, '-c', _SOLVER_PROBE, when], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split('\n')[:len(printed)] == printed

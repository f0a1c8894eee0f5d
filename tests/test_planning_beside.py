"""A request is planned beside the executor: the node answers while it plans, lock-step holds
the simulator meanwhile, and a stop, a cancel or a shutdown during the plan ends the request."""

import math
import threading
import time

import pytest
import rclpy
from action_msgs.msg import GoalStatus
from rcl_interfaces.srv import GetParameters
from rclpy.executors import SingleThreadedExecutor
from std_srvs.srv import Trigger
from turtle_traj_interfaces.action import Draw
from turtle_traj_interfaces.msg import Ending
from turtle_traj_interfaces.srv import DrawShape, Move

from turtle_traj.core.planning import planner
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M
from turtle_traj.rosutils import offload
from turtle_traj.rosutils.runtime import spin_until
from turtle_traj.testing.geometry import distance_to_polyline, regular_polygon, xy


@pytest.fixture
def held_plan(monkeypatch):
    """Plans wait, once begun (`begun`), until `release` is set; released at the end."""
    begun, release = threading.Event(), threading.Event()
    real_plan = planner.plan

    def held(*args, **kwargs):
        begun.set()
        release.wait(60.0)
        return real_plan(*args, **kwargs)
    monkeypatch.setattr(planner, 'plan', held)
    yield begun, release
    release.set()


def _planning(turtle_system, begun, service_type, name, request):
    """Send a request and spin until its plan has begun; its future."""
    future = turtle_system.start(service_type, name, request)
    assert turtle_system.spin_until(begun.is_set, timeout_s=10.0)
    return future


def _drained_until(turtle_system, condition, wall_s: float = 5.0) -> bool:
    """Run the callbacks that come, never stepping, until `condition()` or `wall_s` passed."""
    deadline = time.monotonic() + wall_s
    while not condition() and time.monotonic() < deadline:
        turtle_system.executor.drain()
        time.sleep(0.01)
    return condition()


def test_the_node_answers_while_it_plans_and_the_simulator_waits_for_the_plan(
        turtle_system, held_plan):
    begun, release = held_plan
    square = _planning(turtle_system, begun, DrawShape, 'draw_square',
                       DrawShape.Request(size=1.0))
    planned_from = turtle_system.sim_time_s
    held_until = time.monotonic() + 2 * turtle_system.node.settings.pose_timeout_s
    steps = turtle_system.executor.steps
    speed = turtle_system.call(GetParameters, 'get_parameters',
                               GetParameters.Request(names=['linear_speed']), timeout_s=1.0)
    assert speed.values[0].double_value > 0.0
    busy = turtle_system.call(Move, 'move', Move.Request(distance=1.0), timeout_s=1.0)
    assert not busy.success and busy.ending.code == Ending.BUSY
    assert busy.message.startswith('busy: square is being planned; wait for it or call '
                                   '/turtle_traj/stop')
    # a plan that takes longer than pose_timeout of wall time, while simulated time stands
    spin_until(turtle_system.executor, lambda: time.monotonic() > held_until, timeout_s=5.0)
    assert not square.done()
    # lock-step: the plan belongs to the step it was asked in, whatever it took on the wall
    assert turtle_system.executor.steps == steps and turtle_system.sim_time_s == planned_from
    release.set()
    # The run starts, and the watchdog beats before the next step (as a paced simulator
    # leaves it time to): the plan's wall time is not the simulator's silence.
    assert _drained_until(turtle_system, lambda: turtle_system.node.busy)
    assert not _drained_until(turtle_system, lambda: not turtle_system.node.busy, wall_s=0.2)
    assert turtle_system.executor.steps == steps
    assert turtle_system.spin_until(square.done, timeout_s=60.0)
    assert square.result().success, square.result().message
    corners = regular_polygon(SPAWN_XY_M, SPAWN_XY_M, 0.0, 4, 1.0, False)
    assert distance_to_polyline(xy(turtle_system.poses), corners).max() < 0.01


def test_a_stop_while_planning_ends_the_request_and_the_turtle_never_moves(
        turtle_system, held_plan):
    begun, release = held_plan
    square = _planning(turtle_system, begun, DrawShape, 'draw_square',
                       DrawShape.Request(size=1.0))
    stopped = turtle_system.call(Trigger, 'stop', timeout_s=1.0)
    assert stopped.message == 'stopped square while it was being planned'
    assert turtle_system.spin_until(square.done, timeout_s=1.0)
    assert not square.result().success and square.result().ending.code == Ending.STOPPED
    assert square.result().message == 'square stopped by request before it started'
    release.set()  # the plan ends on its thread; its result is dropped
    assert turtle_system.spin_until(lambda: offload.in_flight(turtle_system.node) == 0,
                                    timeout_s=5.0)
    turtle_system.spin_sim_seconds(1.0)
    assert turtle_system.node.ready and not turtle_system.node.busy
    assert all(math.dist(p, (SPAWN_XY_M, SPAWN_XY_M)) < 1e-9 for p in xy(turtle_system.poses))
    moved = turtle_system.call(Move, 'move', Move.Request(distance=1.0))
    assert moved.success and moved.final_x == pytest.approx(SPAWN_XY_M + 1.0, abs=1e-3)


def test_a_goal_cancelled_while_planning_ends_cancelled(turtle_system, held_plan):
    begun, _release = held_plan
    draw = turtle_system.action_client(Draw, '/turtle_traj/draw')
    assert turtle_system.spin_until(draw.server_is_ready, timeout_s=60.0)
    sent = draw.send_goal_async(Draw.Goal(trajectory='text', text='A', height=1.0))
    assert turtle_system.spin_until(lambda: sent.done() and begun.is_set(), timeout_s=10.0)
    cancel = sent.result().cancel_goal_async()
    assert turtle_system.spin_until(cancel.done, timeout_s=1.0)
    assert len(cancel.result().goals_canceling) == 1
    result = sent.result().get_result_async()
    assert turtle_system.spin_until(result.done, timeout_s=1.0)
    assert result.result().status == GoalStatus.STATUS_CANCELED
    assert result.result().result.ending.code == Ending.CANCELLED
    assert result.result().result.message == 'text stopped by request before it started'


def test_a_shutdown_while_planning_answers_the_request(turtle_system, held_plan):
    begun, _release = held_plan
    square = _planning(turtle_system, begun, DrawShape, 'draw_square',
                       DrawShape.Request(size=1.0))
    assert turtle_system.node.shutdown_turtle() is None  # no run to wait for
    assert turtle_system.spin_until(square.done, timeout_s=1.0)
    assert square.result().ending.code == Ending.SHUTTING_DOWN
    assert square.result().message == 'square aborted: the node is shutting down'


def test_offloaded_work_hands_its_result_or_its_error_to_the_executor(rclpy_context):
    node = rclpy.create_node('offload_test', context=rclpy_context)
    executor = SingleThreadedExecutor(context=rclpy_context)
    executor.add_node(node)
    worker = offload.Offloader(node, 'offload_test')
    on_executor = threading.get_ident()
    threads: list[int] = []

    def work(value):
        threads.append(threading.get_ident())
        if value is None:
            raise ValueError('no value')
        return value * 2

    try:
        answered = worker.submit(lambda: work(21))
        failed = worker.submit(lambda: work(None))
        dropped = worker.submit(lambda: work(1))
        dropped.cancel()
        assert spin_until(executor, lambda: offload.in_flight(node) == 0, timeout_s=10.0)
        assert answered.result() == 42
        with pytest.raises(ValueError, match='no value'):
            failed.result()
        assert dropped.cancelled() and dropped.result() is None
        assert len(threads) == 3 and on_executor not in threads
    finally:
        executor.shutdown()
        node.destroy_node()

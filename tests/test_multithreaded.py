"""The trajectory node composed on rclpy's MultiThreadedExecutor, as a ROS user composing nodes
would run it: concurrent requests start exactly one run, and the turtle drives exactly it.

Its handlers sit in a ReentrantCallbackGroup (they await the run's end while the control timer
drives), so on several threads they run at once: a request's check for a running trajectory and
its claim of the turtle must be one step (the node serialises its state with a lock).
"""

from __future__ import annotations

import math
import threading
import time

import pytest

from turtle_traj.core.registry import BY_NAME
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M

REQUESTS = 8  # within a service's request queue (rmw's default depth, 10)
POLYGON = {'sides': 12, 'size': 0.15}
# Planning is slowed to this (a drawing's plan takes longer), sleeping: the other handlers run
# meanwhile, and without the node's lock each would find no run yet and start its own.
PLANNING_S = 0.05


@pytest.fixture
def composed(ros_context, monkeypatch):
    """The trajectory node and a client node in one MultiThreadedExecutor of four threads, our
    simulator in a SingleThreadedExecutor (as if in a process of its own), each spun on a
    thread of its own."""
    from rclpy.executors import MultiThreadedExecutor, SingleThreadedExecutor
    from rclpy.node import Node

    from turtle_traj.node import trajectory_node
    from turtle_traj.node.trajectory_node import TrajectoryNode
    from turtle_traj.sim.node import SimNode

    plan = trajectory_node.planning.plan

    def slow_plan(*args, **kwargs):
        time.sleep(PLANNING_S)
        return plan(*args, **kwargs)
    monkeypatch.setattr(trajectory_node.planning, 'plan', slow_plan)
    namespace = '/composed'
    sim = SimNode(context=ros_context, namespace=namespace)
    node = TrajectoryNode(context=ros_context, namespace=namespace)
    client = Node('concurrent_client', context=ros_context, namespace=namespace)
    composed_executor = MultiThreadedExecutor(num_threads=4, context=ros_context)
    sim_executor = SingleThreadedExecutor(context=ros_context)
    composed_executor.add_node(node)
    composed_executor.add_node(client)
    sim_executor.add_node(sim)
    stop = threading.Event()

    def spin(executor) -> None:  # until asked: an executor shut down while spinning can raise
        while not stop.is_set():
            executor.spin_once(timeout_sec=0.05)
    spinners = [threading.Thread(target=spin, args=(executor,), daemon=True)
                for executor in (composed_executor, sim_executor)]
    for spinner in spinners:
        spinner.start()
    try:
        yield sim, node, client
    finally:
        node.abort_run('the test is over')  # a handler still waiting lets go of its thread
        stop.set()
        for spinner in spinners:
            spinner.join(timeout=10.0)
        for executor in (composed_executor, sim_executor):
            executor.shutdown()
        for each in (client, node, sim):
            each.destroy_node()


def _wait(condition, timeout_s: float) -> bool:
    event = threading.Event()
    for _ in range(int(timeout_s / 0.02)):
        if condition():
            return True
        event.wait(0.02)
    return condition()


def _matched_both_ways(call, request) -> None:
    """Send `request` until it is answered. A service that answers a new client before it has
    matched the client's reply reader loses the answer (rmw_fastrtps: "client will not receive
    response"; see turtle_traj.client.answers): the concurrent requests below are answered at
    once (refused as busy), so every client is first known to the node."""
    send = call if callable(call) else call.call_async
    for _ in range(5):
        answer = send(request)
        if _wait(answer.done, 2.0):
            return
    raise AssertionError('the node never answered a warm-up request')


def test_concurrent_requests_start_exactly_one_run(composed):
    from turtle_traj.api.ros_interface import make_request, service_type

    sim, node, client = composed
    kind = BY_NAME['polygon']
    assert _wait(lambda: node.ready, 20.0), 'the node never became ready'
    calls = [client.create_client(service_type(kind), f'turtle_traj/{kind.service}')
             for _ in range(REQUESTS)]
    try:
        assert _wait(lambda: all(call.service_is_ready() for call in calls), 20.0)
        for call in calls:
            _matched_both_ways(call, make_request(kind, {'sides': 2}))  # refused at once
        request = make_request(kind, POLYGON)
        answers = [call.call_async(request) for call in calls]  # all at once
        assert _wait(lambda: all(answer.done() for answer in answers), 60.0), \
            'not every request was answered'
        responses = [answer.result() for answer in answers]
    finally:
        for call in calls:
            client.destroy_client(call)
    done = [response for response in responses if response.success]
    refused = [response.message for response in responses if not response.success]
    assert len(done) == 1, [response.message for response in responses]
    assert len(refused) == REQUESTS - 1 and all('busy' in reason for reason in refused), refused
    # one closed polygon driven, once: back where it started, on the simulator's own state
    turtle = next(iter(sim.world))
    assert (turtle.x, turtle.y) == pytest.approx((SPAWN_XY_M, SPAWN_XY_M), abs=0.005)
    # heading along its last side: a turn of one exterior angle short of the start's
    exterior = math.tau / POLYGON['sides']
    assert min(abs(math.remainder(turtle.theta - turn, math.tau))
               for turn in (exterior, -exterior)) < 0.01, turtle.theta
    assert done[0].path_length == pytest.approx(POLYGON['sides'] * POLYGON['size'])
    assert not node.busy


def test_concurrent_draw_goals_run_one_and_abort_the_rest_as_busy(composed):
    from action_msgs.msg import GoalStatus
    from rclpy.action import ActionClient

    from turtle_traj.api.ros_interface import DRAW_ACTION, DRAW_ACTION_TYPE, make_goal
    from turtle_traj.rosutils.interfaces import interface

    sim, node, client = composed
    assert _wait(lambda: node.ready, 20.0), 'the node never became ready'
    action = ActionClient(client, interface(DRAW_ACTION_TYPE), f'turtle_traj/{DRAW_ACTION}')
    try:
        assert _wait(action.server_is_ready, 20.0)
        unknown = interface(DRAW_ACTION_TYPE).Goal(trajectory='no_such_kind')  # aborted at once
        _matched_both_ways(lambda _: action.send_goal_async(unknown), None)
        goal = make_goal(BY_NAME['polygon'], POLYGON)
        sent = [action.send_goal_async(goal) for _ in range(REQUESTS)]
        assert _wait(lambda: all(future.done() for future in sent), 30.0)
        results = [future.result().get_result_async() for future in sent]
        assert _wait(lambda: all(result.done() for result in results), 60.0), \
            'not every goal ended'
    finally:
        action.destroy()
    ended = [result.result() for result in results]
    succeeded = [each for each in ended if each.status == GoalStatus.STATUS_SUCCEEDED]
    aborted = [each.result.message for each in ended
               if each.status == GoalStatus.STATUS_ABORTED]
    assert len(succeeded) == 1, [each.result.message for each in ended]
    assert len(aborted) == REQUESTS - 1 and all('busy' in reason for reason in aborted), aborted
    turtle = next(iter(sim.world))
    assert (turtle.x, turtle.y) == pytest.approx((SPAWN_XY_M, SPAWN_XY_M), abs=0.005)
    assert succeeded[0].result.path_length == pytest.approx(
        POLYGON['sides'] * POLYGON['size'])

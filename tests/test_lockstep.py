"""Lock-step simulated time: repeatable to the bit, and fine with several nodes in the executor."""

import math
import time

import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from turtle_traj_interfaces.srv import DrawShape, GoTo, Move
from turtlesim.msg import Pose
from turtlesim.srv import Spawn

from turtle_traj.apps.in_process import SIM_TIME, InProcessSystem
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M, STEP_S
from turtle_traj.node.trajectory_node import TrajectoryNode
from turtle_traj.rosutils.lockstep import MAX_PACE_LAG_S, LockstepExecutor
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.rosutils.runtime import spin_until
from turtle_traj.sim.node import SimNode


def _pose_stream(context, tmp_path, pace=None, **sim_parameters) -> list[tuple[float, ...]]:
    system = InProcessSystem(context=context, output_dir=tmp_path, sim_parameters=sim_parameters,
                             pace=pace)
    try:
        response = system.call(DrawShape, 'draw_hexagon', DrawShape.Request(size=1.0))
        assert response.success, response.message
        return [(p.x, p.y, p.theta, p.linear_velocity, p.angular_velocity)
                for p in system.poses]
    finally:
        system.close()


def _from_first_move(poses: list[tuple[float, ...]]) -> list[tuple[float, ...]]:
    moving = next(index for index, pose in enumerate(poses) if pose[3] or pose[4])
    return poses[moving:]


def test_the_same_request_gives_a_bit_identical_pose_stream(rclpy_context, tmp_path):
    first = _pose_stream(rclpy_context, tmp_path)
    second = _pose_stream(rclpy_context, tmp_path)
    assert len(first) > 300
    assert first == second


def test_seeded_command_jitter_repeats_exactly(rclpy_context, tmp_path):
    jitter = {'command_jitter': 0.032, 'command_jitter_seed': 7}
    first = _pose_stream(rclpy_context, tmp_path, **jitter)
    assert first == _pose_stream(rclpy_context, tmp_path, **jitter)
    assert first != _pose_stream(rclpy_context, tmp_path)  # the jitter did change the run


def test_paced_lockstep_runs_the_same_steps_never_ahead_of_the_wall_clock(
        rclpy_context, tmp_path):
    """Paced (a program's --time-scale): the node answers every step before the next, so the
    pose stream is the unpaced one to the bit; and simulated time never runs ahead of the
    wall clock times the pace by more than the lag it may catch up (after a hold-up)."""
    pace = 5.0
    system = InProcessSystem(context=rclpy_context, output_dir=tmp_path, pace=pace)
    stamps: list[tuple[float, float]] = []  # (wall s, simulated s) at each pose heard
    system.client.create_subscription(
        Pose, 'turtle1/pose', lambda _pose: stamps.append((time.monotonic(), system.sim_time_s)),
        TURTLE_TOPIC_QOS)
    try:
        response = system.call(DrawShape, 'draw_hexagon', DrawShape.Request(size=1.0))
        assert response.success, response.message
        paced = [(p.x, p.y, p.theta, p.linear_velocity, p.angular_velocity)
                 for p in system.poses]
    finally:
        system.close()
    # The request may reach the node a step sooner or later (the two wait differently between
    # steps); from the first step the turtle moves, every pose is the same.
    assert _from_first_move(paced) == _from_first_move(_pose_stream(rclpy_context, tmp_path))
    (wall_0, sim_0), (wall_n, sim_n) = stamps[0], stamps[-1]
    assert sim_n - sim_0 > 5.0  # the hexagon's 6 m at 1 m/s, and its turns: 0.2-0.5 s unpaced
    assert sim_n - sim_0 <= pace * (wall_n - wall_0 + MAX_PACE_LAG_S) + STEP_S


def test_two_trajectory_nodes_drive_two_turtles_at_once(turtle_system):
    spawned = turtle_system.call(
        Spawn, '/spawn', Spawn.Request(x=2.0, y=2.0, theta=0.0, name='turtle2')
    )
    assert spawned.name == 'turtle2'
    second = TrajectoryNode(
        'turtle_traj2',
        context=turtle_system.client.context,
        parameter_overrides=[SIM_TIME, Parameter('turtle_name', value='turtle2')],
    )
    turtle_system.add_node(second)
    poses2: list[Pose] = []
    turtle_system.client.create_subscription(Pose, 'turtle2/pose', poses2.append, TURTLE_TOPIC_QOS)
    assert turtle_system.spin_until(lambda: second.ready)
    square = turtle_system.start(DrawShape, 'draw_square', DrawShape.Request(size=2.0))
    go_to = turtle_system.start(GoTo, '/turtle_traj2/go_to', GoTo.Request(x=4.0, y=3.0))
    assert turtle_system.spin_until(lambda: square.done() and go_to.done())
    assert square.result().success and go_to.result().success
    assert square.result().final_error < 0.001
    assert math.dist((poses2[-1].x, poses2[-1].y), (4.0, 3.0)) < 0.01
    # Each ran on its own turtle: the first ended where it started, the second where it was sent.
    assert (
        math.dist(
            (turtle_system.poses[-1].x, turtle_system.poses[-1].y),
            (square.result().final_x, square.result().final_y),
        )
        < 1e-6
    )


def test_a_request_that_came_before_the_first_step_is_judged_on_the_first_pose(
        rclpy_context, tmp_path):
    """`turtle-traj up` serves from its first spin: a command sent as it said it serves can be
    waiting before simulated time has begun. It is served after the first step, on the pose
    that step published, not refused as 'no pose (never)'."""
    sim = SimNode(context=rclpy_context, lockstep=True,
                  parameter_overrides=[Parameter('output_dir', value=str(tmp_path))])
    node = TrajectoryNode(context=rclpy_context, parameter_overrides=[SIM_TIME])
    client = Node('early_client', context=rclpy_context, parameter_overrides=[SIM_TIME],
                  start_parameter_services=False)
    executor = LockstepExecutor(sim, context=rclpy_context)
    for each in (sim, node, client):
        executor.add_node(each)
    move = client.create_client(Move, '/turtle_traj/move')
    try:
        deadline = time.monotonic() + 30.0  # discovery runs on the middleware's threads
        while not (move.service_is_ready() and client.count_subscribers('/turtle1/pose')
                   and client.count_subscribers('/turtle1/cmd_vel')):
            assert time.monotonic() < deadline, 'the nodes never discovered each other'
            time.sleep(0.01)
        time.sleep(0.2)  # each matched the others' endpoints too
        assert executor.steps == 0
        moved = move.call_async(Move.Request(distance=0.5))
        time.sleep(0.2)  # the request waits for the executor
        assert spin_until(executor, moved.done, timeout_s=30.0)
        assert moved.result().success, moved.result().message
        assert moved.result().final_x == pytest.approx(SPAWN_XY_M + 0.5, abs=1e-3)
    finally:
        executor.shutdown()
        for each in (client, node, sim):
            each.destroy_node()


def test_nodes_on_simulated_time_tick_in_the_order_they_were_added_after_the_first_step(
        rclpy_context, tmp_path):
    """The same callbacks in the same order: each step after the first (at which the executor
    takes the nodes in), the timers of the nodes on simulated time fire in the order their nodes
    joined the executor (not in the order of a set, which changes from run to run), and a node
    that joins later reads the simulated time at once."""
    sim = SimNode(context=rclpy_context, lockstep=True,
                  parameter_overrides=[Parameter('output_dir', value=str(tmp_path))])
    names = ['ticker_d', 'ticker_a', 'ticker_f', 'ticker_b', 'ticker_e', 'ticker_c']
    fired: list[tuple[float, str]] = []
    nodes = [Node(name, context=rclpy_context, parameter_overrides=[SIM_TIME],
                  start_parameter_services=False) for name in names]
    for node in nodes:
        node.create_timer(STEP_S, lambda node=node: fired.append(
            (node.get_clock().now().nanoseconds * 1e-9, node.get_name())))
    executor = LockstepExecutor(sim, context=rclpy_context)
    try:
        for node in (sim, *nodes):
            executor.add_node(node)
        while executor.steps < 40:
            executor.spin_once(0.1)
        steps = sorted({stamp for stamp, _ in fired})[1:]
        assert len(steps) >= 30
        for stamp in steps:
            assert [name for at, name in fired if at == stamp] == names, f'at {stamp:.3f} s'
        late = Node('ticker_late', context=rclpy_context, parameter_overrides=[SIM_TIME],
                    start_parameter_services=False)
        nodes.append(late)
        executor.add_node(late)
        assert late.get_clock().now().nanoseconds == pytest.approx(sim.time_s * 1e9, abs=1)
    finally:
        executor.shutdown()
        for node in (*nodes, sim):
            node.destroy_node()

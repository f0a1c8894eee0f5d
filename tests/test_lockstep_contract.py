"""What lock-step relies on of rclpy's experimental EventsExecutor, pinned to the rclpy we ship.

turtle_traj.rosutils.lockstep steps the simulator after `spin_until_future_complete(Future(), 0)`
returned, taking that to mean: every callback that was ready ran, and so did every callback
those made ready in turn (a message published to a subscriber of this process, a timer whose
simulated time came). If an rclpy upgrade changes that, these tests say so before the demo
drifts.
"""

import re
from importlib.metadata import version
from pathlib import Path

import pytest
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.task import Future
from rclpy.time import Time
from rclpy.time_source import TimeSource
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Trigger
from turtlesim.msg import Color

from turtle_traj.node.async_service import create_async_service

ROOT = Path(__file__).resolve().parents[1]


def _drain(executor) -> None:
    executor.spin_until_future_complete(Future(), 0.0)


@pytest.fixture
def events(rclpy_context):
    executor = EventsExecutor(context=rclpy_context)
    nodes = []

    def add(name: str, **kwargs) -> Node:
        node = Node(name, context=rclpy_context, **kwargs)
        nodes.append(node)
        executor.add_node(node)
        return node
    try:
        yield executor, add
    finally:
        executor.shutdown()
        for node in nodes:
            node.destroy_node()


def test_the_installed_rclpy_is_the_pinned_one():
    pinned = re.search(r'"ros-jazzy-rclpy\[fastrtps\]==([\d.]+)"',
                       (ROOT / 'pyproject.toml').read_text())
    assert pinned is not None, 'pyproject.toml must pin ros-jazzy-rclpy'
    assert version('ros-jazzy-rclpy') == pinned.group(1)


def test_one_drain_runs_a_chain_of_messages_published_in_callbacks(events):
    executor, add = events
    ping, pong = add('ping'), add('pong')
    heard = []
    to_pong = ping.create_publisher(Color, 'ping', 10)
    to_ping = pong.create_publisher(Color, 'pong', 10)

    def on_ping(msg):
        heard.append(('ping', msg.r))
        if msg.r < 6:
            to_ping.publish(Color(r=msg.r + 1))

    def on_pong(msg):
        heard.append(('pong', msg.r))
        to_pong.publish(Color(r=msg.r + 1))
    pong.create_subscription(Color, 'ping', on_ping, 10)
    ping.create_subscription(Color, 'pong', on_pong, 10)
    _drain(executor)  # the executor takes the new entities on
    to_pong.publish(Color(r=0))
    _drain(executor)
    assert heard == [('ping', 0), ('pong', 1), ('ping', 2), ('pong', 3), ('ping', 4),
                     ('pong', 5), ('ping', 6)]
    _drain(executor)
    assert len(heard) == 7  # nothing was left over for a later pass


def test_a_sim_time_timer_fires_in_the_drain_after_its_clock_is_set(events):
    executor, add = events
    node = add('timed', parameter_overrides=[Parameter('use_sim_time', value=True)])
    for subscription in list(node.subscriptions):  # as lockstep does: no /clock needed
        if subscription.topic_name == '/clock':
            node.destroy_subscription(subscription)
    driver = TimeSource()
    driver.ros_time_is_active = True
    driver.attach_clock(node.get_clock())
    fired = []
    node.create_timer(0.016, lambda: fired.append(node.get_clock().now().nanoseconds))
    _drain(executor)
    for step in range(1, 6):
        clock = Clock()
        clock.clock = Time(nanoseconds=step * 16_000_000).to_msg()
        driver.clock_callback(clock)
        _drain(executor)
        assert fired == [n * 16_000_000 for n in range(1, step + 1)]


@pytest.mark.parametrize('executor_kind', ['events', 'single-threaded'])
def test_a_coroutine_service_answers_when_it_returns(rclpy_context, executor_kind):
    from rclpy.executors import SingleThreadedExecutor

    executor = (EventsExecutor(context=rclpy_context) if executor_kind == 'events'
                else SingleThreadedExecutor(context=rclpy_context))
    server = Node('server', context=rclpy_context)
    caller = Node('caller', context=rclpy_context)
    release = Future()

    async def handler(request, response):
        response.message = await release
        response.success = True
        return response
    create_async_service(server, Trigger, 'held', handler)
    client = caller.create_client(Trigger, 'held')
    for node in (server, caller):
        executor.add_node(node)
    try:
        assert client.wait_for_service(timeout_sec=5.0)
        answer = client.call_async(Trigger.Request())
        for _ in range(50):
            executor.spin_once(timeout_sec=0.01)
        assert not answer.done()  # the handler is still awaiting
        release.set_result('released')
        executor.spin_until_future_complete(answer, timeout_sec=5.0)
        assert answer.done() and answer.result().message == 'released'
    finally:
        executor.shutdown()
        server.destroy_node()
        caller.destroy_node()


def test_a_spin_with_a_task_awaiting_sleeps_instead_of_spinning(rclpy_context):
    """runtime.run_nodes spins with spin_until_future_complete(Future(), timeout): while a
    coroutine service handler awaits (a trajectory running), the process must stay idle."""
    import os
    import time

    executor = EventsExecutor(context=rclpy_context)
    server = Node('server', context=rclpy_context)
    release = Future()

    async def handler(request, response):
        await release
        return response
    create_async_service(server, Trigger, 'held', handler)
    client = server.create_client(Trigger, 'held')
    executor.add_node(server)
    try:
        assert client.wait_for_service(timeout_sec=5.0)
        client.call_async(Trigger.Request())
        executor.spin_until_future_complete(Future(), timeout_sec=0.2)  # the handler awaits
        used, start = os.times(), time.monotonic()
        while time.monotonic() - start < 1.0:
            executor.spin_until_future_complete(Future(), timeout_sec=0.1)
        now = os.times()
        cpu_s = (now.user - used.user) + (now.system - used.system)
        assert cpu_s < 0.3, f'{cpu_s:.2f} s of CPU in 1 s: the executor spins'
    finally:
        release.set_result(None)
        executor.shutdown()
        server.destroy_node()


@pytest.mark.filterwarnings('ignore:coroutine .* was never awaited:RuntimeWarning')
def test_the_events_executor_of_this_rclpy_cannot_answer_a_coroutine_service(rclpy_context):
    """Why node.async_service exists (ros2/rclpy#1473): a plain service with a coroutine
    handler gets no answer on this rclpy's EventsExecutor. When this fails, the pinned rclpy
    answers it itself: create_async_service can go."""
    executor = EventsExecutor(context=rclpy_context)
    server = Node('plain_server', context=rclpy_context)

    async def handler(request, response):
        response.success = True
        return response
    server.create_service(Trigger, 'plain', handler)
    client = server.create_client(Trigger, 'plain')
    executor.add_node(server)
    try:
        assert client.wait_for_service(timeout_sec=5.0)
        answer = client.call_async(Trigger.Request())
        try:
            executor.spin_until_future_complete(answer, timeout_sec=2.0)
        except TypeError:
            pass  # rclpy's send_response refuses the coroutine object, out of spin
        assert not answer.done()
    finally:
        executor.shutdown()
        server.destroy_node()

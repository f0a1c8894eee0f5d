"""The control tick steers from the newest pose: it first reads every pose waiting at the node.

An executor hands a subscription's messages over one at a time, between its other callbacks. A
starved one (rclpy 7.1.6's MultiThreadedExecutor while a handler awaits, ros2/rclpy#1452)
dispatched fewer poses a second than turtlesim publishes, and the node steered from poses up to
0.7 s old: the MultiThreadedExecutor test then aborted 'no progress along the path for 3 s' in
every run with a thread holding the GIL in 10 ms slices (bench/gil_starved_bench.py).
"""

from __future__ import annotations

import time

import pytest

POSES = 30


def test_the_control_tick_reads_every_waiting_pose_in_order(rclpy_context):
    from rclpy.node import Node
    from turtlesim.msg import Pose

    from turtle_traj.node.trajectory_node import TrajectoryNode
    from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS

    node = TrajectoryNode(context=rclpy_context, namespace='/waiting')
    sim = Node('publishes_poses', context=rclpy_context, namespace='/waiting')
    try:
        publisher = sim.create_publisher(Pose, 'turtle1/pose', TURTLE_TOPIC_QOS)
        began = time.monotonic()
        while publisher.get_subscription_count() < 1:  # the node's reader is matched
            assert time.monotonic() - began < 10.0, 'the node never subscribed to the poses'
            time.sleep(0.01)
        for step in range(POSES):  # nothing spins: they wait in the node's reader
            publisher.publish(Pose(x=1.0 + 0.01 * step, y=2.0, linear_velocity=0.625))
        time.sleep(0.2)  # delivered within the process
        period_ns = round(1e9 / node.get_parameter('control_rate').value)
        (tick,) = [timer.callback for timer in node.timers if timer.timer_period_ns == period_ns]
        assert node.pose is None
        tick()
        assert node.pose is not None, 'the tick read no pose'
        assert node.pose.x == pytest.approx(1.0 + 0.01 * (POSES - 1))  # the newest, read last
    finally:
        sim.destroy_node()
        node.destroy_node()

"""The fleet as programs: a coordinator of its own, killed mid-drawing."""

import signal
import subprocess
import sys
import time

import pytest
import rclpy
from rclpy.action import ActionClient
from turtle_traj_interfaces.action import FleetDraw
from turtle_traj_interfaces.msg import Drawing
from turtlesim.msg import Pose

from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.rosutils.runtime import events_executor, spin_until
from turtle_traj.testing.processes import Program, program

COMMAND_TIMEOUT_S = 1.0  # turtlesim's


@pytest.mark.system
def test_the_turtles_of_a_coordinator_that_dies_stop_within_the_command_timeout(rclpy_context):
    """The coordinator (a program of its own) is killed while its turtles draw a square slowly
    (a piece of 1 m takes 5 s): each turtle's node ends its run when the coordinator's lease on
    it lapses, and the turtles stand within turtlesim's command timeout."""
    with program('turtle_traj', '--with-sim', '--turtles', '2') as fleet:
        coordinator = Program([sys.executable, '-m', 'turtle_traj.fleet', '--ros-args', '-r',
                               '__node:=fleet_b'], stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True)
        coordinator.start_reading()
        node = rclpy.create_node('fleet_test_client', context=rclpy_context)
        client = ActionClient(node, FleetDraw, '/fleet_b/draw')
        executor = events_executor(context=rclpy_context)
        executor.add_node(node)
        try:
            poses: dict[str, Pose] = {}
            for name in ('turtle1', 'turtle2'):
                node.create_subscription(Pose, f'/{name}/pose',
                                         lambda pose, name=name: poses.__setitem__(name, pose),
                                         TURTLE_TOPIC_QOS)
            assert spin_until(executor, client.server_is_ready, timeout_s=30.0), \
                coordinator.said()
            client.send_goal_async(FleetDraw.Goal(
                drawing=Drawing(trajectory='square', size=2.0, linear_speed=0.2),
                turtles=['turtle1', 'turtle2']))

            def drawing() -> bool:
                return any(abs(pose.linear_velocity) > 0.1 for pose in poses.values())
            assert spin_until(executor, drawing, timeout_s=30.0), coordinator.said()
            spin_until(executor, lambda: False, timeout_s=0.3)  # well into a piece
            coordinator.send_signal(signal.SIGKILL)
            killed = time.monotonic()

            def standing() -> bool:
                return all(pose.linear_velocity == 0.0 and pose.angular_velocity == 0.0
                           for pose in poses.values())
            assert spin_until(executor, standing, timeout_s=10.0)
            assert time.monotonic() - killed < COMMAND_TIMEOUT_S, fleet.said()
            spin_until(executor, lambda: False, timeout_s=1.5)  # and they stay
            assert standing()
        finally:
            client.destroy()
            coordinator.kill()
            coordinator.wait_and_read()
            executor.shutdown()
            node.destroy_node()

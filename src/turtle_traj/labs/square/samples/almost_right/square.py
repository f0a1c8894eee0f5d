"""Moves the turtle in a square of 2 m sides, open loop: drive 2 s at 1 m/s, turn 1 s at
pi/2 rad/s, four times; then on 0.6 m too far."""

import math
import time

import rclpy
from geometry_msgs.msg import Twist


def move(publisher, linear, angular, seconds):
    """Publish the command at 20 Hz for `seconds`, then a stop, which leaves on time: the last
    sleep ends at the deadline, not up to a period past it."""
    command = Twist()
    command.linear.x = linear
    command.angular.z = angular
    end = time.monotonic() + seconds
    while (left := end - time.monotonic()) > 0:
        publisher.publish(command)
        time.sleep(min(0.05, left))
    publisher.publish(Twist())
    time.sleep(0.3)


def main():
    rclpy.init()
    node = rclpy.create_node('square')
    publisher = node.create_publisher(Twist, '/turtle1/cmd_vel', 10)
    while publisher.get_subscription_count() == 0:  # until the simulator has found us
        time.sleep(0.05)
    for _ in range(4):
        move(publisher, 1.0, 0.0, 2.0)
        move(publisher, 0.0, math.pi / 2, 1.0)
    move(publisher, 1.0, 0.0, 0.6)
    node.destroy_node()
    rclpy.shutdown()


if __name__ == '__main__':
    main()

"""The letter L mirrored: its foot points left."""

import math
import time

import rclpy
from geometry_msgs.msg import Twist

FOOT = -1.0  # m, to the left


def move(publisher, linear, angular, seconds):
    command = Twist()
    command.linear.x, command.angular.z = linear, angular
    end = time.monotonic() + seconds
    while (left := end - time.monotonic()) > 0:
        publisher.publish(command)
        time.sleep(min(0.05, left))
    publisher.publish(Twist())
    time.sleep(0.3)


def main():
    rclpy.init()
    node = rclpy.create_node('letter')
    publisher = node.create_publisher(Twist, '/turtle1/cmd_vel', 10)
    while publisher.get_subscription_count() == 0:
        time.sleep(0.05)
    move(publisher, 0.0, math.pi / 2, 1.0)  # face up
    move(publisher, 1.0, 0.0, 2.0)  # the bar, upwards
    move(publisher, 0.0, math.pi / 2, 2.0)  # face down
    move(publisher, 1.0, 0.0, 2.0)  # back down the bar
    move(publisher, 0.0, math.copysign(math.pi / 2, FOOT), 1.0)  # face along the foot
    move(publisher, 1.0, 0.0, abs(FOOT))
    rclpy.shutdown()


if __name__ == '__main__':
    main()

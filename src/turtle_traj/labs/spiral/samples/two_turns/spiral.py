"""The right sample's spiral, stopped after two of its three turns."""

import math
import time

import rclpy
from geometry_msgs.msg import Twist

RADIUS, TURNS, OMEGA = 2.0, 3.0, 1.0


def main(turns=TURNS):
    rclpy.init()
    node = rclpy.create_node('spiral')
    publisher = node.create_publisher(Twist, '/turtle1/cmd_vel', 10)
    while publisher.get_subscription_count() == 0:
        time.sleep(0.05)
    pitch = RADIUS / (2 * math.pi * TURNS)
    start = time.monotonic()
    end = start + 2 * math.pi * turns / OMEGA
    command = Twist()
    command.angular.z = OMEGA
    while (left := end - time.monotonic()) > 0:
        theta = OMEGA * (time.monotonic() - start + 0.01)  # the middle of the next 20 ms
        command.linear.x = pitch * OMEGA * math.sqrt(1 + theta * theta)
        publisher.publish(command)
        time.sleep(min(0.02, left))
    publisher.publish(Twist())
    time.sleep(0.3)
    rclpy.shutdown()


if __name__ == '__main__':
    main(turns=2.0)

"""Crashes before it moves: a misspelt method."""

import rclpy
from geometry_msgs.msg import Twist


def main():
    rclpy.init()
    node = rclpy.create_node('square')
    publisher = node.create_publisher(Twist, '/turtle1/cmd_vel', 10)
    publisher.publsh(Twist())


if __name__ == '__main__':
    main()

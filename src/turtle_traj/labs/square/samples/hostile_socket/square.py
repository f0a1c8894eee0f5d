"""Tries the network: a TCP connection to a port on the grader's machine (127.0.0.1:47815,
where the suite listens) and a name look-up; says what happened; then draws the right
square."""

import math
import socket
import time

import rclpy
from geometry_msgs.msg import Twist

PORT = 47815


def reach_out():
    try:
        with socket.create_connection(('127.0.0.1', PORT), timeout=2.0) as connection:
            connection.sendall(b'let me out')
            print('socket: connected')
    except OSError as error:
        print(f'socket: no connection to 127.0.0.1:{PORT}: {error}')
    try:
        print('socket: resolved', socket.gethostbyname('pypi.org'))
    except OSError as error:
        print(f'socket: no name look-up: {error}')


def main():
    reach_out()
    rclpy.init()
    node = rclpy.create_node('square')
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

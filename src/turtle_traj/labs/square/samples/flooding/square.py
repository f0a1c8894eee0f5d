"""The closed-loop square of right_package, while a process of its own floods a topic with
64 kB messages as fast as it can, at the lowest priority (the flood takes whatever CPU its run
is allowed and the drawing leaves)."""

import math
import os
import subprocess
import sys

import rclpy
from geometry_msgs.msg import Twist
from rclpy.node import Node
from std_msgs.msg import String
from turtlesim.msg import Pose

SIDE = 2.0


class Square(Node):
    def __init__(self):
        super().__init__('square')
        self.cmd_vel = self.create_publisher(Twist, '/turtle1/cmd_vel', 10)
        self.create_subscription(Pose, '/turtle1/pose', self.on_pose, 10)
        self.pose = None
        self.leg = 0  # even legs drive, odd legs turn
        self.start = None
        self.done = False
        self.create_timer(0.02, self.tick)

    def on_pose(self, pose):
        self.pose = pose

    def tick(self):
        if self.pose is None or self.done:
            return
        if self.start is None:
            self.start = (self.pose.x, self.pose.y, self.pose.theta)
        command = Twist()
        x0, y0, heading = self.start
        if self.leg % 2 == 0:
            left = SIDE - math.hypot(self.pose.x - x0, self.pose.y - y0)
            command.linear.x = min(1.0, 4.0 * left)
            finished = left < 0.005
        else:
            error = math.remainder(heading + math.pi / 2 - self.pose.theta, math.tau)
            command.angular.z = max(-1.5, min(1.5, 6.0 * error))
            finished = abs(error) < 0.002
        if finished:
            command = Twist()
            self.leg += 1
            self.start = None
            self.done = self.leg == 8
        self.cmd_vel.publish(command)


def flood():
    rclpy.init()
    publisher = Node('flood').create_publisher(String, '/flood', 10)
    message = String(data='x' * 65536)
    while rclpy.ok():
        publisher.publish(message)


def main():
    if sys.argv[1:] == ['--flood']:
        flood()
        return
    # at the lowest priority from its first instruction: its start-up (importing rclpy, a
    # second of CPU) counts against the run's share too
    flooder = subprocess.Popen([sys.executable, __file__, '--flood'],
                               preexec_fn=lambda: os.nice(19))
    try:
        rclpy.init()
        node = Square()
        while rclpy.ok() and not node.done:
            rclpy.spin_once(node, timeout_sec=0.1)
        node.destroy_node()
        rclpy.shutdown()
    finally:
        flooder.kill()


if __name__ == '__main__':
    main()

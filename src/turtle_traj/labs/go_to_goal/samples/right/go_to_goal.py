"""Drives the turtle to the goal given as arguments (x y), closed loop on /turtle1/pose: turn
towards it while driving, slow down as it comes near, stop within 1 cm."""

import math
import sys

import rclpy
from geometry_msgs.msg import Twist
from rclpy.node import Node
from turtlesim.msg import Pose


class GoToGoal(Node):
    def __init__(self, x, y):
        super().__init__('go_to_goal')
        self.goal = (x, y)
        self.done = False
        self.cmd_vel = self.create_publisher(Twist, '/turtle1/cmd_vel', 10)
        self.create_subscription(Pose, '/turtle1/pose', self.on_pose, 10)

    def on_pose(self, pose):
        dx, dy = self.goal[0] - pose.x, self.goal[1] - pose.y
        distance = math.hypot(dx, dy)
        command = Twist()
        if distance < 0.01:
            self.done = True
        else:
            error = math.remainder(math.atan2(dy, dx) - pose.theta, math.tau)
            command.angular.z = max(-2.0, min(2.0, 4.0 * error))
            command.linear.x = min(1.5, 1.5 * distance) * max(0.0, math.cos(error))
        self.cmd_vel.publish(command)


def main():
    rclpy.init()
    node = GoToGoal(float(sys.argv[1]), float(sys.argv[2]))
    while rclpy.ok() and not node.done:
        rclpy.spin_once(node, timeout_sec=0.1)
    rclpy.shutdown()


if __name__ == '__main__':
    main()

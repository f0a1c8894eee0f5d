"""A square, then the turtle is left turning: the last command is never taken back."""

import math

import rclpy
from geometry_msgs.msg import Twist
from rclpy.node import Node

# (linear m/s, angular rad/s, s): four sides and turns, then a turn that never ends
PERIOD = 0.05  # s between commands
PLAN = [(1.0, 0.0, 2.0), (0.0, math.pi / 2, 1.0)] * 4 + [(0.0, 1.0, math.inf)]


class Square(Node):
    def __init__(self):
        super().__init__('square')
        self.publisher = self.create_publisher(Twist, '/turtle1/cmd_vel', 10)
        self.leg_started = None  # when the current move began (s, the node's clock)
        self.create_timer(PERIOD, self.tick)

    def tick(self):
        if self.publisher.get_subscription_count() == 0:  # the simulator has not found us
            return
        now = self.get_clock().now().nanoseconds * 1e-9
        if self.leg_started is None:
            self.leg_started = now
        if now - self.leg_started >= PLAN[0][2] - PERIOD / 2:  # at the tick nearest its end
            PLAN.pop(0)
            self.leg_started = now
        linear, angular, _seconds = PLAN[0]
        command = Twist()
        command.linear.x, command.angular.z = linear, angular
        self.publisher.publish(command)


def main():
    rclpy.init()
    rclpy.spin(Square())


if __name__ == '__main__':
    main()

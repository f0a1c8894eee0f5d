"""The DDS traffic floor: what turtlesim's message traffic alone costs an rclpy program.

`python bench/traffic_floor.py stand-in` is a turtlesim without physics, drawing or services:
it publishes /turtle1/pose and /turtle1/color_sensor every 16 ms and takes /turtle1/cmd_vel,
on the EventsExecutor our simulator uses. `python bench/traffic_floor.py driver` subscribes
to the pose and publishes cmd_vel every 16 ms, as our trajectory node does while it drives.
`python bench/traffic_floor.py listener` only subscribes to the pose, as any node that knows
where the turtle is must, idle. bench/sim_bench.py measures the stand-in and our simulator
under the same driver: the difference is what our simulator itself costs; bench/speed_bench.py
measures the driver and the listener beside our simulator: what any trajectory node with this
traffic costs at the least, driving and idle.
"""

import sys

import rclpy
from geometry_msgs.msg import Twist
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from turtlesim.msg import Color, Pose

PERIOD_S = 0.016


class StandIn(Node):
    def __init__(self) -> None:
        super().__init__('turtlesim')
        self._pose = self.create_publisher(Pose, 'turtle1/pose', 1)
        self._color = self.create_publisher(Color, 'turtle1/color_sensor', 1)
        self.create_subscription(Twist, 'turtle1/cmd_vel', self._on_command, 1)
        self.create_timer(PERIOD_S, self._step)
        self._speed = 0.0
        self._x = 5.544445

    def _on_command(self, command: Twist) -> None:
        self._speed = command.linear.x

    def _step(self) -> None:
        self._x += self._speed * PERIOD_S
        self._pose.publish(Pose(x=self._x, y=5.544445, linear_velocity=self._speed))
        self._color.publish(Color(r=69, g=86, b=255))


class Driver(Node):
    def __init__(self, driving: bool = True) -> None:
        super().__init__('traffic_driver')
        self.create_subscription(Pose, 'turtle1/pose', lambda _pose: None, 1)
        if driving:
            command = self.create_publisher(Twist, 'turtle1/cmd_vel', 1)
            self.create_timer(PERIOD_S, lambda: command.publish(Twist()))


def main() -> None:
    role = sys.argv[1] if len(sys.argv) > 1 else 'driver'
    if role not in ('stand-in', 'driver', 'listener'):
        sys.exit(f'usage: traffic_floor.py [stand-in | driver | listener], not {role!r}')
    rclpy.init()
    executor = EventsExecutor()
    executor.add_node(StandIn() if role == 'stand-in' else Driver(driving=role == 'driver'))
    try:
        while rclpy.ok():  # EventsExecutor.spin() busy-waits: a whole core
            executor.spin_once(timeout_sec=0.25)
    except KeyboardInterrupt:
        pass
    finally:
        executor.shutdown()
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()

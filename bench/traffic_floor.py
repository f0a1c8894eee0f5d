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

`lockstep_floor_ms(turtles)` is the same traffic in lock-step, for a fleet: one program, a
stand-in simulator stepped by our `LockstepExecutor` publishing every turtle's pose, and one
driver node per turtle on simulated time that takes its pose and publishes cmd_vel each step.
bench/speed_bench.py --step-cost prints it beside what a step of ours costs.
"""

import sys
import time

import rclpy
from geometry_msgs.msg import Twist
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from turtlesim.msg import Color, Pose

PERIOD_S = 0.016
MATCH_TIMEOUT_S = 60.0  # discovery in one process: milliseconds when quiet, seconds when busy


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


class StandInFleet(Node):
    """A simulator for lock-step without physics, drawing or services: each step publishes
    every turtle's pose and takes its last cmd_vel."""

    def __init__(self, turtles: int) -> None:
        super().__init__('turtlesim')
        self.poses = [self.create_publisher(Pose, f'turtle{index + 1}/pose', 1)
                      for index in range(turtles)]
        self._speeds = [0.0] * turtles
        for index in range(turtles):
            self.create_subscription(Twist, f'turtle{index + 1}/cmd_vel',
                                     lambda command, index=index: self._on_command(index,
                                                                                   command), 1)
        self._time_s = 0.0

    def _on_command(self, index: int, command: Twist) -> None:
        self._speeds[index] = command.linear.x

    def step(self) -> None:
        self._time_s += PERIOD_S
        for publisher, speed in zip(self.poses, self._speeds, strict=True):
            publisher.publish(Pose(linear_velocity=speed))

    def clock_message(self):
        from turtle_traj.rosutils.lockstep import clock_message
        return clock_message(self._time_s)

    @property
    def time_s(self) -> float:
        return self._time_s


class StepDriver(Node):
    """One turtle's driver on simulated time: its pose taken, a cmd_vel published each step."""

    def __init__(self, number: int) -> None:
        super().__init__(f'traffic_driver{number}',
                         parameter_overrides=[Parameter('use_sim_time', value=True)])
        self.create_subscription(Pose, f'turtle{number}/pose', lambda _pose: None, 1)
        command = self.create_publisher(Twist, f'turtle{number}/cmd_vel', 1)
        self.create_timer(PERIOD_S, lambda: command.publish(Twist()))


def lockstep_floor_ms(turtles: int, steps: int = 500) -> float:
    """Wall time per lock-step step of `turtles` turtles' traffic and nothing else, ms (in
    this process; rclpy initialised)."""
    from turtle_traj.rosutils.lockstep import LockstepExecutor

    simulator = StandInFleet(turtles)
    executor = LockstepExecutor(simulator)
    nodes = [simulator, *(StepDriver(number) for number in range(1, turtles + 1))]
    try:
        for node in nodes:
            executor.add_node(node)
        matched_by = time.monotonic() + MATCH_TIMEOUT_S
        while not all(publisher.get_subscription_count() for publisher in simulator.poses):
            if time.monotonic() > matched_by:
                raise RuntimeError(f'the drivers did not match within {MATCH_TIMEOUT_S:g} s')
            executor.spin_once(0.01)  # every driver matched (stepping meanwhile)
        for _ in range(steps // 5):  # and settled
            executor.spin_once(0.01)
        first, began = executor.steps, time.perf_counter()
        while executor.steps - first < steps:
            executor.spin_once(0.01)
        return 1e3 * (time.perf_counter() - began) / (executor.steps - first)
    finally:
        executor.shutdown()
        for node in nodes:
            node.destroy_node()


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

"""Accuracy and speed of every trajectory, closed loop against the classic open-loop method.

Runs our simulator and the trajectory node in one process on lock-step simulated time
at default speeds, and prints one table. Run: .venv/bin/python bench/accuracy_bench.py
"""

from __future__ import annotations

import math
import os
import tempfile

os.environ.setdefault('ROS_DOMAIN_ID', '78')
os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
os.environ.setdefault('ROS_LOG_DIR', tempfile.mkdtemp(prefix='turtle_traj_bench_logs_'))

import numpy as np  # noqa: E402
import rclpy  # noqa: E402
from geometry_msgs.msg import Twist  # noqa: E402
from rclpy.node import Node  # noqa: E402
from std_srvs.srv import Trigger  # noqa: E402
from turtle_traj_interfaces.srv import DrawShape, GoTo, Move  # noqa: E402

from turtle_traj import planning  # noqa: E402
from turtle_traj.geometry.path import Pose2D, distance_to_polyline  # noqa: E402
from turtle_traj.system import InProcessSystem  # noqa: E402
from turtle_traj.wire import TURTLE_TOPIC_QOS  # noqa: E402

LINEAR, ANGULAR = 1.0, 2.0  # the node's default top speeds


class OpenLoopDriver(Node):
    """The classic script: publish a fixed velocity for a computed time, step by step."""

    def __init__(self, schedule: list[tuple[float, float, float]], **kwargs) -> None:
        super().__init__('open_loop_driver', **kwargs)
        self.schedule = list(schedule)
        self.publisher = self.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
        self.step_started = None  # set on the first tick, once simulated time is known
        self.create_timer(0.016, self.on_timer)

    @property
    def done(self) -> bool:
        return not self.schedule

    def on_timer(self) -> None:
        twist = Twist()
        now = self.get_clock().now()
        if self.step_started is None:
            self.step_started = now
        while self.schedule and (now - self.step_started).nanoseconds * 1e-9 >= \
                self.schedule[0][2]:
            self.schedule.pop(0)
            self.step_started = now
        if self.schedule:
            twist.linear.x, twist.angular.z, _ = self.schedule[0]
        self.publisher.publish(twist)


def open_loop_schedule(sides: int, side: float) -> list[tuple[float, float, float]]:
    turn = 2 * math.pi / sides
    steps = []
    for _ in range(sides):
        steps += [(LINEAR, 0.0, side / LINEAR), (0.0, ANGULAR, turn / ANGULAR)]
    return steps[:-1]


def reset(system: InProcessSystem) -> Pose2D:
    system.call(Trigger, 'reset')
    system.spin_sim_seconds(0.2)
    pose = system.poses[-1]
    return Pose2D(pose.x, pose.y, pose.theta)


def drive_open_loop(system: InProcessSystem, schedule) -> tuple[np.ndarray, float]:
    driver = OpenLoopDriver(schedule, context=system.client.context, parameter_overrides=[
        rclpy.parameter.Parameter('use_sim_time', value=True)])
    system.executor.add_node(driver)
    system.poses.clear()
    start = system.sim.world.time_s
    try:
        system.spin_until(lambda: driver.done, timeout_s=120.0)
        system.spin_sim_seconds(0.1)
    finally:
        system.executor.remove_node(driver)
        driver.destroy_node()
    return np.array([(p.x, p.y) for p in system.poses]), system.sim.world.time_s - start


def main() -> None:
    rclpy.init()
    system = InProcessSystem(output_dir=tempfile.mkdtemp())
    defaults = system.node.settings.defaults
    arena = system.node.settings.arena
    rows = []
    try:
        cases = [
            ('square', DrawShape, 'draw_square', DrawShape.Request(size=2.0), 4),
            ('triangle', DrawShape, 'draw_triangle', DrawShape.Request(size=2.5), 3),
            ('hexagon', DrawShape, 'draw_hexagon', DrawShape.Request(size=1.5), 6),
            ('polygon', DrawShape, 'draw_polygon', DrawShape.Request(sides=8, size=1.2), 8),
            ('circle', DrawShape, 'draw_circle', DrawShape.Request(size=1.5, turns=1.0), 0),
            ('spiral', DrawShape, 'draw_spiral',
             DrawShape.Request(size=0.5, growth=0.5, turns=3.0), 0),
            ('sine', DrawShape, 'draw_sine', DrawShape.Request(size=0.5, frequency=0.5,
                                                               length=4.0), 0),
            ('go_to', GoTo, 'go_to', GoTo.Request(x=9.0, y=2.0), 0),
            ('move', Move, 'move', Move.Request(distance=-3.0), 0),
            ('rotate', Move, 'rotate', Move.Request(angle=math.pi), 0),
        ]
        for name, service_type, service, request, sides in cases:
            start = reset(system)
            if service_type is DrawShape:
                fields = planning.ShapeRequest(
                    sides=request.sides, size=request.size, turns=request.turns,
                    growth=request.growth, frequency=request.frequency, length=request.length)
                path = planning.plan_shape(name, fields, start, defaults, arena)
            elif service_type is GoTo:
                path = planning.plan_go_to(start, x=request.x, y=request.y, theta=None,
                                           tolerance=0.0, defaults=defaults, arena=arena)
            elif service == 'move':
                path = planning.plan_move(start, distance=request.distance, arena=arena)
            else:
                path = planning.plan_rotation(start, angle=request.angle)
            response = system.run(service_type, service, request)
            assert response.success, response.message
            bound = path.lower_bound_s(LINEAR, ANGULAR)
            extra = ''
            if name == 'circle':
                center = np.array([start.x, start.y + request.size])
                radii = np.linalg.norm(np.array([(p.x, p.y) for p in system.poses]) - center,
                                       axis=1)
                extra = f'radius error {100 * np.abs(radii / request.size - 1).max():.2f}%'
            rows.append((name, response, bound, extra))

            if sides:
                reset(system)
                poses, elapsed = drive_open_loop(
                    system, open_loop_schedule(sides, request.size))
                vertices = path.points()
                open_dev = distance_to_polyline(poses, vertices).max()
                open_closure = math.dist(poses[-1], (start.x, start.y))
                rows.append((f'  {name} open-loop', (open_dev, open_closure, elapsed), bound,
                             f'closed loop is {open_closure / max(response.final_error, 1e-6):.0f}'
                             'x more exact at closure'))
    finally:
        system.close()
        rclpy.try_shutdown()

    print('turtle_traj accuracy benchmark: our simulator, default speeds '
          f'({LINEAR:g} m/s, {ANGULAR:g} rad/s), simulated time')
    print(f'{"trajectory":22} {"max dev m":>10} {"end err m":>10} {"elapsed s":>10} '
          f'{"bound s":>8} {"ratio":>6}  notes')
    for name, result, bound, extra in rows:
        if isinstance(result, tuple):
            deviation, end_error, elapsed = result
        else:
            deviation, end_error, elapsed = (result.max_deviation, result.final_error,
                                             result.elapsed)
        print(f'{name:22} {deviation:10.4f} {end_error:10.4f} {elapsed:10.2f} {bound:8.2f} '
              f'{elapsed / bound:6.2f}  {extra}')


if __name__ == '__main__':
    main()

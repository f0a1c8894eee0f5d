"""Accuracy and speed of every trajectory, closed loop against the classic open-loop method.

Runs our simulator and the trajectory node in one process on lock-step simulated time, draws
the registry's example of every trajectory (the demo's pictures) and, for the polygons, the
classic open-loop script too, and prints one table. Run: .venv/bin/python bench/accuracy_bench.py
"""

from __future__ import annotations

import math
import tempfile

import numpy as np
import rclpy
from geometry_msgs.msg import Twist
from rclpy.node import Node

from isolation import isolate
from turtle_traj.api.ros_interface import make_request
from turtle_traj.apps.demo import prepare, run_example
from turtle_traj.apps.in_process import InProcessSystem
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.planning.limits import POLYGON_SIDES
from turtle_traj.core.registry import TRAJECTORIES
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.testing.geometry import (
    distance_to_polyline,
    drawn_strokes,
    ink_at,
    pen_up_moves,
    resampled,
)

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


def open_loop_schedule(sides: int, side: float,
                       clockwise: bool) -> list[tuple[float, float, float]]:
    turn = 2 * math.pi / sides
    sign = -1.0 if clockwise else 1.0
    steps = []
    for _ in range(sides):
        steps += [(LINEAR, 0.0, side / LINEAR), (0.0, sign * ANGULAR, turn / ANGULAR)]
    return steps[:-1]


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


def drawing_figures(system: InProcessSystem, plan) -> str:
    """A drawing's accuracy from the recorded poses and the saved canvas: stroke ends missed,
    deviation while the pen is down, ink pixels along the pen-up moves."""
    poses = np.array([(p.x, p.y) for p in system.poses])
    strokes = drawn_strokes(plan.path)
    ends = np.array([end for stroke in strokes for end in (stroke[0], stroke[-1])])
    end_miss = max(np.hypot(*(poses - end).T).min() for end in ends)
    # Pen-down poses: those nearer a stroke than any pen-up move (ties at stroke ends count).
    to_strokes = np.min([distance_to_polyline(poses, stroke) for stroke in strokes], axis=0)
    moves = pen_up_moves(plan.path)
    to_moves = (np.min([distance_to_polyline(poses, move) for move in moves], axis=0)
                if moves else np.full(len(poses), np.inf))
    stroke_deviation = to_strokes[to_strokes <= to_moves].max()
    pen = plan.pen
    travel = np.concatenate([resampled(move, 0.01) for move in moves]) if moves \
        else np.empty((0, 2))
    clear = np.min([distance_to_polyline(travel, stroke) for stroke in strokes], axis=0) > 0.06 \
        if len(travel) else np.zeros(0, bool)
    ink = int(ink_at(system.sim.canvas, travel[clear], (pen.r, pen.g, pen.b)).sum())
    return (f'{len(strokes)} strokes, ends missed by <= {1000 * end_miss:.2f} mm, deviation '
            f'along strokes <= {1000 * stroke_deviation:.2f} mm, pen up '
            f'{plan.path.pen_up_length:.2f} m (given order {plan.pen_up_unordered:.2f} m), ink '
            f'on {ink} of {int(clear.sum())} pen-up points')


def main() -> None:
    isolate('accuracy')
    rclpy.init()
    system = InProcessSystem(output_dir=tempfile.mkdtemp())
    settings = system.node.settings
    rows = []
    try:
        for trajectory in TRAJECTORIES:
            example = trajectory.example
            request = make_request(trajectory, example.given)
            start = Pose2D(*example.start)
            plan = planning.plan(trajectory.name, request, start, settings)
            response = run_example(system, trajectory)
            assert response.success, response.message
            bound = plan.lower_bound_s(settings.control)
            extra = ''
            if trajectory.name == 'circle':
                radius = request.size
                center = np.array([start.x - radius * math.sin(start.theta),
                                   start.y + radius * math.cos(start.theta)])
                radii = np.linalg.norm(np.array([(p.x, p.y) for p in system.poses]) - center,
                                       axis=1)
                extra = f'radius error {100 * np.abs(radii / radius - 1).max():.2f}%'
            if plan.pen is not None:
                extra = drawing_figures(system, plan)
            rows.append((trajectory.name, response, bound, extra))

            sides = POLYGON_SIDES.get(trajectory.name, getattr(request, 'sides', 0))
            if trajectory.service_type.endswith('/DrawShape') and sides >= 3:
                prepare(system, *example.start)
                poses, elapsed = drive_open_loop(
                    system, open_loop_schedule(sides, request.size, request.clockwise))
                open_dev = distance_to_polyline(poses, plan.path.points()).max()
                open_closure = math.dist(poses[-1], (start.x, start.y))
                rows.append((f'  {trajectory.name} open-loop', (open_dev, open_closure, elapsed),
                             bound, f'closed loop closes within '
                             f'{1000 * response.final_error:.3f} mm'))
    finally:
        system.close()
        rclpy.try_shutdown()

    print('turtle_traj accuracy benchmark: our simulator, the demo\'s trajectories at default '
          f'speeds ({LINEAR:g} m/s, {ANGULAR:g} rad/s) unless the example sets one, lock-step '
          'simulated time')
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

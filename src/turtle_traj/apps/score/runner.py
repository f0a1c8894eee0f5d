"""One course driven by one controller, and its figures, measured from the poses.

Every figure is measured here against the plan (the path the node plans for the same request
and start), not taken from the controller: time (simulated, to the path's end), time against
the node's least-time bound, cross-track RMSE and maximum error, the end point's miss, and the
share of the controller's commands the node had to clamp to the limits (none for the exact
follower, which plans within them). A run finishes when the node accepted every end the
controller claimed (`walker.PlanWalker`: the path driven in order, to its end) and, as a Nav2
goal checker judges, the robot came to rest within `GOAL_TOLERANCE_M` of the path's end.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from turtle_traj.api.controllers import choose
from turtle_traj.apps.score.courses import PAPER_INERTIA, Course
from turtle_traj.apps.score.loop import drive
from turtle_traj.core.control.walker import ARRIVED_M
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.projection import NearestOnPolyline
from turtle_traj.core.planning import planner

GOAL_TOLERANCE_M = ARRIVED_M  # the node's own; five times the shipped controllers' tolerance


@dataclass
class Result:
    """One controller on one course."""

    course: str
    robot: str
    controller: str
    success: bool
    message: str
    time_s: float
    bound_s: float
    rmse_mm: float
    max_mm: float
    end_mm: float
    clamped_pct: float
    path: np.ndarray = field(repr=False)  # (N, 2), as driven
    plan: np.ndarray = field(repr=False)  # (M, 2), as planned

    @property
    def ratio(self) -> float:
        return self.time_s / self.bound_s if self.bound_s > 0 else math.nan


def _figures(course: Course, controller: str, success: bool, message: str, time_s: float,
             bound_s: float, driven: np.ndarray, planned: np.ndarray, end: tuple[float, float],
             clamped_pct: float) -> Result:
    distances = NearestOnPolyline(planned).distances(driven)
    missed = math.dist(driven[-1], end)
    if success and missed > GOAL_TOLERANCE_M:
        success, message = False, (f'{message}, but {missed:.3f} m from the path\'s end (the '
                                   f'goal tolerance: {GOAL_TOLERANCE_M:g} m)')
    return Result(course.name, course.robot, controller, success, message, time_s, bound_s,
                  1e3 * float(np.sqrt(np.mean(distances ** 2))), 1e3 * float(distances.max()),
                  1e3 * missed, clamped_pct, driven, planned)


def run_course(course: Course, controller: str, *, work_dir: Path | None = None) -> Result:
    """Drive `course` with the controller of that name (`controllers.catalogue`)."""
    if course.robot == 'base':
        return _on_the_base(course, controller, work_dir or Path('output'))
    plan = planner.plan(course.trajectory, course.request, course.start, course.settings)
    chosen = choose(controller)  # untimed: simulated time waits for the controller
    record = drive(plan, course.start, course.settings, controller=chosen,
                   inertia=PAPER_INERTIA if course.robot == 'inertia' else None)
    success, message = record.run.ending
    outcome = record.run.outcome(record.poses[-1], record.elapsed_s)
    return _figures(course, controller, success, message, outcome.elapsed_s,
                    plan.least_time_s(course.settings.control), record.xy(),
                    plan.drawn_points(), plan.path.end, outcome.clamped_percent)


def _on_the_base(course: Course, controller: str, work_dir: Path) -> Result:
    """Through ROS on the MuJoCo base, lock-step, driven by odometry."""
    import rclpy
    from turtle_traj_interfaces.srv import DrawShape

    from turtle_traj.apps.base_system import BaseSystem
    context = rclpy.Context()
    rclpy.init(context=context)
    try:
        system = BaseSystem(context=context, output_dir=work_dir, controller=controller)
        try:
            response = system.call(DrawShape, f'draw_{course.trajectory}', DrawShape.Request(
                size=float(course.request.size),
                corner_tolerance=float(getattr(course.request, 'corner_tolerance', 0.0))))
            odometry = np.array([sample[1:3] for sample in system.odometry])
            start = Pose2D(*system.odometry[0][1:])
            settings = system.node.settings
            clamped = system.node.last_outcome.clamped_percent
        finally:
            system.close()
    finally:
        rclpy.shutdown(context=context)
    plan = planner.plan(course.trajectory, course.request, start, settings)
    return _figures(course, controller, response.success, response.message, response.elapsed,
                    plan.least_time_s(settings.control), odometry, plan.drawn_points(),
                    plan.path.end, clamped)

"""A Dynamic Window Pure Pursuit reference, written from the paper's description.

Ohnishi & Takahashi (2025), "Dynamic Window Pure Pursuit": pure pursuit picks the curvature
k = 2 sin(alpha) / L towards a look-ahead point L ahead on the path; Regulated Pure Pursuit
slows down on tight curvature and towards the goal; DWPP then keeps each command inside the
dynamic window, the velocities the robot can reach within one control period under its
acceleration limits, choosing on the line omega = k v the fastest point up to the regulated
speed, or, when the line misses the window, the point of the window nearest to it.
Written for the benchmark from that description; none of its code was consulted.
"""

from __future__ import annotations

import math

import numpy as np

from base_loop import Limits
from turtle_traj.core.control.commands import Command
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.turtlesim_contract import STEP_S

LOOKAHEAD_TIME_S = 1.5  # adaptive look-ahead: speed times this, clamped (Nav2 RPP's defaults)
LOOKAHEAD_RANGE_M = (0.3, 0.9)
REGULATED_MIN_RADIUS_M = 0.9  # curvature heuristic: slow down below this radius
MIN_REGULATED_SPEED = 0.25  # m/s: the regulated speed never falls below this (far from goal)
GOAL_TOLERANCE_M = 0.01


class Dwpp:
    """One DWPP run along `points`; call with each pose, it returns the command or None once
    at the goal and standing."""

    def __init__(self, points: np.ndarray, limits: Limits, step_s: float = STEP_S) -> None:
        self.points = self._densify(np.asarray(points, dtype=float))
        self.limits = limits
        self.step_s = step_s
        self.arc = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(self.points, axis=0).T))))
        self.nearest = 0
        self.previous = Command()

    @staticmethod
    def _densify(points: np.ndarray, spacing: float = 0.01) -> np.ndarray:
        parts = []
        for a, b in zip(points[:-1], points[1:], strict=True):
            count = max(1, math.ceil(math.dist(a, b) / spacing))
            parts.append(a + np.outer(np.arange(count) / count, b - a))
        parts.append(points[-1:])
        return np.concatenate(parts)

    def _lookahead(self, pose: Pose2D, distance: float) -> np.ndarray:
        window = self.points[self.nearest:self.nearest + 300]
        gaps = np.hypot(window[:, 0] - pose.x, window[:, 1] - pose.y)
        self.nearest += int(np.argmin(gaps))
        ahead = self.points[self.nearest:]
        beyond = np.nonzero(np.hypot(ahead[:, 0] - pose.x, ahead[:, 1] - pose.y) >= distance)[0]
        return ahead[beyond[0]] if len(beyond) else self.points[-1]

    def __call__(self, pose: Pose2D) -> Command | None:
        limits, previous = self.limits, self.previous
        goal = self.points[-1]
        to_goal = math.dist((pose.x, pose.y), goal)
        remaining = self.arc[-1] - self.arc[self.nearest]
        if to_goal <= GOAL_TOLERANCE_M or (remaining < 0.05 and self._passed(pose)):
            if abs(previous.linear) < 1e-9 and abs(previous.angular) < 1e-9:
                return None
            return self._window(0.0, 0.0, stop=True)
        lookahead = min(max(abs(previous.linear) * LOOKAHEAD_TIME_S, LOOKAHEAD_RANGE_M[0]),
                        LOOKAHEAD_RANGE_M[1])
        target = self._lookahead(pose, lookahead)
        dx, dy = target[0] - pose.x, target[1] - pose.y
        local_y = -math.sin(pose.theta) * dx + math.cos(pose.theta) * dy
        distance = max(math.hypot(dx, dy), 1e-6)
        curvature = 2.0 * local_y / (distance * distance)
        speed = limits.v
        radius = 1.0 / max(abs(curvature), 1e-9)
        if radius < REGULATED_MIN_RADIUS_M:
            speed = max(speed * radius / REGULATED_MIN_RADIUS_M, MIN_REGULATED_SPEED)
        speed = min(speed, math.sqrt(2.0 * limits.a * max(remaining, 0.0)))
        return self._window(speed, curvature)

    def _passed(self, pose: Pose2D) -> bool:
        end, before = self.points[-1], self.points[-2]
        along = (pose.x - end[0]) * (end[0] - before[0]) + (pose.y - end[1]) * (end[1] - before[1])
        return along > 0

    def _window(self, speed: float, curvature: float, stop: bool = False) -> Command:
        """The command in the dynamic window: on omega = k v, fastest up to `speed`; else the
        window's point nearest the line (the faster on a tie)."""
        limits, previous, step = self.limits, self.previous, self.step_s
        v_low = max(previous.linear - limits.a * step, 0.0)
        v_high = min(previous.linear + limits.a * step, limits.v)
        w_low = max(previous.angular - limits.alpha * step, -limits.omega)
        w_high = min(previous.angular + limits.alpha * step, limits.omega)
        if stop:
            command = Command(min(max(0.0, v_low), v_high), min(max(0.0, w_low), w_high))
        else:
            command = self._on_line(speed, curvature, v_low, v_high, w_low, w_high)
        self.previous = command
        return command

    @staticmethod
    def _on_line(speed: float, curvature: float, v_low: float, v_high: float, w_low: float,
                 w_high: float) -> Command:
        low, high = v_low, v_high
        if abs(curvature) > 1e-12:
            bounds = sorted((w_low / curvature, w_high / curvature))
            low, high = max(low, bounds[0]), min(high, bounds[1])
        elif not w_low <= 0.0 <= w_high:
            low, high = 1.0, 0.0  # the line omega = 0 misses the window
        if low <= high:
            v = min(max(speed, low), high)
            return Command(v, curvature * v)
        corners = [(v, w) for v in (v_low, v_high) for w in (w_low, w_high)]
        norm = math.sqrt(1.0 + curvature * curvature)
        v, w = min(corners, key=lambda c: (abs(c[1] - curvature * c[0]) / norm, -c[0]))
        return Command(v, w)

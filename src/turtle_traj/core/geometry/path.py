"""Paths as legs: curves tracked continuously and turns made in place.

Every trajectory is a Path: a polygon is straight curves joined by turns, a circle one sampled
curve, a go-to a turn and a straight curve. One follower (turtle_traj.core.control) drives
them all.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from turtle_traj.core.geometry.angles import wrap_angle, wrap_angles
from turtle_traj.core.geometry.projection import PolylineSegments


@dataclass(frozen=True)
class Pose2D:
    """A planar pose in the turtlesim world frame: metres and radians."""

    x: float
    y: float
    theta: float


@dataclass(frozen=True, eq=False)
class Polyline:
    """A polyline tracked continuously, with no corner sharper than the planner allowed.

    :param points: (N, 2) array, N >= 2, metres.
    :param reverse: driven backwards (the turtle faces away from the direction of travel).
    :param repeat: an endless loop (points[-1] == points[0]); the follower never finishes it.
    :param pen: drawn with the pen down; False: a pen-up move between strokes of a drawing.
    :param speeds: (N,) the speed at each point (m/s) of a motion planned in time, from rest to
        rest with a constant acceleration between points (`planning.min_time`): the follower
        keeps to its clock. None: the follower plans the speed.
    """

    points: np.ndarray
    reverse: bool = False
    repeat: bool = False
    pen: bool = True
    speeds: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.speeds is not None and len(self.speeds) != len(self.points):
            raise ValueError(f'{len(self.speeds)} speeds for {len(self.points)} points')

    @cached_property
    def segments(self) -> PolylineSegments:
        """Its segments as plain floats, for the searches along it (`projection`)."""
        return PolylineSegments(self.points)

    @cached_property
    def segment_lengths(self) -> np.ndarray:
        return np.hypot(*np.diff(self.points, axis=0).T)

    @cached_property
    def cumulative_length(self) -> np.ndarray:
        """Arc length at each point, starting at 0."""
        return np.concatenate(([0.0], np.cumsum(self.segment_lengths)))

    @property
    def length(self) -> float:
        return float(self.cumulative_length[-1])

    @cached_property
    def headings(self) -> np.ndarray:
        """Direction of travel of each segment."""
        delta = np.diff(self.points, axis=0)
        return np.arctan2(delta[:, 1], delta[:, 0])

    @cached_property
    def curvatures(self) -> np.ndarray:
        """Signed curvature around each segment (1/m), from the heading change at its ends; an
        open polyline's end vertices count as straight (a chord's view: turtlesim aims at
        chords)."""
        return self._curvatures(open_ends_turn=False)

    @cached_property
    def tangent_curvatures(self) -> np.ndarray:
        """As `curvatures`, for the curve the vertices sample: at an open end the curve goes
        on turning as at the nearest vertex, as `profile.heading_knots` extrapolates its
        tangent. A sampled arc's end chords get the arc's curvature, not half of it."""
        return self._curvatures(open_ends_turn=True)

    def _curvatures(self, open_ends_turn: bool) -> np.ndarray:
        turn = wrap_angles(np.diff(self.headings))
        mean_length = 0.5 * (self.segment_lengths[:-1] + self.segment_lengths[1:])
        at_vertices = turn / np.maximum(mean_length, 1e-9)
        if not len(at_vertices):  # one segment: straight
            return np.zeros(1)
        if self.repeat:
            closing = wrap_angle(self.headings[0] - self.headings[-1])
            first = last = closing / max(0.5 * (self.segment_lengths[0]
                                                + self.segment_lengths[-1]), 1e-9)
        elif open_ends_turn:
            first, last = at_vertices[0], at_vertices[-1]
        else:
            first = last = 0.0
        padded = np.concatenate(([first], at_vertices, [last]))
        return 0.5 * (padded[:-1] + padded[1:])

    @property
    def end(self) -> tuple[float, float]:
        return float(self.points[-1, 0]), float(self.points[-1, 1])


@dataclass(frozen=True)
class Turn:
    """Turn in place at (x, y) by `sweep_rad` (signed, may exceed pi) from `start_heading`."""

    x: float
    y: float
    start_heading: float
    sweep_rad: float

    @property
    def end(self) -> tuple[float, float]:
        return self.x, self.y


Leg = Polyline | Turn


@dataclass(frozen=True)
class Path:
    """A planned trajectory: legs in order, plus what the report needs to know."""

    legs: tuple[Leg, ...]
    closed: bool = False
    endless: bool = False

    @property
    def end(self) -> tuple[float, float]:
        return self.legs[-1].end

    @property
    def end_heading(self) -> float:
        """The turtle's heading at the end: a last turn's final heading, else the direction of
        the last segment (the opposite one when driven backwards)."""
        leg = self.legs[-1]
        if isinstance(leg, Turn):
            return wrap_angle(leg.start_heading + leg.sweep_rad)
        return wrap_angle(float(leg.headings[-1]) + (math.pi if leg.reverse else 0.0))

    @property
    def length(self) -> float:
        return sum(leg.length for leg in self.legs if isinstance(leg, Polyline))

    @property
    def pen_up_length(self) -> float:
        """Length driven with the pen up (between the strokes of a drawing)."""
        return sum(leg.length for leg in self.legs if isinstance(leg, Polyline) and not leg.pen)

    @property
    def turning(self) -> float:
        """Total in-place turning, radians."""
        return sum(abs(leg.sweep_rad) for leg in self.legs if isinstance(leg, Turn))

    def points(self) -> np.ndarray:
        """Every point the turtle is meant to visit, (N, 2)."""
        parts = [leg.points if isinstance(leg, Polyline) else np.array([[leg.x, leg.y]])
                 for leg in self.legs]
        return np.concatenate(parts) if parts else np.empty((0, 2))

    def lower_bound_s(self, linear_speed: float, angular_speed: float) -> float:
        """Kinematic lower bound of the time to drive it at the given top speeds."""
        return self.length / linear_speed + self.turning / angular_speed


# A bend of a polyline is a sample of a curve where the curve through it passes at most
# `CURVE_SAMPLE_M` off the polyline, or at most `SAMPLED_CURVE_M` where a neighbour bends the
# same way about as sharply (a sampled curve's chords: the demo's sine, 0.47 mm); otherwise it
# is a corner, turned in place however gentle (steered through, a 0.3 rad bend between 2 m
# segments leaves the path by 20 mm)
CURVE_SAMPLE_M = 0.0005
SAMPLED_CURVE_M = 0.002
_LIKE_CURVATURE = 2.0  # a neighbour's curvature within this factor is "about as sharp"


def _bends(start_heading: float, points: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The polyline through `points` (no repeated points, at least two) from `start_heading`:
    its segments' lengths, their directions, and the change of direction before each."""
    steps = np.diff(points, axis=0)
    directions = np.arctan2(steps[:, 1], steps[:, 0])
    change = wrap_angles(np.diff(np.concatenate(([start_heading], directions))))
    return np.hypot(steps[:, 0], steps[:, 1]), directions, change


def _turned_in_place(lengths: np.ndarray, change: np.ndarray,
                     corner_angle_rad: float) -> np.ndarray:
    """Whether to turn in place before each segment (`_bends`): where the direction changes by
    more than `corner_angle_rad`, or by a bend that samples no curve (see `CURVE_SAMPLE_M`)."""
    span = np.concatenate(([0.0], lengths[:-1])) + lengths
    curvature = change / np.maximum(0.5 * span, 1e-12)
    alike = np.zeros(len(change), dtype=bool)
    for shift in (1, -1):  # the bend before, then the bend after
        neighbour = np.roll(curvature, shift)
        ratio = np.divide(neighbour, curvature, out=np.zeros_like(curvature),
                          where=curvature != 0.0)
        like = (ratio >= 1.0 / _LIKE_CURVATURE) & (ratio <= _LIKE_CURVATURE)
        like[0 if shift == 1 else -1] = False  # no bend before the first, none after the last
        alike |= like
    sagitta = span * np.abs(change) / 16.0  # an arc's, through the bend between the segments
    # from the start, a curve leaving along the robot's heading that meets the first segment
    # at its end (a parabola): it passes a quarter of the segment's length times the bend off
    sagitta[0] = lengths[0] * abs(change[0]) / 4.0
    return ((np.abs(change) > corner_angle_rad) | (sagitta > SAMPLED_CURVE_M)
            | ((sagitta > CURVE_SAMPLE_M) & ~alike))


def legs_from_polyline(start: Pose2D, points: np.ndarray, *, corner_angle_rad: float,
                       reverse: bool = False, pen: bool = True) -> list[Leg]:
    """Split a polyline into curves at its corners (`_turned_in_place`).

    The turtle starts at `start`; a turn in place (shortest direction) is inserted at every
    corner, including before the first segment. Zero-length segments are dropped. `pen` marks
    the polylines (see `Polyline`).
    """
    points = np.asarray(points, dtype=float)
    keep = np.concatenate(([True], np.hypot(*np.diff(points, axis=0).T) > 1e-9))
    points = points[keep]
    legs: list[Leg] = []
    current: list[np.ndarray] = [points[0]]
    if len(points) > 1:
        heading = start.theta + (math.pi if reverse else 0.0)
        lengths, directions, change = _bends(heading, points)
        facing = np.concatenate(([heading], directions[:-1])) - (math.pi if reverse else 0.0)
        turned = _turned_in_place(lengths, change, corner_angle_rad)
        for index, (a, b) in enumerate(zip(points[:-1], points[1:], strict=True)):
            if turned[index]:
                if len(current) > 1:
                    legs.append(Polyline(np.array(current), reverse=reverse, pen=pen))
                legs.append(Turn(float(a[0]), float(a[1]), wrap_angle(float(facing[index])),
                                 float(change[index])))
                current = [a]
            current.append(b)
    if len(current) > 1:
        legs.append(Polyline(np.array(current), reverse=reverse, pen=pen))
    return legs

"""The polyline projection (pure): windowed searches against the independent distance of
`testing.geometry`, and the run's largest deviation exact on paths that cross themselves."""

import math

import numpy as np
import pytest

from turtle_traj.core.geometry.projection import PathDeviation, PolylineSegments
from turtle_traj.testing.geometry import distance_to_polyline


def _figure_eight(count: int) -> np.ndarray:
    """A lemniscate sampled at `count` points: it crosses itself at its centre."""
    t = np.linspace(0.0, 2.0 * math.pi, count)
    return np.stack([5.0 + 3.0 * np.sin(t), 5.0 + 1.5 * np.sin(2.0 * t)], axis=1)


def _poses_along(path: np.ndarray, seed: int, noise: float) -> np.ndarray:
    """Points along the path, a few millimetres apart, off it by up to `noise`."""
    lengths = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(path, axis=0).T))))
    along = np.arange(0.0, lengths[-1], 0.008)
    points = np.stack([np.interp(along, lengths, path[:, 0]),
                       np.interp(along, lengths, path[:, 1])], axis=1)
    return points + np.random.default_rng(seed).uniform(-noise, noise, points.shape)


@pytest.mark.parametrize('count', [2, 5, 300, 3000])
@pytest.mark.parametrize('seed', [1, 2])
def test_the_largest_deviation_is_the_exact_one(count, seed):
    path = _figure_eight(count)
    poses = _poses_along(path, seed, noise=0.02)
    poses[len(poses) // 3] += (0.0, 0.35)  # one far off, near another part of the path
    deviation = PathDeviation(path)
    exact = distance_to_polyline(poses, path)
    for index, (x, y) in enumerate(poses):
        deviation.add(x, y)
        assert deviation.largest == pytest.approx(exact[:index + 1].max(), abs=1e-12)
        assert deviation.last == pytest.approx(exact[index], abs=1e-12)


def test_a_pose_that_jumps_to_another_part_of_the_path_is_measured_against_all_of_it():
    """Where the walk from the last segment finds a far distance, the whole path answers:
    a pose at the other end of a U is on the path, not a U's width from it."""
    path = np.array([(0.0, 0.0), (4.0, 0.0), (4.0, 1.0), (0.0, 1.0)])
    deviation = PathDeviation(path)
    deviation.add(0.5, 0.0)
    deviation.add(0.5, 1.002)  # beside the last leg, 1 m from the first
    assert deviation.largest == pytest.approx(0.002)
    assert deviation.distance(2.0, 0.5) == pytest.approx(0.5)


def test_a_window_finds_its_nearest_segment_as_a_search_of_all_of_them_does():
    path = _figure_eight(200)
    segments = PolylineSegments(path)
    for x, y in _poses_along(path, 3, noise=0.05)[::7]:
        index, fraction, offset = segments.project(x, y, range(segments.count))
        start, end = path[index], path[index + 1]
        nearest = start + fraction * (end - start)
        assert math.dist((x, y), nearest) == pytest.approx(
            distance_to_polyline(np.array([(x, y)]), path)[0], abs=1e-12)
        # the offset is the point's y in the segment's own frame (x along it): its distance
        # from the segment's line, positive on its left
        heading = math.atan2(end[1] - start[1], end[0] - start[0])
        across = -math.sin(heading) * (x - start[0]) + math.cos(heading) * (y - start[1])
        assert offset == pytest.approx(across, abs=1e-12)


def test_a_walk_from_the_start_finds_where_the_robot_stands_along_the_path():
    """Walking from the first segment: a robot some way along the path finds its segment, and
    a path that comes back past the robot later is not taken for where it stands."""
    loop = np.array([(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.1, 1.0), (1.1, 0.001),
                     (1.1, -1.0)])
    segments = PolylineSegments(loop)
    assert segments.walk(0, 0.0, 0.0)[0] == 0
    assert segments.walk(0, 1.5, 0.01)[0] == 1
    # beside the loop's return (0.001 m off it) but 0.01 m off the path's first sides
    assert segments.walk(0, 1.1, 0.01)[0] == 1
    # far off: the walk goes on while the path comes no farther (to (2, 1), shared by 2 and 3)
    assert segments.walk(0, 5.0, 5.0)[0] == 3


@pytest.mark.parametrize(('index', 'fraction', 'distance'), [
    (0, 0.0, 0.0), (0, 0.25, 0.3), (1, 0.5, 1.7), (0, 0.1, 100.0), (2, 1.0, 0.5)])
def test_a_point_further_along_is_where_the_arc_length_puts_it(index, fraction, distance):
    points = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 2.0), (3.0, 2.0)])
    arc = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(points, axis=0).T))))
    start = arc[index] + fraction * (arc[index + 1] - arc[index])
    target = min(start + distance, arc[-1])
    expected = (np.interp(target, arc, points[:, 0]), np.interp(target, arc, points[:, 1]))
    found_index, x, y = PolylineSegments(points).along(index, fraction, distance)
    assert (x, y) == pytest.approx(expected)
    assert arc[found_index] <= target + 1e-12 <= arc[found_index + 1] + 1e-12

"""A grid planner's path, as Nav2's planners give one: A* over a 5 cm grid of free cells, eight
neighbours each (NavFn's and Smac 2D's resolution), so the path is a chain of cell centres, a
few centimetres apart, whose diagonal stretches are staircases of 45-degree steps.

networkx's A* searches the grid, the straight-line distance its heuristic (admissible, and
looser than the octile distance: among the many paths of equal length it leaves the search to
interleave diagonal and straight steps, the staircase a grid planner's path is known for).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import networkx as nx
import numpy as np

CELL_M = 0.05
_NEIGHBOURS = ((1, 0), (0, 1), (1, 1), (1, -1))  # the other four are these, reversed


def grid_path(start: tuple[float, float], goal: tuple[float, float],
              blocked: Callable[[float, float], bool], bounds: tuple[float, float],
              cell: float = CELL_M) -> np.ndarray:
    """The shortest 8-connected path between the cells of `start` and `goal` on a square grid
    over `bounds` (low, high on both axes), avoiding cells whose centre is `blocked`: (N, 2)
    cell centres, metres.

    :raises networkx.NetworkXNoPath: the goal cannot be reached.
    """
    low, high = bounds
    count = round((high - low) / cell) + 1
    cells = [(i, j) for i in range(count) for j in range(count)]
    free = {(i, j) for i, j in cells if not blocked(low + i * cell, low + j * cell)}
    grid = nx.Graph()
    grid.add_edges_from(((i, j), (i + di, j + dj), {'weight': math.hypot(di, dj)})
                        for i, j in cells if (i, j) in free
                        for di, dj in _NEIGHBOURS if (i + di, j + dj) in free)
    route = nx.astar_path(grid, _cell(start, low, cell), _cell(goal, low, cell),
                          heuristic=_straight, weight='weight')
    return low + cell * np.array(route, dtype=float)


def _cell(point: tuple[float, float], low: float, cell: float) -> tuple[int, int]:
    return round((point[0] - low) / cell), round((point[1] - low) / cell)


def _straight(a: tuple[int, int], b: tuple[int, int]) -> float:
    return math.dist(a, b)

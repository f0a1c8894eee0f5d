"""Which turtle draws which part of a split tour: a bottleneck assignment. Pure.

Given what each turtle would take to draw each part (the travel to it from where it stands, and
the part), the assignment that ends soonest is the one whose longest pair is least: the linear
bottleneck assignment problem (Gross, 1959; Burkard, Dell'Amico and Martello, "Assignment
Problems", SIAM 2009, section 6.2). Its least possible longest pair is found by a binary search
over the costs, each threshold checked for a matching of every part (SciPy's Hopcroft-Karp);
among the assignments within it, the one of least total is kept (SciPy's linear sum
assignment), so that the turtles that are not the last do not travel further than they must.
"""

from __future__ import annotations

import numpy as np


def bottleneck_assignment(costs: np.ndarray) -> list[int]:
    """For each part (a column of `costs`, turtles by parts, at least as many turtles), the
    turtle (row) that draws it, for the least longest cost, then the least total."""
    # imported here: scipy.optimize takes 0.3 s to import, and only fleets of more than
    # `sharing.EXHAUSTIVE_TURTLES` turtles come here (every program with a coordinator would
    # pay it at its start)
    from scipy.optimize import linear_sum_assignment
    values = np.unique(costs)
    low, high = 0, len(values) - 1
    while low < high:  # the least threshold under which every part can have its own turtle
        middle = (low + high) // 2
        if _every_part_matched(costs <= values[middle]):
            high = middle
        else:
            low = middle + 1
    within = np.where(costs <= values[low], costs, np.inf)
    finite = np.where(np.isfinite(within), within, 2.0 * values[-1] * costs.size + 1.0)
    rows, columns = linear_sum_assignment(finite)
    turtle_of = [0] * costs.shape[1]
    for row, column in zip(rows, columns, strict=True):
        turtle_of[column] = int(row)
    return turtle_of


def _every_part_matched(allowed: np.ndarray) -> bool:
    """Whether each part (column) can have a turtle (row) of its own among the `allowed`."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import maximum_bipartite_matching
    matched = maximum_bipartite_matching(csr_matrix(allowed.T.astype(np.int8)),
                                         perm_type='column')
    return bool(np.all(matched >= 0))

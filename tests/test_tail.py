"""A node held up as a leg ends (pure: no ROS; see `follower`, a leg's tail).

turtlesim repeats the last command it took until the next one comes. Before the tail, a node
that missed a tick or two on a corner's last approach left the turtle repeating an approach
command past the corner: issue 44's last flake, 5.9 mm in the full suite. Here the node's
control timer misses `held` ticks starting at each tick around the first corner of the 0.5 m
square, and the turtle's own positions are measured against the square.
"""

from collections import deque
from collections.abc import Callable

import numpy as np
import pytest

from turtle_traj.core.control.loop import ControlLoop
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.turtlesim_contract import STEP_S, TOPIC_QOS_DEPTH
from turtle_traj.sim.physics import World
from turtle_traj.testing.geometry import distance_to_polyline, regular_polygon
from turtle_traj.testing.pure_loop import shape

SETTINGS = DEFAULT_SETTINGS
START = Pose2D(5.5, 5.5, 0.0)
SQUARE = regular_polygon(START.x, START.y, START.theta, 4, 0.5, False)


def _square(held: Callable[[int], bool]) -> tuple[np.ndarray, int, bool]:
    """The 0.5 m square, the control timer silent at the ticks `held` says (the poses still
    arrive). The turtle's positions, the tick the first turn began, and whether it ended as
    done."""
    world = World()
    turtle = world.spawn(START.x, START.y, START.theta, 'turtle1')
    loop = ControlLoop(STEP_S)
    loop.observe(START, 0.0, 0.0)
    run = loop.start(planning.plan('polygon', shape(sides=4, size=0.5), START, SETTINGS),
                     arena=SETTINGS.arena, now_s=0.0)
    queue, positions, turning = deque(maxlen=TOPIC_QOS_DEPTH), [], None
    for step in range(2000):
        positions.append((turtle.x, turtle.y))
        loop.observe(Pose2D(turtle.x, turtle.y, turtle.theta),
                     float(np.float32(turtle.linear_speed)), float(np.float32(turtle.omega)))
        if not held(step):
            commands = loop.command(SETTINGS.control, SETTINGS.arena, step * STEP_S)
            if run.ending is not None:
                return np.array(positions), turning, run.ending[0]
            for command in commands:
                loop.sent(command, step * STEP_S)
            queue.extend(commands)
        if queue:  # turtlesim takes one queued command a step
            taken = queue.popleft()
            world.command('turtle1', taken.linear, 0.0, taken.angular)
            if turning is None and taken.angular and not taken.linear:
                turning = step
        world.step()
    raise AssertionError('the run never ended')


@pytest.mark.parametrize('ticks', [1, 2, 3, 4])
def test_a_node_held_up_as_a_leg_ends_leaves_the_turtle_on_the_corner(ticks):
    _, corner, _ = _square(lambda _step: False)
    for first in range(corner - 12, corner + 3):
        positions, _, done = _square(range(first, first + ticks).__contains__)
        assert done
        # to the micrometre: without the tail a tick missed on the approach drew up to a full
        # step (16 mm at 1 m/s) past the corner
        assert distance_to_polyline(positions, SQUARE).max() < 1e-6, (first, ticks)


def test_a_tail_the_link_drops_is_driven_again():
    """A link that loses the first tail for good (held past the commands' lifespan, the writer
    drops them): the turtle drives on past the corner meanwhile, but the leg does not end
    where the tail would have left it; the corner is reached, then every other one."""
    world = World()
    turtle = world.spawn(START.x, START.y, START.theta, 'turtle1')
    loop = ControlLoop(STEP_S)
    loop.observe(START, 0.0, 0.0)
    run = loop.start(planning.plan('polygon', shape(sides=4, size=0.5), START, SETTINGS),
                     arena=SETTINGS.arena, now_s=0.0)
    queue, positions, lost = deque(maxlen=TOPIC_QOS_DEPTH), [], None
    for step in range(3000):
        positions.append((turtle.x, turtle.y))
        loop.observe(Pose2D(turtle.x, turtle.y, turtle.theta),
                     float(np.float32(turtle.linear_speed)), float(np.float32(turtle.omega)))
        commands = loop.command(SETTINGS.control, SETTINGS.arena, step * STEP_S)
        if run.ending is not None:
            break
        for command in commands:
            loop.sent(command, step * STEP_S)
        if lost is None and len(commands) > 1:
            lost = commands  # never arrives
        else:
            queue.extend(commands)
        if queue:
            taken = queue.popleft()
            world.command('turtle1', taken.linear, 0.0, taken.angular)
        world.step()
    assert lost is not None and run.ending == (True, 'polygon done')
    drawn = np.array(positions)
    for corner in SQUARE:
        assert np.hypot(*(drawn - corner).T).min() < 1e-3

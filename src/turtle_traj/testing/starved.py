"""The trajectory node's control loop on a starved executor, in pure Python (no ROS).

rclpy 7.1.6's MultiThreadedExecutor can starve a node (ros2/rclpy#1452): its spin thread
re-yields waiting tasks without waiting and holds the GIL, so the control timer fires tens to
hundreds of milliseconds late and the poses that queued meanwhile arrive in a burst. Measured in
tests/test_multithreaded.py at c1af86f: timer gaps of 16 ms at the median, 31 ms at the 90th
percentile, 57 ms at the 95th, 190 ms at the 99th and up to 450 ms, and a stall of 0.1 to 0.45 s
as a run starts (planning and the refused requests hold the node).

Here the simulator steps every 16 ms on its own clock (as the simulator program does) with
`sim.physics.World`, taking one queued command a step (turtlesim's 7-deep queue); the node is
`ControlLoop` exactly as `TrajectoryNode` drives it, its pose subscription and its control timer
each run only when the executor lets them: stalls start at a dispatch with some probability and
last a log-normal time; after one, the queued poses are observed in order, and the timer fires
once (rcl skips the periods it missed). Seeded: the same seed gives the same run.
"""

from __future__ import annotations

import inspect
import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from turtle_traj.core.control.commands import STOP
from turtle_traj.core.control.loop import ControlLoop
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M, STEP_S, TOPIC_QOS_DEPTH
from turtle_traj.sim.physics import World

STEP_MS = round(STEP_S * 1000)


@dataclass(frozen=True)
class Stalls:
    """How the executor holds back one kind of callback: the chance that a stall starts at a
    dispatch, its median and spread (log-normal, ms), its longest, and the stall as the run
    starts (planning and the refused requests hold the node)."""

    chance: float
    median_ms: float
    sigma: float
    longest_ms: int
    start_ms: tuple[int, int]

    def draw(self, rng: np.random.Generator) -> int:
        """A stall's length (ms), or 0 when none starts."""
        if rng.random() >= self.chance:
            return 0
        return min(int(self.median_ms * math.exp(self.sigma * rng.standard_normal())),
                   self.longest_ms)


# As measured in tests/test_multithreaded.py at c1af86f (the docstring's figures): the control
# timer, and the pose subscription, each held back on its own.
TIMER = Stalls(chance=0.14, median_ms=28.0, sigma=1.15, longest_ms=450, start_ms=(0, 250))
POSES = Stalls(chance=0.14, median_ms=28.0, sigma=1.15, longest_ms=450, start_ms=(150, 450))
# Nothing held back: the poses, when only the timer stalls.
NONE = Stalls(chance=0.0, median_ms=0.0, sigma=0.0, longest_ms=0, start_ms=(0, 1))


def rare(chance: float) -> Stalls:
    """A quiet but shared machine's: a timer stall (median 35 ms, at most 120 ms) starting at a
    tick with `chance` (bench/starved_bench.py --rare)."""
    return Stalls(chance=chance, median_ms=35.0, sigma=0.5, longest_ms=120, start_ms=(0, 1))


@dataclass
class Outcome:
    success: bool
    message: str
    elapsed_s: float
    bound_s: float
    max_deviation_m: float
    end: tuple[float, float]  # where the turtle stood a second after the run ended


def drive(name: str, request, seed: int, timer: Stalls = TIMER, poses_held: Stalls = POSES,
          max_s: float = 90.0) -> Outcome:
    """One run of trajectory `name` from the spawn pose, on an executor starved as said."""
    rng = np.random.default_rng(seed)
    settings = DEFAULT_SETTINGS
    world = World()
    turtle = world.spawn(SPAWN_XY_M, SPAWN_XY_M, 0.0, 'turtle1')
    start = Pose2D(SPAWN_XY_M, SPAWN_XY_M, 0.0)
    loop = ControlLoop(STEP_S)
    stamped = 'now_s' in inspect.signature(loop.sent).parameters  # c1af86f's took no time
    plan = planning.plan(name, request, start, settings)
    poses: deque[tuple[int, Pose2D, float, float]] = deque()  # reaching the node at, pose, echo
    commands: deque = deque(maxlen=TOPIC_QOS_DEPTH)  # at the simulator
    timer_free = int(rng.integers(*timer.start_ms))
    poses_free = int(rng.integers(*poses_held.start_ms))
    loop.observe(start, 0.0, 0.0)
    run = loop.start(plan, arena=settings.arena, now_s=0.0)
    next_tick, in_effect = 0, (0.0, 0.0)
    for now in range(int(max_s * 1000)):
        if now % STEP_MS == 0:  # the simulator's step
            if commands:
                command = commands.popleft()
                world.command('turtle1', command.linear, 0.0, command.angular)
                in_effect = (command.linear, command.angular)
            world.step()
            poses.append((now + 1, Pose2D(turtle.x, turtle.y, turtle.theta),
                          float(np.float32(abs(in_effect[0]))),
                          float(np.float32(in_effect[1]))))
        if now >= poses_free:
            while poses and poses[0][0] <= now:
                _, pose, linear, angular = poses.popleft()
                loop.observe(pose, linear, angular)
            poses_free = now + poses_held.draw(rng)
        if now >= timer_free and now >= next_tick:
            command = loop.command(settings.control, settings.arena, now / 1000)
            if run.ending is not None:
                commands.append(STOP)  # the node's last word: a stop
                break
            if command is not None:
                loop.sent(command, now / 1000) if stamped else loop.sent(command)
                commands.append(command)
            next_tick = (now // STEP_MS + 1) * STEP_MS
            timer_free = now + timer.draw(rng)
        if run.ending is not None:
            break
    ended = run.outcome(loop.pose, now / 1000)
    for _ in range(64):  # a second more: what was still on its way acts, then the stop
        if commands:
            command = commands.popleft()
            world.command('turtle1', command.linear, 0.0, command.angular)
        world.step()
    return Outcome(ended.success, ended.message, ended.elapsed_s,
                   plan.lower_bound_s(plan.control(settings.control)), ended.max_deviation,
                   (turtle.x, turtle.y))

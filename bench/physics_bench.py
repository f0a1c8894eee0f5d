"""turtle_traj driving the physics base (MuJoCo, a TurtleBot3 Burger), measured by ground truth.

    .venv/bin/python bench/physics_bench.py

Lock-step, one fresh base per run (odometry and ground truth start together at the origin).
Paths: a 1 m square, a 0.5 m circle, the DWPP paper's 90 degree step curve (three 3 m legs,
the middle one turned) and the text "ROS" 0.5 m tall (the pen-up moves are driven too: a base
has no pen). At TurtleBot3's limits (0.22 m/s, 2.84 rad/s) and at half of them, the base's
accelerations (2.5 m/s², 3.2 rad/s²) either way; exact corners and corners rounded by 20 mm.

Errors are distances from the path asked for (exact corners), at every step: against the
ground truth (where the base really was) and against the odometry (what the controller saw).
"end" is the distance from the path's end (the start, for closed shapes); "drift" is where the
odometry ended away from the truth; "outside" counts commands beyond the limits the node was
given, or changing faster than they allow; "clipped" counts steps whose wheel speeds the base
scaled down to its motors' top speed (a command of both top speed and a turn); "x RT" is
simulated time over wall time.

Then the physics step: one open-loop drive (four legs and turns) at each step, against 0.25 ms.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

from isolation import isolate

SQUARE_M, CIRCLE_M, TEXT_M, LEG_M, TOLERANCE_M = 1.0, 0.5, 0.5, 3.0, 0.02
TARGET_ODOM_MM, TARGET_TRUTH_MM, TARGET_RT = 5.0, 15.0, 20.0
PERIOD_S = 0.016  # the base's and the node's period


def _requests():
    from geometry_msgs.msg import Point
    from turtle_traj_interfaces.srv import DrawShape, DrawText, FollowPath
    step = [(0.0, 0.0), (LEG_M, 0.0), (LEG_M, LEG_M), (2 * LEG_M, LEG_M)]
    return [
        ('square 1 m', 'square', DrawShape, 'draw_square', DrawShape.Request(size=SQUARE_M)),
        ('circle 0.5 m', 'circle', DrawShape, 'draw_circle', DrawShape.Request(size=CIRCLE_M)),
        ('step 90 deg', 'follow_path', FollowPath, 'follow_path',
         FollowPath.Request(points=[Point(x=x, y=y) for x, y in step])),
        ('text ROS', 'text', DrawText, 'draw_text', DrawText.Request(text='ROS', height=TEXT_M)),
    ]


def _distances(samples: list[tuple[float, float, float, float]], ideal: np.ndarray
               ) -> np.ndarray:
    from turtle_traj.core.geometry.projection import NearestOnPolyline
    return NearestOnPolyline(ideal).distances([(x, y) for _t, x, y, _yaw in samples])


def _outside(commands, speed: float, turn: float) -> int:
    """Commands beyond the node's limits or changing faster than they allow (`outside_share`
    of bench/base_bench.py, counted)."""
    from base_loop import Limits, outside_share
    from turtle_traj.base.drive import DriveLimits
    from turtle_traj.core.control.commands import Command

    base = DriveLimits()
    sent = [Command(msg.twist.linear.x, msg.twist.angular.z) for msg in commands]
    limits = Limits(v=speed, omega=turn, a=base.max_linear_accel, alpha=base.max_angular_accel)
    return round(outside_share(sent, limits) * len(sent))


def run(label, kind, service, name, request, speed, turn, tolerance, *, record=True) -> dict:
    from geometry_msgs.msg import TwistStamped

    from turtle_traj.apps.base_system import BaseSystem
    from turtle_traj.core.geometry.path import Pose2D
    from turtle_traj.core.planning import planner
    from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS

    request.corner_tolerance = tolerance
    system = BaseSystem(linear_speed=speed, angular_speed=turn)
    try:
        commands = []
        if record:
            system.client.create_subscription(TwistStamped, 'cmd_vel', commands.append,
                                              TURTLE_TOPIC_QOS)
        exact = type(request)()
        for field in request.get_fields_and_field_types():
            setattr(exact, field, getattr(request, field))
        exact.corner_tolerance = 0.0
        ideal = planner.plan(kind, exact, Pose2D(0.0, 0.0, 0.0),
                             system.node.settings).drawn_points()
        started_sim, started_wall = system.sim_time_s, time.perf_counter()
        response = system.call(service, name, request)
        wall = time.perf_counter() - started_wall
        truth, odometry = _distances(system.truth, ideal), _distances(system.odometry, ideal)
        end = ideal[-1]
        t_end, o_end = system.truth[-1], system.odometry[-1]
        return dict(
            label=label, ok=response.success, message=response.message,
            truth_rmse=1e3 * math.sqrt(np.mean(truth ** 2)), truth_max=1e3 * truth.max(),
            truth_end=1e3 * math.dist(t_end[1:3], end),
            odom_rmse=1e3 * math.sqrt(np.mean(odometry ** 2)), odom_max=1e3 * odometry.max(),
            odom_end=1e3 * math.dist(o_end[1:3], end),
            drift=1e3 * math.dist(t_end[1:3], o_end[1:3]),
            drift_deg=math.degrees(math.remainder(o_end[3] - t_end[3], math.tau)),
            time=response.elapsed, reported=1e3 * response.max_deviation,
            outside=_outside(commands, speed, turn) if record else -1,
            clipped=system.sim.clipped_commands,
            rt=(system.sim_time_s - started_sim) / wall)
    finally:
        system.close()


def tracking() -> bool:
    header = (f"{'path':13} {'speeds':>11} {'corners':>7} {'ok':>3} | {'truth: rmse':>11} "
              f"{'max':>6} {'end':>6} | {'odom: rmse':>10} {'max':>6} {'end':>6} | "
              f"{'drift mm':>8} {'deg':>5} | {'time s':>6} {'outside':>7} {'clipped':>7} "
              f"{'x RT':>5}")
    print('Tracking, errors in mm\n')
    print(header)
    passed = True
    for label, kind, service, name, request in _requests():
        for speed, turn in ((0.22, 2.84), (0.11, 1.42)):
            for tolerance in (0.0, TOLERANCE_M):
                r = run(label, kind, service, name, request, speed, turn, tolerance)
                target = (tolerance == 0.0 and speed == 0.22
                          and kind in ('square', 'circle'))
                met = r['outside'] == 0 and (not target or (
                    r['ok'] and r['odom_max'] <= TARGET_ODOM_MM
                    and r['truth_max'] <= TARGET_TRUTH_MM))
                passed &= met
                print(f"{label:13} {speed:5.2f}/{turn:4.2f} "
                      f"{'exact' if not tolerance else '20 mm':>7} {'yes' if r['ok'] else 'NO':>3}"
                      f" | {r['truth_rmse']:11.2f} {r['truth_max']:6.2f} {r['truth_end']:6.2f} |"
                      f" {r['odom_rmse']:10.2f} {r['odom_max']:6.2f} {r['odom_end']:6.2f} |"
                      f" {r['drift']:8.2f} {r['drift_deg']:5.2f} | {r['time']:6.2f} "
                      f"{r['outside']:7d} {r['clipped']:7d} {r['rt']:5.1f}"
                      f"{'' if met else '  <- target missed'}")
                if not r['ok']:
                    print(f'    {r["message"]}')
    print(f'\nTargets (square and circle at 0.22 m/s, exact): odometry max <= {TARGET_ODOM_MM:g} '
          f'mm, ground truth max <= {TARGET_TRUTH_MM:g} mm; every run: 0 commands outside.')
    return passed


def real_time_factor() -> bool:
    """The square at TurtleBot3's limits with nothing but the base and the node (no recorder),
    three times: the lock-step speed of one robot."""
    label, kind, service, name, request = _requests()[0]
    factors = sorted(run(label, kind, service, name, request, 0.22, 2.84, 0.0,
                         record=False)['rt'] for _ in range(3))
    print(f'\nLock-step, one base and the node, the 1 m square three times: '
          f'{", ".join(f"{f:.1f}" for f in factors)}x real time (median {factors[1]:.1f}x; '
          f'target >= {TARGET_RT:g}x)')
    return factors[1] >= TARGET_RT


def physics_step() -> None:
    """The same open-loop drive at several physics steps, against the finest."""
    from turtle_traj.base import model
    from turtle_traj.base.drive import DriveLimits, VelocityLimiter, wheel_speeds
    from turtle_traj.base.model import BaseSpec
    from turtle_traj.base.physics import DiffDrivePhysics

    def drive(timestep: float) -> tuple[tuple[float, float, float], float]:
        spec = BaseSpec(timestep=timestep)
        physics, limiter = DiffDrivePhysics(spec), VelocityLimiter(DriveLimits())
        started = time.perf_counter()
        for _leg in range(4):
            for v, w, duration in ((0.22, 0.0, 4.5), (0.0, 0.0, 0.3), (0.0, 2.84, 0.553),
                                   (0.0, 0.0, 0.5)):
                for _ in range(round(duration / PERIOD_S)):
                    left, right, _ = wheel_speeds(
                        *limiter.limit(v, w, PERIOD_S), wheel_radius=spec.wheel_radius,
                        wheel_separation=spec.wheel_separation,
                        max_wheel_speed=spec.max_wheel_speed)
                    physics.drive(left, right)
                    physics.advance(PERIOD_S)
        return physics.pose(), physics.time_s / (time.perf_counter() - started)

    print('\nPhysics step: four 1 m legs and quarter turns, open loop, against a 0.25 ms step '
          f'(contact time constant {model.CONTACT_TIME_CONSTANT_S * 1e3:g} ms)')
    reference, _ = drive(0.00025)
    for timestep in (0.0005, 0.001, 0.002):
        pose, factor = drive(timestep)
        print(f'  {timestep * 1e3:5.2f} ms: {1e3 * math.dist(pose[:2], reference[:2]):6.2f} mm, '
              f'{math.degrees(pose[2] - reference[2]):6.3f} deg off; physics alone '
              f'{factor:5.0f}x real time')


def main() -> int:
    isolate('physics')
    import rclpy
    rclpy.init()
    try:
        passed = tracking()
        passed &= real_time_factor()
    finally:
        rclpy.shutdown()
    physics_step()
    print('every target met' if passed else 'some targets missed (see above)')
    return 0 if passed else 1


if __name__ == '__main__':
    sys.exit(main())

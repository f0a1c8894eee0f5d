"""The controller interface, the shipped controllers and the node's safety net, in the pure loop
(the node's control loop on the simulator's physics, no ROS)."""

import math
import re
import time
from dataclasses import replace

import numpy as np
import pytest
from shapely.geometry import LineString, Point

from tests.misbehaving_controllers import StopsHalfWay, StopsNearTheLastPoint
from turtle_traj.api.controllers import UnknownController, choose, names, resolve
from turtle_traj.api.ros_interface import make_request
from turtle_traj.apps.score.courses import PAPER_INERTIA, follow_request, step_curve
from turtle_traj.apps.score.loop import drive
from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.controller import (
    Controller,
    Limits,
    State,
    Stroke,
    interface_problem,
)
from turtle_traj.core.control.controllers.catalogue import ControllerChoice
from turtle_traj.core.control.controllers.dwpp import Dwpp
from turtle_traj.core.control.controllers.exact import ExactFollower
from turtle_traj.core.control.controllers.pure_pursuit import PurePursuit
from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.prediction import Prediction
from turtle_traj.core.control.walker import PlanWalker, strokes_of
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Polyline, Pose2D, Turn
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS, settings_from_values
from turtle_traj.core.parameters.table import DEFAULTS
from turtle_traj.core.planning import planner
from turtle_traj.core.registry import BY_NAME
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.node.answer_timer import ProcessAnswerTimer
from turtle_traj.testing.geometry import distance_to_polyline, regular_polygon
from turtle_traj.testing.pure_loop import shape

PAPER = settings_from_values({**DEFAULTS, 'linear_speed': 0.5, 'angular_speed': 1.0,
                              'max_linear_accel': 0.5, 'max_angular_accel': 1.0,
                              'arena': 'none'})


def _outside_the_limits(commands: list[Command], config) -> list[Command]:
    """Commands a base with these limits cannot take from the one before (checked here)."""
    outside, previous = [], Command()
    for command in commands:
        if (abs(command.linear) > config.linear_speed + 1e-9
                or abs(command.angular) > config.angular_speed + 1e-9
                or (config.max_linear_accel and abs(command.linear - previous.linear)
                    > config.max_linear_accel * config.period_s * (1 + 1e-6))
                or (config.max_angular_accel and abs(command.angular - previous.angular)
                    > config.max_angular_accel * config.period_s * (1 + 1e-6))):
            outside.append(command)
        previous = command
    return outside


def _step_course(degrees: float):
    points = step_curve(degrees)
    start = Pose2D(float(points[0, 0]), float(points[0, 1]), 0.0)
    return points, start, planner.plan('follow_path', follow_request(points), start, PAPER)


# --- strokes -----------------------------------------------------------------------------------

def test_a_square_is_one_stroke_its_corners_the_controllers():
    plan = planner.plan('polygon', shape(sides=4, size=2.0), Pose2D(4.0, 4.0, 0.0),
                        DEFAULT_SETTINGS)
    assert sum(isinstance(leg, Turn) for leg in plan.path.legs) == 3  # exact: turned in place
    steps = strokes_of(plan.path)
    assert len(steps) == 1 and isinstance(steps[0], Polyline)
    corners = regular_polygon(4.0, 4.0, 0.0, 4, 2.0, False)
    assert np.allclose(steps[0].points, corners)


def test_text_is_cut_where_the_pen_lifts_and_joined_at_its_corners():
    plan = planner.plan('text', make_request(BY_NAME['text'], {'text': 'NH', 'height': 1.0}),
                        Pose2D(2.0, 5.0, 0.0), DEFAULT_SETTINGS)
    strokes = [step for step in strokes_of(plan.path) if isinstance(step, Polyline)]
    pens = [stroke.pen for stroke in strokes]
    assert all(a != b for a, b in zip(pens, pens[1:], strict=False))  # up and down in turn
    inked = {tuple(point) for s in strokes if s.pen for point in s.points.round(9)}
    drawn = [leg for leg in plan.path.legs if isinstance(leg, Polyline) and leg.pen]
    assert all(tuple(point) in inked for leg in drawn for point in leg.points.round(9))
    assert len(strokes) < len([leg for leg in plan.path.legs if isinstance(leg, Polyline)])


def test_a_path_that_doubles_back_is_two_strokes():
    points = np.array([(2.0, 2.0), (6.0, 2.0), (3.0, 2.0)])  # out and back along one line
    plan = planner.plan('follow_path', follow_request(points), Pose2D(2.0, 2.0, 0.0),
                        DEFAULT_SETTINGS)
    kinds = [type(step).__name__ for step in strokes_of(plan.path)]
    assert kinds == ['Polyline', 'Turn', 'Polyline']


# --- the shipped controllers -------------------------------------------------------------------

@pytest.mark.parametrize('degrees', [45, 90, 135])
def test_dwpp_keeps_every_command_in_the_window_and_beats_stop_and_turn(degrees):
    points, start, plan = _step_course(degrees)
    exact = drive(plan, start, PAPER, inertia=PAPER_INERTIA)
    dwpp = drive(plan, start, PAPER, inertia=PAPER_INERTIA, controller=choose('dwpp'))
    assert dwpp.run.ending[0], dwpp.run.ending
    assert _outside_the_limits(dwpp.commands, PAPER.control) == []
    assert dwpp.run.follower.clamped <= 1  # DWPP chooses within the window itself
    assert dwpp.elapsed_s < exact.elapsed_s  # no stop at the corners
    error = distance_to_polyline(dwpp.xy(), points)
    # it cuts the corners (that is what rounding them costs), by less than its look-ahead
    assert 0.02 < error.max() < 0.9 * math.sin(math.radians(degrees) / 2)
    assert math.dist((dwpp.poses[-1].x, dwpp.poses[-1].y), points[-1]) < 0.015


def test_pure_pursuit_turns_in_place_first_when_facing_away():
    points = np.array([(3.0, 3.0), (7.0, 3.0)])
    start = Pose2D(3.0, 3.0, math.pi)  # facing away from the path
    plan = planner.plan('follow_path', follow_request(points), start, DEFAULT_SETTINGS)
    # the node turns in place before a stroke: drive the stroke alone, as its controller sees it
    controller = PurePursuit()
    config = DEFAULT_SETTINGS.control
    limits = Limits(config.linear_speed, config.angular_speed, 0.0, 0.0, config.period_s)
    controller.start(Stroke(points), limits)
    command = controller.command(State(Prediction(start, Command()), start, 0.0, limits))
    assert command.linear == 0.0 and abs(command.angular) == config.angular_speed
    ahead = Pose2D(3.0, 3.0, controller.rotate_to_heading_min_angle / 2)
    assert controller.command(State(Prediction(ahead, Command()), ahead, 0.0, limits)).linear > 0.0
    run = drive(plan, start, DEFAULT_SETTINGS, controller=choose('pure_pursuit'))
    assert run.run.ending[0] and math.dist((run.poses[-1].x, run.poses[-1].y), (7.0, 3.0)) < 0.015


def test_a_stroke_driven_backwards_is_shown_to_the_controller_as_a_forward_one():
    start = Pose2D(6.0, 5.0, 0.0)
    plan = planner.plan('move', make_request(BY_NAME['move'], {'distance': -2.0}), start,
                        DEFAULT_SETTINGS)
    run = drive(plan, start, DEFAULT_SETTINGS, controller=choose('dwpp'))
    assert run.run.ending[0], run.run.ending
    assert all(command.linear <= 0.0 for command in run.commands)
    assert abs(run.poses[-1].x - 4.0) < 0.015 and abs(run.poses[-1].y - 5.0) < 0.005
    assert all(abs(wrap_angle(pose.theta)) < 0.01 for pose in run.poses)  # never turned round


def test_an_endless_circle_goes_round_lap_after_lap():
    start = Pose2D(5.5, 3.0, 0.0)
    plan = planner.plan('circle', shape(size=1.0, forever=True), start, DEFAULT_SETTINGS)
    run = drive(plan, start, DEFAULT_SETTINGS, controller=choose('pure_pursuit'), max_s=25.0)
    assert run.run.ending == (False, 'circle still running after 25 s')  # never ended by itself
    # at 1 m/s round a 2 pi m circle: about four laps, each passing the start again
    near_start = np.hypot(run.xy()[:, 0] - 5.5, run.xy()[:, 1] - 3.0) < 0.05
    passes = np.count_nonzero(np.diff(near_start.astype(int)) == 1)
    assert passes >= 3
    centre = np.array([5.5, 4.0])
    assert np.abs(np.hypot(*(run.xy()[100:] - centre).T) - 1.0).max() < 0.05


# --- the node, not the controller, decides that the end is reached --------------------------

@pytest.mark.parametrize(('kind', 'size', 'length'), [
    ('square', 2.0, 8.0), ('triangle', 2.0, 6.0), ('circle', 1.0, 2.0 * math.pi)])
def test_an_end_claimed_at_a_closed_strokes_start_is_a_controller_fault(kind, size, length):
    start = Pose2D(3.0, 3.0, 0.0)
    plan = planner.plan(kind, shape(size=size), start, DEFAULT_SETTINGS)
    run = drive(plan, start, DEFAULT_SETTINGS, controller=choose(
        'tests.misbehaving_controllers:StopsNearTheLastPoint'))
    outcome = run.run.outcome(run.poses[-1], run.elapsed_s)
    assert not outcome.success and outcome.reason is Ending.CONTROLLER_FAULT
    assert (f"controller 'tests.misbehaving_controllers:StopsNearTheLastPoint' claimed the end "
            f'after 0.00 m of {length:.2f} m') in outcome.message
    assert outcome.driven_length == 0.0 and outcome.path_length == pytest.approx(length, rel=1e-4)
    assert np.abs(run.xy() - (3.0, 3.0)).max() < 1e-9  # it never moved


def test_an_end_claimed_half_way_is_a_fault_and_the_figures_say_how_far_it_got():
    start = Pose2D(3.0, 3.0, 0.0)
    plan = planner.plan('square', shape(size=2.0), start, DEFAULT_SETTINGS)
    run = drive(plan, start, DEFAULT_SETTINGS, controller=ControllerChoice('half', StopsHalfWay))
    outcome = run.run.outcome(run.poses[-1], run.elapsed_s)
    assert not outcome.success and outcome.reason is Ending.CONTROLLER_FAULT
    claimed = re.search(r"controller 'half' claimed the end after ([0-9.]+) m of 8.00 m",
                        outcome.message)
    assert claimed, outcome.message
    # how far along the square the turtle got, measured by shapely from its last pose
    square = LineString(regular_polygon(3.0, 3.0, 0.0, 4, 2.0, False))
    along = square.project(Point(run.xy()[-1]))
    assert 4.0 <= along < 4.3  # half-way, and stopped soon after
    assert outcome.driven_length == pytest.approx(along, abs=0.02)
    assert float(claimed[1]) == pytest.approx(along, abs=0.05)  # as it said it was done


def test_a_lap_of_an_endless_circle_claimed_at_its_start_is_a_fault():
    start = Pose2D(5.5, 3.0, 0.0)
    plan = planner.plan('circle', shape(size=1.0, forever=True), start, DEFAULT_SETTINGS)
    run = drive(plan, start, DEFAULT_SETTINGS,
                controller=ControllerChoice('lap', StopsNearTheLastPoint), max_s=5.0)
    assert run.run.reason is Ending.CONTROLLER_FAULT
    assert "controller 'lap' claimed the end after 0.00 m of" in run.run.ending[1]


def test_every_shipped_controller_ends_its_strokes_where_the_node_agrees():
    """The shipped controllers' own ends pass the node's check on closed and open paths."""
    start = Pose2D(3.0, 3.0, 0.0)
    for kind, request in (('square', shape(size=2.0)), ('circle', shape(size=1.0)),
                          ('triangle', shape(size=2.0))):
        plan = planner.plan(kind, request, start, DEFAULT_SETTINGS)
        for name in ('exact', 'dwpp', 'pure_pursuit'):
            run = drive(plan, start, DEFAULT_SETTINGS, controller=choose(name))
            outcome = run.run.outcome(run.poses[-1], run.elapsed_s)
            assert outcome.success, (kind, name, outcome.message)
            assert outcome.driven_length == pytest.approx(plan.path.length)
            assert math.dist(run.xy()[-1], (3.0, 3.0)) < 0.02


# --- the node keeps the robot safe from the controller ----------------------------------------

class _Raises(Dwpp):
    def command(self, state):
        return 1 / 0


class _Nan(Dwpp):
    def command(self, state):
        return Command(math.nan, 0.0)


class _Slow(Dwpp):
    def command(self, state):
        time.sleep(0.05)
        return super().command(state)


def _reported_late_s(message: str) -> float:
    """How late the last answer was, as the run's ending says."""
    return float(re.search(r'the last after ([0-9.]+) s$', message).group(1))


class _WrongType(Dwpp):
    def command(self, state):
        return 'forward'


class _CannotBeMade:
    def __init__(self):
        raise RuntimeError('no licence')

    def start(self, stroke, limits):
        pass

    def command(self, state):
        return None


class _Reckless(Dwpp):
    def command(self, state):
        return None if super().command(state) is None else Command(100.0, -100.0)


TIMER = ProcessAnswerTimer()  # the node's: answers later than the period end the run


@pytest.mark.parametrize(('controller', 'said'), [
    (_Raises, "controller 'bad' raised ZeroDivisionError in command(): division by zero"),
    (_Nan, "controller 'bad' returned a non-finite command (nan m/s, 0.0 rad/s)"),
    (_Slow, "controller 'bad' answered later than the control period (0.016 s) 3 times in a "
            'row, the last after 0.0'),
    (_WrongType, "controller 'bad' returned 'forward', not a Command"),
    (_CannotBeMade, "controller 'bad' could not be made: RuntimeError: no licence"),
])
def test_a_misbehaving_controller_ends_the_run_saying_what_it_did(controller, said):
    points, start, plan = _step_course(90)
    run = drive(plan, start, PAPER, inertia=PAPER_INERTIA,
                controller=ControllerChoice('bad', controller, TIMER))
    success, message = run.run.ending
    assert not success
    assert message.startswith('follow_path aborted: ') and said in message
    assert len(run.commands) < 20  # at once, not after the progress watchdog
    if controller is _Slow:  # nothing it may be excused (a CPU wait, its thread's collection)
        assert _reported_late_s(message) >= 0.05  # shortens its 50 ms sleep


def test_another_threads_garbage_collection_does_not_excuse_a_slow_controller():
    """Only a collection in the controller's own thread holds it up: with another thread
    collecting all along, the slow controller's 50 ms still read as 50 ms."""
    import gc
    import threading
    stop = threading.Event()

    def collect() -> None:
        while not stop.is_set():
            gc.collect()
    collector = threading.Thread(target=collect)
    collector.start()
    try:
        points, start, plan = _step_course(90)
        run = drive(plan, start, PAPER, inertia=PAPER_INERTIA,
                    controller=ControllerChoice('bad', _Slow, TIMER))
    finally:
        stop.set()
        collector.join()
    assert _reported_late_s(run.run.ending[1]) >= 0.05


def test_the_cpu_wait_is_read_afresh_from_the_file_kept_open():
    """The thread's CPU wait, read from the schedstat file it keeps open, is the kernel's
    figure now: between two readings of the file opened anew (it only grows)."""
    from turtle_traj.node import answer_timer

    def fresh() -> float:
        with open('/proc/thread-self/schedstat') as stats:
            return int(stats.read().split()[1]) * 1e-9
    for _ in range(3):
        before = fresh()
        kept = answer_timer._waited_s()
        assert before <= kept <= fresh()


def test_an_answer_in_time_is_taken_as_it_is_and_a_late_one_is_excused(monkeypatch):
    """Nothing excused can make an answer within the period late, so its excuse is not read
    again (a control tick saves a read of the schedstat file); a later one is excused what the
    thread waited for a CPU meanwhile."""
    from turtle_traj.node import answer_timer
    reads, waited = [], [0.0]

    def waiting() -> float:
        reads.append(None)
        return waited[0]
    monkeypatch.setattr(answer_timer, 'not_the_controllers_s', waiting)
    timer = ProcessAnswerTimer()
    mark = timer.start()
    waited[0] += 0.02  # the thread waited 20 ms for a CPU: not the controller's time
    assert timer.took(mark, 10.0) < 0.02 and len(reads) == 1
    for excused, reads_then in ((0.0, 3), (0.02, 5)):  # late, with or without an excuse
        began = time.perf_counter()
        mark = timer.start()
        waited[0] += excused
        time.sleep(0.03)
        took = timer.took(mark, 0.01)
        elapsed = time.perf_counter() - began
        assert 0.03 - excused <= took <= elapsed - excused and len(reads) == reads_then


def test_the_cpu_wait_is_read_without_letting_go_of_pythons_lock():
    """The CPU wait is read, and its file opened on each thread, by foreign calls that keep
    Python's lock (ctypes' PyDLL flag): `os.pread` and `os.open` let go of it, and taking it
    back waited up to 25 ms on a busy machine beside a spinning thread, inside the
    controller's timed answer (`bench/gil_timer_bench.py`).
    Which thread holds the lock at a release is up to the scheduler, so this is checked on
    the call, not timed."""
    import ctypes

    from turtle_traj.node import answer_timer

    for call in (answer_timer._OPEN, answer_timer._PREAD):  # the file opened on each thread
        assert call is not None
        assert call._flags_ & ctypes._FUNCFLAG_PYTHONAPI


def test_a_cpu_wait_as_the_answer_is_timed_is_not_taken_off_the_controllers_time(monkeypatch):
    """The slow controller's 50 ms still read as 50 ms when the thread waits 30 ms for a CPU
    as its answer is timed, inside the excuse's own reading (a loaded full run reported a 1 s
    sleep as 0.996 s: a wait after the clock was read, then excused from the time)."""
    from turtle_traj.node import answer_timer
    reads, waited = [], [0.0]

    def busy_machine() -> float:  # each answer's second reading waits 30 ms for a CPU
        reads.append(None)
        if len(reads) % 2 == 0:
            time.sleep(0.03)
            waited[0] += 0.03
        return waited[0]
    monkeypatch.setattr(answer_timer, 'not_the_controllers_s', busy_machine)
    points, start, plan = _step_course(90)
    run = drive(plan, start, PAPER, inertia=PAPER_INERTIA,
                controller=ControllerChoice('bad', _Slow, TIMER))
    assert _reported_late_s(run.run.ending[1]) >= 0.05


def test_commands_beyond_the_limits_are_clamped_and_counted():
    points, start, plan = _step_course(45)
    run = drive(plan, start, PAPER, inertia=PAPER_INERTIA, max_s=5.0,
                controller=ControllerChoice('reckless', _Reckless))
    follower = run.run.follower
    assert follower.commands > 100 and follower.clamped == follower.commands
    assert _outside_the_limits(run.commands, PAPER.control) == []


def test_an_untimed_choice_lets_a_slow_controller_finish():
    points, start, plan = _step_course(45)
    run = drive(plan, start, PAPER, inertia=PAPER_INERTIA, max_s=0.5,
                controller=ControllerChoice('slow', _Slow))
    assert run.run.ending == (False, 'follow_path still running after 0.5 s')
    assert len(run.commands) == int(0.5 / STEP_S)  # one every step, none refused


# --- choosing by name --------------------------------------------------------------------------

def test_the_shipped_controllers_are_offered_by_name():
    assert names()[:3] == ['exact', 'dwpp', 'pure_pursuit']
    assert resolve('exact') is ExactFollower and choose('exact') == ControllerChoice()
    assert resolve('dwpp') is Dwpp and resolve('pure_pursuit') is PurePursuit
    assert resolve('turtle_traj.core.control.controllers.dwpp:Dwpp') is Dwpp


def test_every_controller_drives_the_plan_through_one_interface():
    """One walker drives every controller, the exact follower a `Controller` like the rest:
    it turns in place at every corner (its strokes are the plan's legs), the others drive
    round them (a square is one stroke)."""
    start = Pose2D(5.0, 5.0, 0.0)
    plan = planner.plan('square', make_request(BY_NAME['square'], {'size': 1.0}), start,
                        DEFAULT_SETTINGS)
    walkers = {name: choose(name).driver(plan, manage_pen=False)
               for name in ('exact', 'dwpp', 'pure_pursuit')}
    for walker in walkers.values():
        assert isinstance(walker, PlanWalker) and isinstance(walker.controller, Controller)
        assert not walker.done and walker.progress(plan.control(DEFAULT_SETTINGS.control)) == 0
    assert walkers['exact'].steps == list(plan.path.legs)
    assert [type(step) for step in walkers['dwpp'].steps] == [Polyline]


class _Recording:
    """Records what the walker hands it, and drives straight on."""

    def start(self, stroke, limits):
        self.stroke, self.limits, self.states = stroke, limits, []

    def command(self, state):
        self.states.append(state)
        return Command(0.5, 0.0)


def test_a_controller_is_handed_what_the_model_of_the_robot_knows():
    """The state carries the model of the robot's prediction (its uncertainty, what the robot
    is), as the exact follower uses it: a user's controller gets what ours gets."""
    start = Pose2D(2.0, 5.0, 0.0)
    plan = planner.plan('move', make_request(BY_NAME['move'], {'distance': 2.0}), start,
                        DEFAULT_SETTINGS)
    recording = _Recording()
    walker = PlanWalker(plan, recording, 'recording')
    predicted = Pose2D(2.01, 5.0, 0.0)
    prediction = Prediction(predicted, Command(0.5, 0.0), late_steps=2, overrun=(0.016, 0.0),
                            standing=False, turns_first=False, braking_overrun=(0.03, 0.0))
    walker.update(start, DEFAULT_SETTINGS.control, prediction)
    state = recording.states[0]
    assert (state.pose, state.measured, state.velocity) == (predicted, start, Command(0.5, 0.0))
    assert state.robot == prediction  # the model's prediction, to ask, as it made it
    assert state.limits.linear_speed == DEFAULT_SETTINGS.control.linear_speed
    assert recording.stroke.tolerance == DEFAULT_SETTINGS.control.position_tolerance
    assert recording.stroke.endless is False and np.allclose(recording.stroke.points[-1],
                                                            (4.0, 5.0))


def test_the_exact_follower_is_tuned_as_any_controller():
    """Its gains are `Tunable`s served under its prefix, as every controller's, and the values
    in effect are set as each stroke starts."""
    assert [spec.name for spec in ControllerChoice().tunables] == [
        'heading_gain', 'cross_track_gain', 'deceleration', 'turn_first_angle']
    assert ControllerChoice().prefix == 'exact'
    start = Pose2D(2.0, 5.0, 0.0)
    plan = planner.plan('move', make_request(BY_NAME['move'], {'distance': 2.0}), start,
                        DEFAULT_SETTINGS)
    tuned = replace(ControllerChoice(),
                    tuning=lambda: {'heading_gain': 3.0, 'cross_track_gain': 7.0})
    walker = tuned.driver(plan, manage_pen=False)
    walker.update(start, DEFAULT_SETTINGS.control)
    assert (walker.controller.heading_gain, walker.controller.cross_track_gain) == (3.0, 7.0)


class _NoCommand:
    def start(self, stroke, limits):
        pass


@pytest.mark.parametrize(('name', 'said'), [
    ('magic', "controller 'magic' is unknown: choose one of exact, dwpp, pure_pursuit"),
    ('no_such_module:Controller', "cannot be loaded: ModuleNotFoundError: No module named "
                                  "'no_such_module'"),
    ('turtle_traj.core.control.controllers.dwpp:Missing', "cannot be loaded: AttributeError"),
    ('tests.test_controllers:_NoCommand', 'tests.test_controllers._NoCommand has no command '
                                          'method: a controller needs start(stroke, limits) and '
                                          'command(state)'),
    ('tests.test_controllers:_CannotBeMade', 'cannot be loaded: RuntimeError: no licence'),
    ('math:pi', 'is not a class'),
])
def test_a_name_that_is_not_a_controller_is_refused_with_the_reason(name, said):
    with pytest.raises(UnknownController) as refused:
        resolve(name)
    assert said in str(refused.value)


def test_the_interface_check_accepts_any_class_with_the_two_methods():
    class Minimal:
        def start(self, stroke, limits):
            pass

        def command(self, state):
            return None
    assert interface_problem(Minimal) is None
    assert 'not a class' in interface_problem(Minimal())


class Installed(Dwpp):
    """A controller another package installs, offered by name through its entry point."""


def test_a_controller_installed_as_an_entry_point_is_offered_by_its_name(tmp_path, monkeypatch):
    info = tmp_path / 'someones_controllers-1.0.dist-info'
    info.mkdir()
    (info / 'METADATA').write_text('Metadata-Version: 2.1\nName: someones-controllers\n'
                                   'Version: 1.0\n')
    (info / 'entry_points.txt').write_text('[turtle_traj.controllers]\n'
                                           'theirs = tests.test_controllers:Installed\n')
    monkeypatch.syspath_prepend(str(tmp_path))
    assert 'theirs' in names()
    assert resolve('theirs') is Installed
    assert choose('theirs') == ControllerChoice('theirs', Installed)


@pytest.mark.parametrize('radius', [0.5, 1.0])
def test_from_rest_the_exact_follower_turns_into_a_circle_at_its_curvature(radius):
    """A circle started from rest on a base with inertia: the end chord turns as the arc does
    (`Polyline.tangent_curvatures`), so the base turns at the circle's rate as it speeds up.
    With the chord's half curvature there it started too straight, 0.53-0.58 mm outside."""
    start = Pose2D(4.0, 5.0, math.pi / 2)
    plan = planner.plan('circle', shape(size=radius), start, PAPER)
    run = drive(plan, start, PAPER, inertia=PAPER_INERTIA)
    assert run.run.ending == (True, 'circle done')
    worst = distance_to_polyline(run.xy(), plan.path.points()).max()
    assert worst < 0.3e-3, worst


def test_on_a_curve_the_exact_follower_holds_a_steady_turn_rate_within_the_limits():
    """On a base with acceleration limits, the exact follower steers to a curve's tangent as it
    turns along each chord: the turn rate settles instead of beating against its limit at every
    vertex of the sampled curve (which cost millimetres and time on the MuJoCo base)."""
    start = Pose2D(4.0, 5.0, math.pi / 2)
    plan = planner.plan('circle', shape(size=1.0), start, PAPER)
    run = drive(plan, start, PAPER, inertia=PAPER_INERTIA)
    assert run.run.ending == (True, 'circle done')
    turn_rates = np.array([command.angular for command in run.commands])
    middle = turn_rates[len(turn_rates) // 4: 3 * len(turn_rates) // 4]  # at speed, on the arc
    window = PAPER.control.max_angular_accel * PAPER.control.period_s
    at_the_limit = np.abs(np.diff(middle)) >= 0.99 * window
    assert at_the_limit.mean() < 0.01, at_the_limit.mean()
    assert np.ptp(middle) < 0.1 * np.mean(np.abs(middle))


@pytest.mark.parametrize(('decel', 'braking'), [(0.0, 0.5), (2.0, 2.0)])
def test_dwpp_brakes_within_the_deceleration_the_node_clamps_with(decel, braking):
    """Limits carry max_linear_decel (0: the acceleration limit); DWPP's window slows down by
    that much a period, and speeds up by the acceleration limit."""
    config = replace(DEFAULT_SETTINGS.control, max_linear_accel=0.5, max_angular_accel=1.0,
                     max_linear_decel=decel)
    limits = config.limits
    assert limits.linear_braking == braking
    controller = Dwpp()
    controller.start(Stroke(np.array([(0.0, 0.0), (0.05, 0.0)])), limits)
    moving = Pose2D(0.04, 0.0, 0.0)  # 1 cm before the end at 0.5 m/s: it must brake hard
    command = controller.command(State(Prediction(moving, Command(0.5, 0.0)), moving, 1.0, limits))
    assert command.linear == pytest.approx(0.5 - braking * config.period_s)



def test_a_turn_of_no_sweep_is_made_as_soon_as_it_begins():
    """A go-to asked to end in the heading it drives in ends with such a turn; the supervisor
    reads how much of it is made on every tick (it divided by the sweep)."""
    from turtle_traj.core.control.trackers import TurnTracker
    from turtle_traj.core.geometry.path import Pose2D, Turn

    tracker = TurnTracker(Turn(7.5, 5.5, 0.25, 0.0), Pose2D(7.5, 5.5, 0.25))
    assert tracker.fraction == 1.0

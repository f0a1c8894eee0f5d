"""The model of the robot (pure): which commands are in flight, how long each acts, where they
take the turtle, and how uncertain that is. Predictions are checked against the simulator's own
physics (`sim.physics.World`)."""

import math

import numpy as np
import pytest

from turtle_traj.core.control.commands import STOP, Command
from turtle_traj.core.control.observers import ODOMETRY_BASE
from turtle_traj.core.control.quantile import RunningQuantile, WindowQuantile
from turtle_traj.core.control.robot_model import BRAKING_WINDOW, RATE, RobotModel
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.sim.physics import World

COMMANDS = [Command(1.0, 0.5), Command(0.8, -1.0), Command(0.6, 2.0), Command(0.3, 0.1)]


def _echo(command: Command) -> tuple[float, float]:
    """What a turtlesim pose reports for a command in effect (float32, speed as magnitude)."""
    return float(np.float32(abs(command.linear))), float(np.float32(command.angular))


def _send(model: RobotModel, commands, start_step: int = 0) -> None:
    """Send `commands` one step apart (node clock)."""
    for index, command in enumerate(commands):
        model.sent(command, (start_step + index) * STEP_S)


@pytest.mark.parametrize('in_effect', range(len(COMMANDS)))
def test_the_echo_tells_how_many_commands_are_in_flight(in_effect):
    model = RobotModel(STEP_S)
    _send(model, COMMANDS)
    model.observe(*_echo(COMMANDS[in_effect]))
    assert model.in_flight == len(COMMANDS) - 1 - in_effect


def test_an_echo_of_nothing_sent_means_everything_is_in_flight():
    model = RobotModel(STEP_S)
    _send(model, COMMANDS[:2])
    model.observe(0.0, 0.0)
    assert model.in_flight == 2


def test_a_foreign_echo_mid_run_is_a_step_on():
    model = RobotModel(STEP_S)
    _send(model, [Command(1.0, 0.0)] * 10)
    model.observe(*_echo(Command(1.0, 0.0)))
    assert model.in_flight == 9  # nothing taken before: the first of the alike ones
    _send(model, [Command(1.0, 0.0)], 10)
    model.observe(0.7, 0.3)  # not ours: e.g. a stale command
    assert model.in_flight == 9  # a step passed: the next is taken to act, one more was sent
    model.observe(*_echo(Command(1.0, 0.0)))
    assert model.in_flight == 8


def test_a_standing_turtle_stands_as_before_until_a_command_shows():
    """Poses late at the start of a run (a busy executor) still show the turtle standing as
    it stood: the stop sent after the moving commands cannot be in effect before they were."""
    model = RobotModel(STEP_S)
    _send(model, [Command(1.0, 0.0), Command(0.9, 0.0), STOP])
    model.observe(0.0, 0.0)
    assert model.in_flight == 3
    model.observe(*_echo(Command(1.0, 0.0)))
    assert model.in_flight == 2


def test_alike_commands_match_one_step_on_never_an_older_one():
    model = RobotModel(STEP_S)
    _send(model, [Command(0.5, 0.0), Command(1.0, 0.0), Command(1.0, 0.0)])
    model.observe(*_echo(Command(0.5, 0.0)))
    assert model.in_flight == 2
    _send(model, [Command(1.0, 0.0)], 3)
    model.observe(*_echo(Command(1.0, 0.0)))
    assert model.in_flight == 2  # the one after the 0.5 m/s: one step on, not the newest
    _send(model, [Command(1.0, 0.0)], 4)
    model.observe(*_echo(Command(1.0, 0.0)))
    assert model.in_flight == 2  # one step on again: never back to an older alike one


@pytest.mark.parametrize('in_flight', [0, 1, 2, 3])
@pytest.mark.parametrize('theta', [0.0, 3.1, -3.1])
def test_prediction_matches_the_simulator_physics(in_flight, theta):
    world = World()
    turtle = world.spawn(5.0, 5.0, theta)
    model = RobotModel(STEP_S)
    _send(model, COMMANDS)
    acted = COMMANDS[:len(COMMANDS) - in_flight]
    for command in acted:
        world.command(turtle.name, command.linear, 0.0, command.angular)
        world.step()
    now = Pose2D(turtle.x, turtle.y, turtle.theta)
    model.observe(*_echo(acted[-1]) if acted else (0.0, 0.0))
    for command in COMMANDS[len(acted):]:
        world.command(turtle.name, command.linear, 0.0, command.angular)
        world.step()
    predicted = model.predict(now, len(COMMANDS) * STEP_S).pose
    assert (predicted.x, predicted.y) == pytest.approx((turtle.x, turtle.y), abs=1e-9)
    assert math.remainder(predicted.theta - turtle.theta, math.tau) == pytest.approx(0.0,
                                                                                     abs=1e-7)


@pytest.mark.parametrize('gaps', [(1, 3, 1), (4, 1, 2), (1, 1, 6)])
def test_a_command_acts_until_the_next_one_is_sent(gaps):
    """A busy executor fires the control timer late: the command before acts on, and the
    robot steps every period with it. The stamps say for how many steps."""
    world = World()
    turtle = world.spawn(5.0, 5.0, 0.5)
    model = RobotModel(STEP_S)
    model.sent(COMMANDS[0], 0.0)
    world.command(turtle.name, COMMANDS[0].linear, 0.0, COMMANDS[0].angular)
    world.step()
    now = Pose2D(turtle.x, turtle.y, turtle.theta)
    model.observe(*_echo(COMMANDS[0]))
    stamp = 0
    for command, gap in zip(COMMANDS[1:], gaps, strict=True):
        stamp += gap
        model.sent(command, stamp * STEP_S)  # sent `gap` steps after the one before
    for _ in range(gaps[0] - 1):  # the first command acts on meanwhile
        world.step()
    for command, acts in zip(COMMANDS[1:], [*gaps[1:], 1], strict=True):
        world.command(turtle.name, command.linear, 0.0, command.angular)
        for _ in range(acts):
            world.step()
    # the last one acts until the next command, computed now, one step after it was sent
    predicted = model.predict(now, (stamp + 1) * STEP_S).pose
    assert (predicted.x, predicted.y) == pytest.approx((turtle.x, turtle.y), abs=1e-9)


def _through_a_link(model: RobotModel, commands: list[Command], delays: list[int]) -> None:
    """Send one command a step; command i arrives `delays[i]` steps later, and the robot takes
    the oldest arrived one at each step (one a step, in order) and echoes it in its pose."""
    taken = -1
    for step, command in enumerate(commands):
        model.sent(command, step * STEP_S)
        if taken + 1 < len(commands) and taken + 1 <= step - delays[taken + 1]:
            taken += 1
        model.observe(*(_echo(commands[taken]) if taken >= 0 else (0.0, 0.0)))


def _distinct_commands(count: int, first: float = 0.1) -> list[Command]:
    return [Command(first + 0.001 * k, 0.0) for k in range(count)]


def _misses(ticks: np.ndarray, delay: float) -> tuple[np.ndarray, np.ndarray]:
    """Drive the simulator's physics through a link, the robot stepping at whole times and the
    node ticking at `ticks` (in steps): each tick predicts and sends a command, which arrives
    `delay` steps later; the robot takes the oldest arrived at each step (one a step, in order)
    and echoes it in the pose it publishes. For each command that took effect: how far the
    robot was, when it did, from where the model predicted, and the overrun it allowed."""
    world = World()
    turtle = world.spawn(5.0, 5.0, 0.0)
    model = RobotModel(STEP_S)
    sent: list[tuple[Command, Pose2D, float, float]] = []  # command, prediction, overrun, due
    taken, in_effect, misses, allowed = 0, None, [], []
    for step in range(int(ticks[-1]) + 10):
        for tick in ticks[(ticks >= step) & (ticks < step + 1)]:
            pose = Pose2D(turtle.x, turtle.y, turtle.theta)
            model.ticked(tick * STEP_S)
            prediction = model.predict(pose, tick * STEP_S)
            index = len(sent)
            command = model.distinct(Command(0.5 + 0.4 * math.sin(index / 9.0),
                                             1.5 * math.cos(index / 7.0)))
            model.sent(command, tick * STEP_S)
            sent.append((command, prediction.pose, prediction.overrun[0], tick + delay))
        if taken < len(sent) and sent[taken][3] <= step + 1:  # the robot's step, at step + 1
            in_effect, taken = taken, taken + 1
            _command, predicted, overrun, _due = sent[in_effect]
            misses.append(math.dist((turtle.x, turtle.y), (predicted.x, predicted.y)))
            allowed.append(overrun)
        if in_effect is not None:
            command = sent[in_effect][0]
            world.command(turtle.name, command.linear, 0.0, command.angular)
        world.step()
        model.observe(*(_echo(sent[in_effect][0]) if in_effect is not None else (0.0, 0.0)))
    return np.array(misses), np.array(allowed)


def test_a_steady_latency_is_predicted_exactly():
    misses, allowed = _misses(np.arange(400) + 0.5, 2.2)
    assert misses[10:].max() < 1e-9 and allowed.max() == 0.0


def test_a_jittery_timer_is_hedged_and_the_hedge_covers_what_happens():
    """The node's timer fires up to 0.8 steps early or late: some steps take no new command
    (the one before acts on), some two (one waits). The prediction is the soonest arrival,
    and the overrun it allows covers a later one for most commands."""
    jitter = np.random.default_rng(7).uniform(-0.8, 0.8, 600)
    ticks = np.maximum.accumulate(np.arange(600) + 0.5 + jitter)
    misses, allowed = _misses(ticks, 2.2)
    assert allowed[100:].min() > 0.0  # the jitter is learnt: every approach is hedged
    assert np.mean(misses[100:] <= allowed[100:] + 1e-9) >= 0.95


def test_a_spike_seen_once_does_not_slow_what_follows():
    """A stall (a cut link, a stalled executor) is one observation among many: it moves a
    running quantile by a fraction of a step, which the next observations take back."""
    model = RobotModel(STEP_S)
    commands = _distinct_commands(400)
    _through_a_link(model, commands, [1] * 200 + [25] + [1] * 199)
    assert model.predict(Pose2D(1.0, 1.0, 0.0), 400 * STEP_S).late_steps == 0
    # the control timer late once: the command before acted 20 steps; then one each
    for tick in [*range(400), *range(420, 470)]:
        model.ticked(tick * STEP_S)
    assert model.predict(Pose2D(1.0, 1.0, 0.0), 470 * STEP_S).late_steps == 0


def test_one_late_command_makes_a_braking_at_the_limit_allow_for_a_step():
    """One command among 400 acts a step late (the ones after it wait a step: a queue of
    one). Too rare for a turtle's approach, whose last command alone lands; a base's braking
    is all of its approach, and allows for a step, until 6400 commands have acted on time."""
    model = RobotModel(STEP_S)
    commands = _distinct_commands(400)
    _through_a_link(model, commands, [1] * 200 + [2] + [1] * 199)
    prediction = model.predict(Pose2D(1.0, 1.0, 0.0), 400 * STEP_S)
    assert prediction.late_steps == 0 and prediction.overrun == (0.0, 0.0)
    assert prediction.braking_overrun == (pytest.approx(commands[-1].linear * STEP_S), 0.0)
    assert prediction.overrun_when(limited=False) == prediction.overrun
    assert prediction.overrun_when(limited=True) == prediction.braking_overrun
    for after, hedged in ((BRAKING_WINDOW - 5, True), (BRAKING_WINDOW + 5, False)):
        model = RobotModel(STEP_S)
        count = 201 + after
        _through_a_link(model, _distinct_commands(count, first=0.01),
                        [1] * 200 + [2] + [1] * after)
        overrun = model.predict(Pose2D(1.0, 1.0, 0.0), count * STEP_S).braking_overrun
        assert (overrun[0] > 0.0) == hedged


@pytest.mark.parametrize('window', [1, 5, 64])
def test_a_window_quantile_is_the_largest_of_the_last_observations(window):
    observed = np.random.default_rng(window).integers(-3, 4, 300).astype(float)
    quantile = WindowQuantile(window)
    assert quantile.value is None and quantile.whole(default=2) == 2
    for count, value in enumerate(observed, start=1):
        quantile.add(value)
        assert quantile.value == observed[max(count - window, 0):count].max()


def _lossy_link(model: RobotModel, steps: int, lossy_steps: int, lost_every: int) -> None:
    """A command a step, unless the model says some are overdue (as the control loop does);
    each arrives a step after it is sent, but for the first `lossy_steps` every
    `lost_every`-th is repaired a step later and those sent after it wait for it (reliable
    delivery is in order). The robot takes the oldest arrived each step and echoes it."""
    sent, arrives, taken = [], [], -1
    for step in range(steps):
        if model.excess == 0:
            command = Command(0.1 + 0.0001 * len(sent), 0.0)
            model.sent(command, step * STEP_S)
            late = step < lossy_steps and len(sent) % lost_every == lost_every - 1
            arrives.append(max(step + 1 + late, arrives[-1] if arrives else 0))
            sent.append(command)
        if taken + 1 < len(sent) and arrives[taken + 1] <= step:
            taken += 1
        model.observe(*(_echo(sent[taken]) if taken >= 0 else (0.0, 0.0)))


def test_loss_that_lasts_makes_the_approach_wary_and_clean_driving_takes_it_back():
    """A lossy link: one command in forty repaired a step late. Too rare for the 95th
    percentile, it is in the 99th, which the approach allows for; clean driving forgets it."""
    lossy = RobotModel(STEP_S)
    _lossy_link(lossy, 800, lossy_steps=800, lost_every=40)
    assert lossy.predict(Pose2D(1.0, 1.0, 0.0), 800 * STEP_S).late_steps == 1
    assert lossy.excess == 0  # the queue each loss left has drained
    cleaned = RobotModel(STEP_S)
    _lossy_link(cleaned, 1100, lossy_steps=800, lost_every=40)
    assert cleaned.predict(Pose2D(1.0, 1.0, 0.0), 1100 * STEP_S).late_steps == 0


def test_a_timer_that_is_often_late_makes_the_approach_wary():
    model = RobotModel(STEP_S)
    stamp = 0
    for index, command in enumerate(_distinct_commands(100)):
        stamp += 3 if index % 4 == 0 else 1  # every fourth tick comes two steps late
        model.ticked(stamp * STEP_S)
        model.sent(command, stamp * STEP_S)
    assert model.predict(Pose2D(1.0, 1.0, 0.0), (stamp + 1) * STEP_S).late_steps == 2


def test_the_timer_is_learnt_before_the_first_command():
    """A busy executor delays the control timer while no run is driven too: the first
    command of a run is already sent with its hedge."""
    model = RobotModel(STEP_S)
    for tick in range(0, 200, 4):  # every fourth step
        model.ticked(tick * STEP_S)
    assert model.predict(Pose2D(1.0, 1.0, 0.0), 200 * STEP_S).late_steps == 3


def test_a_running_quantile_settles_where_its_share_lies_below():
    high = RunningQuantile(0.95, RATE)
    assert high.value is None and high.whole(7) == 7
    for index in range(2000):
        high.add(2 if index % 50 else 5)  # 2% of fives
    assert high.whole() == 2
    for index in range(2000):
        high.add(2 if index % 10 else 5)  # 10% of fives
    assert high.whole() == 5
    low = RunningQuantile(0.05, RATE)
    for index in range(2000):
        low.add(2 if index % 10 else 5)
    assert low.whole() == 2


def test_standing_only_at_rest_with_nothing_but_stops_on_their_way():
    model = RobotModel(STEP_S)
    _send(model, [Command(0.5, 0.0), STOP, STOP])
    for _ in range(3):
        model.observe(*_echo(Command(0.5, 0.0)))
    pose = Pose2D(1.0, 1.0, 0.0)
    assert not model.predict(pose, 3 * STEP_S).standing  # the 0.5 m/s command is in effect
    model.sent(STOP, 3 * STEP_S)
    model.observe(0.0, 0.0)
    assert model.predict(pose, 4 * STEP_S).standing
    model.sent(Command(0.0, 1.0), 4 * STEP_S)
    model.observe(0.0, 0.0)
    assert not model.predict(pose, 5 * STEP_S).standing  # a turn is on its way


@pytest.mark.parametrize('command', [Command(1.0, 0.0), Command(-0.7, 0.3), Command(0.0, -2.0)])
def test_alike_commands_are_made_smaller_by_float32_steps_until_each_echo_is_unique(command):
    model = RobotModel(STEP_S)
    sent = []
    for step in range(40):
        sent.append(model.distinct(command))
        model.sent(sent[-1], step * STEP_S)
    echoes = [_echo(each) for each in sent]
    assert len(set(echoes[-32:])) == 32  # each echo names one command of those remembered
    for each in sent:
        assert each.linear == pytest.approx(command.linear, rel=4e-6, abs=0.0)
        assert each.angular == pytest.approx(command.angular, rel=4e-6, abs=0.0)
        assert math.copysign(1, each.linear) == math.copysign(1, command.linear)
        # smaller, never larger: a command at a limit stays within it
        assert abs(each.linear) <= abs(command.linear)
        assert abs(each.angular) <= abs(command.angular)
    # the echo of a command now in effect names it, whatever came after
    model.observe(*_echo(sent[-5]))
    assert model.in_flight == 4


def test_a_stop_is_never_nudged_and_odometry_needs_no_nudging():
    model = RobotModel(STEP_S)
    for step in range(3):
        model.sent(model.distinct(STOP), step * STEP_S)
    assert model.distinct(STOP) == STOP
    odometry = RobotModel(STEP_S, robot=ODOMETRY_BASE)
    for step in range(3):
        odometry.sent(odometry.distinct(Command(1.0, 0.0)), step * STEP_S)
    assert odometry.distinct(Command(1.0, 0.0)) == Command(1.0, 0.0)
    odometry.observe(0.3, 0.0)  # a measured velocity names no command, and no latency is
    assert odometry.in_flight == 0  # known yet: none is taken to be in flight


def _base_with_delay(delay: int, commands: list[Command]) -> RobotModel:
    """A base that acts on each command `delay` steps after it was sent, one command a step,
    its odometry (pose and measured velocity) observed after every step."""
    model = RobotModel(STEP_S, robot=ODOMETRY_BASE)
    world = World()
    base = world.spawn(5.0, 5.0, 0.0)
    for step, command in enumerate(commands):
        model.ticked(step * STEP_S)
        model.sent(command, step * STEP_S)
        acting = commands[step - delay] if step >= delay else STOP
        world.command(base.name, acting.linear, 0.0, acting.angular)
        world.step()
        model.observe(abs(acting.linear), acting.angular,
                      Pose2D(base.x, base.y, base.theta))
    return model


@pytest.mark.parametrize('delay', [0, 3, 7])
def test_odometry_gives_the_latency_that_explains_the_motion(delay):
    """Commands that vary (a weave) tell every latency apart: the fitted one is the delay,
    and the commands in flight are the ones sent since the one due."""
    weave = [Command(0.2 + 0.1 * math.sin(k / 5), 1.5 * math.sin(k / 4)) for k in range(120)]
    model = _base_with_delay(delay, weave)
    assert model.in_flight == delay
    pose = Pose2D(1.0, 1.0, 0.0)
    predicted = model.predict(pose, 120 * STEP_S).pose
    world = World()  # the commands in flight, replayed on the physics from `pose`
    base = world.spawn(1.0, 1.0, 0.0)
    for command in weave[len(weave) - delay:]:
        world.command(base.name, command.linear, 0.0, command.angular)
        world.step()
    assert (predicted.x, predicted.y) == pytest.approx((base.x, base.y), abs=1e-9)


def test_odometry_on_one_command_tells_no_latency():
    model = _base_with_delay(3, [Command(0.2, 0.5)] * 60)
    assert model.in_flight == 0  # cruising fits every latency alike: none learnt


def test_a_stop_sent_after_moving_commands_is_not_what_a_standing_turtle_stands_on():
    """Start of a run on a slow link: the turtle stands while the commands are on their way.
    The stop sent after them echoes as the standing turtle does, but commands act in order:
    the turtle is on the stop before them, all of them are still in flight, and no latency is
    learnt."""
    model = RobotModel(STEP_S)
    model.sent(STOP, 0.0)
    model.observe(0.0, 0.0)
    moving = [Command(1.0 - 0.01 * k, 0.0) for k in range(10)]
    _send(model, [*moving, STOP], 1)
    for _ in range(3):
        model.observe(0.0, 0.0)
        assert model.in_flight == 11
    prediction = model.predict(Pose2D(1.0, 1.0, 0.0), 12 * STEP_S)
    assert prediction.late_steps == 0 and not prediction.standing
    assert prediction.pose.x == pytest.approx(1.0 + sum(c.linear for c in moving) * STEP_S)
    model.observe(*_echo(moving[0]))  # the first one acts at last
    assert model.in_flight == 10
    for command in moving[1:]:  # then each in turn, then the stop: the turtle stands on it
        model.observe(*_echo(command))
    model.observe(0.0, 0.0)
    assert model.in_flight == 0 and model.predict(Pose2D(1.0, 1.0, 0.0), 13 * STEP_S).standing


def test_the_loop_is_at_rest_when_the_model_is_as_each_robot_tells_it():
    """One judgement of rest for the run's settling and the model's prediction, from the
    robot's description: turtlesim stands at zero only; a base within what its odometry
    resolves (`MEASURED_STILL`); only turtlesim's step turns first."""
    from turtle_traj.core.control.loop import ControlLoop
    from turtle_traj.core.control.observers import MEASURED_STILL

    odometry = ControlLoop(STEP_S, robot=ODOMETRY_BASE)
    creeping = (0.4 * MEASURED_STILL[0], 0.4 * MEASURED_STILL[1])
    odometry.observe(Pose2D(1.0, 1.0, 0.0), *creeping)
    assert odometry.at_rest and odometry.model.at_rest
    odometry.observe(Pose2D(1.0, 1.0, 0.0), 2.0 * MEASURED_STILL[0], 0.0)
    assert not odometry.at_rest
    turtlesim = ControlLoop(STEP_S)
    turtlesim.observe(Pose2D(1.0, 1.0, 0.0), *creeping)
    assert not turtlesim.at_rest
    turtlesim.observe(Pose2D(1.0, 1.0, 0.0), 0.0, 0.0)
    assert turtlesim.at_rest
    # what the robot is, told by its description, not by how it is sensed
    pose = Pose2D(1.0, 1.0, 0.0)
    assert turtlesim.model.predict(pose, 0.0).turns_first
    assert not odometry.model.predict(pose, 0.0).turns_first


def _square_with_the_first_stop_late(late_prior: float):
    """A 0.5 m square on turtlesim, its first stop after moving acting a step late (the
    sending process stalled at the first corner), from a control loop with `late_prior`:
    its largest distance from the square (m) and its time (s)."""
    from turtle_traj.apps.score.loop import drive
    from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
    from turtle_traj.core.planning import planner
    from turtle_traj.testing.geometry import distance_to_polyline
    from turtle_traj.testing.pure_loop import shape

    start = Pose2D(5.544, 5.544, 0.0)
    plan = planner.plan('square', shape(size=0.5), start, DEFAULT_SETTINGS)
    moved, late = [False], []

    def first_stop_after_moving(step: int, command: Command) -> bool:
        moved[0] = moved[0] or command.linear != 0.0
        if moved[0] and command == STOP and not late:
            late.append(step)
            return True
        return False

    record = drive(plan, start, DEFAULT_SETTINGS, late_if=first_stop_after_moving,
                   late_prior=late_prior)
    assert record.run.ending[0] and late, record.run.ending
    corners = np.array([[5.544, 5.544], [6.044, 5.544], [6.044, 6.044], [5.544, 6.044],
                        [5.544, 5.544]])
    return float(distance_to_polyline(record.xy(), corners).max()), record.steps * STEP_S


def test_a_cold_start_allows_for_a_late_command_at_the_first_corner():
    """Before the link's timing is seen (`COLD_START_LATE_STEPS`), the approach to the first
    corner allows for a command a step late: a stop that acts late leaves the turtle within
    a millimetre. Without that allowance the last command of the approach acts a step longer
    and carries it millimetres past the corner. The allowance costs about a quarter of a
    second a corner (the approach stops short, stands, then lands)."""
    from turtle_traj.core.control.robot_model import COLD_START_LATE_STEPS

    brisk_m, brisk_s = _square_with_the_first_stop_late(0.0)
    wary_m, wary_s = _square_with_the_first_stop_late(COLD_START_LATE_STEPS)
    assert brisk_m > 0.002
    assert wary_m < 0.001
    assert brisk_s < wary_s <= brisk_s + 4 * 0.3


def test_the_cold_start_allowance_fades_as_commands_act_on_time():
    """It counts as a stall seen: each command seen acting on time takes back a share, and
    after about 200 of them (3 s of driving) the approach is brisk again."""
    from turtle_traj.core.control.robot_model import COLD_START_LATE_STEPS

    pose = Pose2D(1.0, 1.0, 0.0)
    assert RobotModel(STEP_S).predict(pose, 0.0).late_steps == 0
    fading = [RobotModel(STEP_S, late_prior=COLD_START_LATE_STEPS) for _ in range(2)]
    assert fading[0].predict(pose, 0.0).late_steps == 1
    for model, count in zip(fading, (150, 250), strict=True):
        _through_a_link(model, _distinct_commands(count), [1] * count)
        model.ticked(count * STEP_S)
    assert [model.predict(pose, 250 * STEP_S).late_steps for model in fading] == [1, 0]


def test_the_echo_index_names_the_commands_remembered_and_forgets_the_oldest():
    """`echoes` is the commands remembered grouped by echo, their numbers oldest first, also as
    the history's oldest are forgotten (a steady circle's commands, moved apart by `distinct`,
    among stops and repeats)."""
    model = RobotModel(STEP_S)
    steady = Command(1.0, 2.0)
    for step in range(100):
        wanted = STOP if step % 7 == 0 else steady
        model.sent(model.distinct(wanted) if step % 3 else wanted, step * STEP_S)
        grouped: dict[tuple[float, float], list[int]] = {}
        for number, sent in enumerate(model.remembered, start=model.first):
            grouped.setdefault(sent.echo, []).append(number)
        assert model.echoes == grouped
    assert len(model.remembered) == 32 and model.first == 68

"""Latency compensation (pure): which commands are in flight, and where they take the turtle."""

import math

import numpy as np
import pytest

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.latency import LatencyPredictor
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.sim.delay import CommandDelay
from turtle_traj.sim.physics import World

COMMANDS = [Command(1.0, 0.5), Command(0.8, -1.0), Command(0.6, 2.0), Command(0.3, 0.1)]


def _echo(command: Command) -> tuple[float, float]:
    """What a turtlesim pose reports for a command in effect (float32, speed as magnitude)."""
    return float(np.float32(abs(command.linear))), float(np.float32(command.angular))


@pytest.mark.parametrize('in_effect', range(len(COMMANDS)))
def test_the_echo_tells_how_many_commands_are_in_flight(in_effect):
    predictor = LatencyPredictor(STEP_S)
    for command in COMMANDS:
        predictor.sent(command)
    assert predictor.observe(*_echo(COMMANDS[in_effect])) == len(COMMANDS) - 1 - in_effect


def test_an_echo_of_nothing_sent_means_everything_is_in_flight():
    predictor = LatencyPredictor(STEP_S)
    for command in COMMANDS[:2]:
        predictor.sent(command)
    assert predictor.observe(0.0, 0.0) == 2


def test_a_foreign_echo_mid_run_keeps_the_count():
    predictor = LatencyPredictor(STEP_S)
    for _ in range(10):
        predictor.sent(Command(1.0, 0.0))
    assert predictor.observe(*_echo(Command(1.0, 0.0))) == 0
    predictor.sent(Command(1.0, 0.0))
    assert predictor.observe(0.7, 0.3) == 0  # not ours: e.g. a stale command
    predictor.sent(Command(1.0, 0.0))
    assert predictor.observe(*_echo(Command(1.0, 0.0))) == 0


def test_identical_commands_keep_the_previous_count():
    predictor = LatencyPredictor(STEP_S)
    for command in [Command(0.5, 0.0), Command(1.0, 0.0), Command(1.0, 0.0)]:
        predictor.sent(command)
    assert predictor.observe(*_echo(Command(0.5, 0.0))) == 2
    predictor.sent(Command(1.0, 0.0))
    assert predictor.observe(*_echo(Command(1.0, 0.0))) == 2  # not 0: the nearest match


@pytest.mark.parametrize('in_flight', [0, 1, 2, 3])
@pytest.mark.parametrize('theta', [0.0, 3.1, -3.1])
def test_prediction_matches_the_simulator_physics(in_flight, theta):
    world = World()
    turtle = world.spawn(5.0, 5.0, theta)
    predictor = LatencyPredictor(STEP_S)
    for command in COMMANDS:
        predictor.sent(command)
    acted = COMMANDS[:len(COMMANDS) - in_flight]
    for command in acted:
        world.command(turtle.name, command.linear, 0.0, command.angular)
        world.step()
    now = Pose2D(turtle.x, turtle.y, turtle.theta)
    predictor.observe(*_echo(acted[-1]) if acted else (0.0, 0.0))
    for command in COMMANDS[len(acted):]:
        world.command(turtle.name, command.linear, 0.0, command.angular)
        world.step()
    predicted = predictor.predict(now)
    assert (predicted.x, predicted.y) == pytest.approx((turtle.x, turtle.y), abs=1e-9)
    assert math.remainder(predicted.theta - turtle.theta, math.tau) == pytest.approx(0.0,
                                                                                     abs=1e-7)


def test_command_delay_holds_commands_in_order():
    delay = CommandDelay(0.032, 0.05, seed=3)
    for index in range(20):
        delay.push(index * STEP_S, 'turtle1', index)
    released = []
    for step in range(200):
        released += [message for _turtle, message in delay.due(step * STEP_S)]
        if step * STEP_S < 0.032:
            assert not released
    assert released == list(range(20))


def test_command_delay_off_by_default_and_fixed_delay_is_exact():
    assert not CommandDelay(0.0, 0.0).active
    delay = CommandDelay(0.032, 0.0)
    delay.push(1.0, 'turtle1', 'go')
    assert list(delay.due(1.016)) == []
    assert list(delay.due(1.032)) == [('turtle1', 'go')]


def test_commands_queued_for_a_removed_turtle_are_dropped():
    delay = CommandDelay(0.032, 0.0)
    delay.push(0.0, 'turtle1', 'old')
    delay.push(0.0, 'turtle2', 'other')
    delay.drop('turtle1')
    assert list(delay.due(1.0)) == [('turtle2', 'other')]


def _drive(predictor: LatencyPredictor, commands: list[Command], in_flight: list[int]) -> None:
    """Send each command, then observe the echo of the one `in_flight[i]` sends back."""
    sent: list[Command] = []
    for command, behind in zip(commands, in_flight, strict=True):
        predictor.sent(command)
        sent.append(command)
        predictor.observe(*(_echo(sent[-1 - behind]) if behind < len(sent) else (0.0, 0.0)))


def test_a_steady_latency_has_no_spread_and_a_varying_one_has():
    commands = [Command(0.1 * k, 0.0) for k in range(1, 11)]  # all distinct
    steady = LatencyPredictor(STEP_S)
    _drive(steady, commands, [2] * 10)
    assert steady.in_flight == 2 and steady.spread == 0
    jittery = LatencyPredictor(STEP_S)
    _drive(jittery, commands, [0, 1, 2, 1, 0, 1, 2, 3, 1, 0])
    assert jittery.spread == 3
    # The newest command (1.0 m/s) may act three periods longer than predicted.
    assert steady.overrun() == (0.0, 0.0)
    assert jittery.overrun() == pytest.approx((1.0 * 3 * STEP_S, 0.0))


def test_the_spread_outlasts_standing_still_and_is_forgotten_when_the_link_returns():
    from turtle_traj.core.control.latency import _SPREAD_WINDOW
    commands = [Command(0.1 * k, 0.0) for k in range(1, 11)]
    jittery = LatencyPredictor(STEP_S)
    _drive(jittery, commands, [0, 1, 2, 1, 0, 1, 2, 3, 1, 0])
    for _ in range(2 * _SPREAD_WINDOW):  # standing: the stops in effect tell no latency
        jittery.sent(Command(0.0, 0.0))
        jittery.observe(0.0, 0.0)
    assert jittery.spread == 3  # the link is what it was when the turtle last drove
    jittery.forget_spread()
    assert jittery.spread == 0 and jittery.overrun() == (0.0, 0.0) and jittery.backlog == 0
    _drive(jittery, [Command(2.0 + 0.1 * k, 0.0) for k in range(5)], [1, 1, 2, 1, 1])
    assert jittery.spread == 1  # judged afresh from the poses since


def test_a_command_later_than_its_lifespan_is_a_stall_not_jitter():
    from turtle_traj.core.control.commands import COMMAND_LIFESPAN_S
    stall = round(COMMAND_LIFESPAN_S / STEP_S)
    commands = [Command(0.01 * k, 0.0) for k in range(1, 31)]
    predictor = LatencyPredictor(STEP_S)
    # The link returns from a cut: the turtle still acts on a command sent before it.
    _drive(predictor, commands, [1] * 19 + [1 + stall + 1] + [1] * 10)
    assert predictor.spread == 0  # the stall was not remembered: approaches stay brisk
    within = LatencyPredictor(STEP_S)
    _drive(within, commands, [1] * 19 + [1 + stall] + [1] * 10)
    assert within.spread == stall  # a latency within the lifespan is jitter to allow for


def test_still_only_when_standing_with_nothing_but_stops_on_their_way():
    predictor = LatencyPredictor(STEP_S)
    _drive(predictor, [Command(0.5, 0.0), Command(0.0, 0.0), Command(0.0, 0.0)], [0, 1, 2])
    assert not predictor.still  # the 0.5 m/s command is in effect
    predictor.sent(Command(0.0, 0.0))
    predictor.observe(0.0, 0.0)
    assert predictor.still
    predictor.sent(Command(0.0, 1.0))
    predictor.observe(0.0, 0.0)
    assert not predictor.still  # a turn is on its way


@pytest.mark.parametrize('command', [Command(1.0, 0.0), Command(-0.7, 0.3), Command(0.0, -2.0)])
def test_alike_commands_are_made_smaller_by_float32_steps_until_each_echo_is_unique(command):
    predictor = LatencyPredictor(STEP_S)
    sent = []
    for _ in range(40):
        sent.append(predictor.distinct(command))
        predictor.sent(sent[-1])
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
    predictor.observe(*_echo(sent[-5]))
    assert predictor.in_flight == 4


def test_a_stop_is_never_nudged():
    predictor = LatencyPredictor(STEP_S)
    for _ in range(3):
        predictor.sent(predictor.distinct(Command(0.0, 0.0)))
    assert predictor.distinct(Command(0.0, 0.0)) == Command(0.0, 0.0)


def test_a_stop_sent_after_moving_commands_is_not_what_a_standing_turtle_stands_on():
    """Start of a run on a slow link: the turtle stands while the commands are on their way.
    The stop sent after them echoes as the standing turtle does, but cannot be in effect
    before they moved it: all of them are still in flight, and no latency is learnt."""
    predictor = LatencyPredictor(STEP_S)
    moving = [Command(1.0 - 0.01 * k, 0.0) for k in range(10)]
    for command in [*moving, Command(0.0, 0.0)]:
        predictor.sent(command)
        assert predictor.observe(0.0, 0.0) == len(predictor._pending())
    assert predictor.in_flight == 11 and predictor.spread == 0 and not predictor.still
    assert predictor.observe(*_echo(moving[0])) == 10  # the first one acts at last
    for command in moving[1:]:  # then each in turn, then the stop: the turtle stands on it
        predictor.observe(*_echo(command))
    assert predictor.observe(0.0, 0.0) == 0 and predictor.still

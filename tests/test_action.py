"""The draw action (`/turtle_traj/draw`): feedback, cancel, refusal, one run at a time."""

import math

import pytest
from action_msgs.msg import GoalStatus
from turtle_traj_interfaces.action import Draw
from turtle_traj_interfaces.msg import Ending
from turtle_traj_interfaces.srv import DrawShape, GoTo

from turtle_traj.core.turtlesim_contract import SPAWN_XY_M
from turtle_traj.testing.geometry import regular_polygon, xy


@pytest.fixture
def draw(turtle_system):
    """An action client of the node's draw action, on the harness's client node (which
    destroys it)."""
    client = turtle_system.action_client(Draw, '/turtle_traj/draw')
    assert turtle_system.spin_until(client.server_is_ready, timeout_s=60.0)
    return client


def send(turtle_system, draw, feedback=None, **fields):
    """Send a goal and return its handle once the server answered (accepted or not)."""
    future = draw.send_goal_async(Draw.Goal(**fields), feedback_callback=feedback)
    assert turtle_system.spin_until(future.done, timeout_s=10.0)
    return future.result()


def result_of(turtle_system, handle, timeout_s: float = 120.0):
    future = handle.get_result_async()
    assert turtle_system.spin_until(future.done, timeout_s=timeout_s)
    return future.result()


def test_a_square_reports_progress_to_one_and_its_result(turtle_system, draw):
    feedback = []
    turtle_system.poses.clear()
    handle = send(turtle_system, draw, lambda message: feedback.append(message.feedback),
                  trajectory='square', size=1.0)
    assert handle.accepted
    outcome = result_of(turtle_system, handle)
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED
    result = outcome.result
    assert result.success and result.message == 'square done'
    progress = [message.progress for message in feedback]
    assert progress == sorted(progress) and 0.0 <= progress[0] < 0.1 and progress[-1] > 0.95
    assert len(feedback) >= 5 * result.elapsed - 1  # at least 5 Hz (node clock)
    distances = [message.distance for message in feedback]
    assert distances == sorted(distances) and distances[-1] == pytest.approx(4.0, abs=0.05)
    assert max(message.deviation for message in feedback) <= result.max_deviation + 1e-9
    corners = regular_polygon(SPAWN_XY_M, SPAWN_XY_M, 0.0, 4, 1.0, False)
    assert math.dist(xy(turtle_system.poses)[-1], corners[-1]) < 1e-3
    last = feedback[-1]
    assert math.dist((last.x, last.y), (result.final_x, result.final_y)) < 0.05


def test_cancel_stops_an_endless_circle_at_once(turtle_system, draw):
    handle = send(turtle_system, draw, trajectory='circle', size=1.0, forever=True)
    assert handle.accepted
    turtle_system.spin_sim_seconds(2.0)
    cancel = handle.cancel_goal_async()
    cancelled_at = turtle_system.sim_time_s
    assert turtle_system.spin_until(cancel.done)
    assert len(cancel.result().goals_canceling) == 1
    outcome = result_of(turtle_system, handle, timeout_s=5.0)
    assert outcome.status == GoalStatus.STATUS_CANCELED
    assert outcome.result.success and outcome.result.ending.code == Ending.CANCELLED
    assert turtle_system.spin_until(
        lambda: turtle_system.poses[-1].linear_velocity == 0.0, timeout_s=1.0
    )
    assert turtle_system.sim_time_s - cancelled_at < 0.1  # standing within a few 16 ms steps
    turtle_system.poses.clear()
    turtle_system.spin_sim_seconds(0.5)
    assert all(p.linear_velocity == 0.0 and p.angular_velocity == 0.0 for p in turtle_system.poses)
    assert turtle_system.node.ready


def test_one_run_at_a_time_across_the_action_and_the_services(turtle_system, draw):
    handle = send(turtle_system, draw, trajectory='circle', size=1.0, forever=True)
    assert handle.accepted
    turtle_system.spin_sim_seconds(0.5)
    busy = turtle_system.call(GoTo, 'go_to', GoTo.Request(x=2.0, y=2.0))
    assert not busy.success and busy.ending.code == Ending.BUSY
    assert 'busy: circle is running' in busy.message
    handle.cancel_goal_async()
    assert result_of(turtle_system, handle).status == GoalStatus.STATUS_CANCELED

    running = turtle_system.start(DrawShape, 'draw_square', DrawShape.Request(size=1.0))
    assert turtle_system.spin_until(lambda: turtle_system.node.busy)
    refused = result_of(turtle_system, send(turtle_system, draw, trajectory='rotate', angle=1.0))
    assert refused.status == GoalStatus.STATUS_ABORTED
    assert refused.result.ending.code == Ending.BUSY
    assert refused.result.message.startswith('busy: square is running')
    assert turtle_system.spin_until(running.done) and running.result().success


@pytest.mark.parametrize(
    'fields, reason',
    [
        (dict(trajectory='blob'), "unknown trajectory 'blob'; known: square"),
        (dict(trajectory='draw_square'), "unknown trajectory 'draw_square'"),
        (dict(trajectory='square', size=math.nan), 'size must be a finite number, got nan'),
        (dict(trajectory='go_to', x=50.0, y=5.0), 'goal (50, 5) is outside the arena'),
        (dict(trajectory='follow_path'), 'points is empty'),
        (
            dict(trajectory='circle', turns=2.0, forever=True),
            'turns 2 and forever contradict each other',
        ),
    ],
)
def test_a_goal_that_cannot_run_ends_aborted_with_the_reason_in_its_result(
    turtle_system, draw, fields, reason
):
    # A plain action client, as any ROS user has one: the reason is in the result, and no
    # log topic is read for it.
    assert all(sub.topic_name != '/rosout' for sub in turtle_system.client.subscriptions)
    handle = send(turtle_system, draw, **fields)
    assert handle.accepted
    refused = result_of(turtle_system, handle, timeout_s=5.0)
    assert refused.status == GoalStatus.STATUS_ABORTED
    assert not refused.result.success and refused.result.ending.code == Ending.INVALID_REQUEST
    assert reason in refused.result.message
    again = send(turtle_system, draw, trajectory='rotate', angle=0.5)
    assert again.accepted
    assert result_of(turtle_system, again).status == GoalStatus.STATUS_SUCCEEDED

"""The script-side client against a node that dies: it says so within seconds."""

import time

import pytest

from tests.ros_helpers import program
from turtle_traj.client import FEEDBACK_SILENCE_S, PROBE_TIMEOUT_S, TrajClient, TrajClientError
from turtle_traj.services import make_goal
from turtle_traj.trajectories import BY_NAME


def test_a_node_killed_mid_goal_is_noticed_within_seconds(tmp_path):
    # A namespace of its own: no other test's simulator or node answers for it.
    with program('turtle_traj', '--with-sim', '--ros-args', '-r', '__ns:=/doomed',
                 cwd=tmp_path) as process, \
            TrajClient(node='/doomed/turtle_traj', connect_timeout_s=10.0) as client:
        assert client.call('reset').success  # answers once poses reach the node
        killed_at = []

        def kill_once(feedback) -> None:
            if not killed_at:
                process.kill()  # SIGKILL: no goodbye on the ROS graph
                killed_at.append(time.monotonic())
        goal = make_goal(BY_NAME['circle'], {'size': 1.0, 'forever': True})
        with pytest.raises(TrajClientError, match='stopped answering during the circle'):
            client.draw(goal, on_feedback=kill_once)
        noticed_after = time.monotonic() - killed_at[0]
    # Not the 20 s it takes DDS to drop a dead participant, nor any run timeout.
    assert noticed_after < FEEDBACK_SILENCE_S + PROBE_TIMEOUT_S + 3.0

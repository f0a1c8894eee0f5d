"""Drawings driven end to end in our simulator (lock-step): the poses against the geometry, the
canvas against the pen, and the pen left down after a stop, an abort or the node's end."""

import numpy as np
import pytest
from std_srvs.srv import Trigger
from turtle_traj_interfaces.action import Draw
from turtle_traj_interfaces.srv import DrawCurve, DrawSvg, DrawText
from turtlesim.srv import TeleportAbsolute

from turtle_traj.api.ros_interface import make_request
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.registry import BY_NAME
from turtle_traj.testing.geometry import (
    distance_to_polyline,
    drawn_strokes,
    ink_at,
    pen_up_moves,
    resampled,
    xy,
)

PEN = DEFAULT_SETTINGS.pen
INK_CLEARANCE_M = 0.06  # pen-up points this far from any stroke: 3 px of pen and 1 px spare
NOTHING_DRAWN = (255, 255, 255)  # what turtlesim's colour sensor reads off the trails


def _planned(turtle_system, name: str, given: dict):
    """The plan the node will make for this request (planning is deterministic)."""
    request = make_request(BY_NAME[name], given)
    return request, planning.plan(
        name, request, turtle_system.node.pose, turtle_system.node.settings
    )


def _ink(turtle_system, points: np.ndarray, color=(PEN.r, PEN.g, PEN.b)) -> np.ndarray:
    return ink_at(turtle_system.sim.canvas, points, color)


def _along(points: np.ndarray) -> np.ndarray:
    return resampled(points, 0.01)


def _check_drawing(turtle_system, response, path) -> None:
    """Every stroke drawn where planned, no ink along pen-up moves, figures that agree."""
    assert response.success, response.message
    poses = xy(turtle_system.poses)
    strokes = drawn_strokes(path)
    for stroke in strokes:  # the turtle passes through both ends of every stroke
        for end in (stroke[0], stroke[-1]):
            assert np.hypot(*(poses - end).T).min() < 0.001
    independent = distance_to_polyline(poses, path.points()).max()
    assert response.max_deviation == pytest.approx(independent, abs=1e-9)
    assert response.max_deviation < 0.002
    assert response.pen_up_length == pytest.approx(path.pen_up_length)
    assert (
        _ink(turtle_system, np.concatenate([_along(stroke) for stroke in strokes])).mean() > 0.97
    )
    travel = np.concatenate([_along(move) for move in pen_up_moves(path)])
    to_ink = np.min([distance_to_polyline(travel, stroke) for stroke in strokes], axis=0)
    clear = travel[to_ink > INK_CLEARANCE_M]
    assert len(clear) > 20  # enough pen-up travel away from the strokes to look at
    assert not _ink(turtle_system, clear).any(), 'ink along a pen-up move'


def _turtle_pen(turtle_system):
    return turtle_system.sim.world.turtle('turtle1').pen


def test_text_is_written_with_the_pen_lifted_between_strokes(turtle_system):
    given = {'text': 'H  i!', 'height': 0.6}
    request, plan = _planned(turtle_system, 'text', given)
    response = turtle_system.call(DrawText, 'draw_text', request)
    _check_drawing(turtle_system, response, plan.path)
    assert response.pen_up_length < response.pen_up_unordered
    pen = _turtle_pen(turtle_system)
    assert (pen.on, pen.r, pen.g, pen.b, pen.width_px) == (True, PEN.r, PEN.g, PEN.b, PEN.width)


def test_svg_path_data_is_drawn_in_its_own_colour(turtle_system):
    given = {
        'path_data': 'M 0 0 C 10 -20 30 -20 40 0 M 0 10 L 40 10 M 20 -5 A 4 4 0 1 0 20 3',
        'size': 2.0,
        'pen_color': 'red',
        'pen_width': 2,
    }
    request, plan = _planned(turtle_system, 'svg', given)
    response = turtle_system.call(DrawSvg, 'draw_svg', request)
    assert response.success, response.message
    poses = xy(turtle_system.poses)
    assert distance_to_polyline(poses, plan.path.points()).max() < 0.002
    strokes = drawn_strokes(plan.path)
    assert len(strokes) == 3
    assert (
        _ink(turtle_system, np.concatenate([_along(s) for s in strokes]), (255, 0, 0)).mean()
        > 0.97
    )
    assert not _ink(
        turtle_system, np.concatenate([_along(s) for s in strokes])
    ).any()  # not the default
    pen = _turtle_pen(turtle_system)  # and the pen is the node's again
    assert (pen.on, pen.r, pen.g, pen.b, pen.width_px) == (True, PEN.r, PEN.g, PEN.b, PEN.width)


@pytest.mark.parametrize(
    ('name', 'given'),
    [
        ('star', {'size': 0.8, 'tips': 5}),
        ('heart', {'size': 1.5}),
        ('lemniscate', {'size': 2.0}),
        ('rose', {'size': 1.6, 'petals': 3}),
        ('lissajous', {'size': 1.4, 'a': 1, 'b': 2, 'phase': 45.0}),
    ],
)
def test_curves_are_drawn_as_planned(turtle_system, name, given):
    request, plan = _planned(turtle_system, name, given)
    response = turtle_system.call(DrawCurve, f'draw_{name}', request)
    assert response.success, response.message
    poses = xy(turtle_system.poses)
    assert response.max_deviation == pytest.approx(
        distance_to_polyline(poses, plan.path.points()).max(), abs=1e-9
    )
    assert response.max_deviation < 0.003
    assert response.final_error < 0.001
    # the whole curve is driven: every planned point is passed within 3 mm, and inked
    assert distance_to_polyline(plan.path.points(), poses).max() < 0.003
    assert _ink(turtle_system, _along(plan.path.points())).mean() > 0.97


def _stopped_while_the_pen_is_up(turtle_system, end_run) -> None:
    request, _ = _planned(turtle_system, 'text', {'text': 'I I I', 'height': 0.5})
    future = turtle_system.start(DrawText, 'draw_text', request)
    assert turtle_system.spin_until(
        lambda: turtle_system.node.busy and turtle_system.poses and _turtle_pen(turtle_system).on
    )
    assert turtle_system.spin_until(
        lambda: not _turtle_pen(turtle_system).on
    )  # travelling to the next I
    end_run()
    assert turtle_system.spin_until(future.done)
    assert not future.result().success
    turtle_system.spin_sim_seconds(0.1)
    pen = _turtle_pen(turtle_system)
    assert (pen.on, pen.r, pen.g, pen.b, pen.width_px) == (True, PEN.r, PEN.g, PEN.b, PEN.width)


def test_a_stop_leaves_the_pen_down(turtle_system):
    _stopped_while_the_pen_is_up(turtle_system, lambda: turtle_system.call(Trigger, 'stop'))


def test_an_abort_leaves_the_pen_down(turtle_system):
    def teleport() -> None:
        pose = turtle_system.node.pose
        turtle_system.call(
            TeleportAbsolute,
            '/turtle1/teleport_absolute',
            TeleportAbsolute.Request(x=pose.x, y=pose.y + 1.0, theta=pose.theta),
        )

    _stopped_while_the_pen_is_up(turtle_system, teleport)


def test_the_draw_action_writes_text_and_reports_the_pen_up_distance(turtle_system):
    _, plan = _planned(turtle_system, 'text', {'text': 'T T', 'height': 0.5})
    client = turtle_system.action_client(Draw, '/turtle_traj/draw')
    assert turtle_system.spin_until(client.server_is_ready, timeout_s=60.0)
    sent = client.send_goal_async(Draw.Goal(trajectory='text', text='T T', height=0.5))
    assert turtle_system.spin_until(sent.done)
    result = sent.result().get_result_async()
    assert turtle_system.spin_until(result.done)
    outcome = result.result().result
    assert outcome.success, outcome.message
    assert outcome.pen_up_length == pytest.approx(plan.path.pen_up_length)
    assert outcome.pen_up_unordered == pytest.approx(plan.pen_up_unordered)
    assert outcome.pen_up_length > 0.4  # from one T to the other, past the space


@pytest.mark.system
def test_a_node_ended_mid_drawing_leaves_the_pen_down(rclpy_context, tmp_path):
    """The node program ends while the pen is up: the turtle, driven on, draws again."""
    import subprocess
    import sys
    import time

    from geometry_msgs.msg import Twist, Vector3
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from turtlesim.msg import Color, Pose

    from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
    from turtle_traj.rosutils.runtime import spin_until
    from turtle_traj.testing.processes import program, terminate

    observer = Node('pen_observer', context=rclpy_context)
    executor = SingleThreadedExecutor(context=rclpy_context)
    executor.add_node(observer)
    colors: list[tuple[int, int, int]] = []
    poses: list[Pose] = []
    observer.create_subscription(
        Color, 'turtle1/color_sensor', lambda c: colors.append((c.r, c.g, c.b)), TURTLE_TOPIC_QOS
    )
    observer.create_subscription(Pose, 'turtle1/pose', poses.append, TURTLE_TOPIC_QOS)
    command = observer.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
    client = observer.create_client(DrawText, '/turtle_traj/draw_text')
    pen = (PEN.r, PEN.g, PEN.b)
    try:
        with program('turtle_traj.sim', cwd=tmp_path):
            node = subprocess.Popen(
                [sys.executable, '-m', 'turtle_traj'],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
                text=True,
            )
            try:
                assert spin_until(executor, client.service_is_ready, timeout_s=20.0)
                # each topic is discovered on its own: hear both before the turtle moves
                assert spin_until(executor, lambda: bool(poses and colors), timeout_s=20.0)
                deadline = time.monotonic() + 40.0
                while pen not in colors:  # a node still discovering the simulator refuses
                    call = client.call_async(DrawText.Request(text='I   I', height=0.4))
                    spin_until(
                        executor, lambda call=call: call.done() or pen in colors, timeout_s=20.0
                    )
                    if pen not in colors:
                        assert call.done() and not call.result().success, 'neither drew nor said'
                        assert time.monotonic() < deadline, call.result().message
                        spin_until(executor, lambda: False, timeout_s=0.2)
                assert spin_until(  # then driving on with the pen up, over nothing drawn
                    executor,
                    lambda: poses[-1].linear_velocity > 0.2 and colors[-1] == NOTHING_DRAWN,
                    timeout_s=20.0,
                )
                stderr = terminate(node)
            finally:
                node.kill()
            assert node.returncode == 0, stderr
            count = len(colors)
            for _ in range(20):
                command.publish(Twist(linear=Vector3(x=1.0)))
                spin_until(executor, lambda: False, timeout_s=0.02)
            assert colors[count:].count(pen) > 5  # the turtle draws again, in turtlesim's pen
    finally:
        executor.shutdown()
        observer.destroy_node()


_LAST_CALL = """
from std_srvs.srv import Trigger
from rclpy.node import Node
from turtle_traj.rosutils.runtime import run_nodes
answered, made = [], []
def create(stop):
    node = Node('exiting')
    node.create_service(Trigger, 'last_call', lambda _request, response: (answered.append(1),
                                                                         response)[1])
    client = node.create_client(Trigger, 'last_call')
    node.create_timer(0.05, lambda: client.service_is_ready() and stop())
    made.append(client)
    return [node]
calls = []
def on_exit():
    calls.append(made[0].call_async(Trigger.Request()))
    return calls
print(run_nodes(create, on_exit=on_exit), answered, calls[0].done())
"""


def test_a_program_waits_for_the_answers_to_its_last_calls():
    """The program's end waits for what its nodes asked on their way out (the node puts a
    drawing's pen back down): destroyed at once, a call could be lost with them, and a node
    ended mid-drawing left the turtle's pen up, once in a dozen under load. Here the call is
    to the program's own service: it is answered only if the program spins for it."""
    import subprocess
    import sys
    ran = subprocess.run([sys.executable, '-c', _LAST_CALL], capture_output=True, text=True,
                         timeout=60)
    assert ran.stdout.split() == ['0', '[1]', 'True'], ran.stdout + ran.stderr


def test_the_pen_parameters_are_checked_and_drawings_use_them(turtle_system):
    from rcl_interfaces.msg import Parameter as ParameterMsg
    from rcl_interfaces.msg import ParameterType, ParameterValue
    from rcl_interfaces.srv import SetParameters

    def set_color(text: str):
        value = ParameterValue(type=ParameterType.PARAMETER_STRING, string_value=text)
        request = SetParameters.Request(parameters=[ParameterMsg(name='pen_color', value=value)])
        return turtle_system.call(SetParameters, '/turtle_traj/set_parameters', request).results[0]

    refused = set_color('blurple')
    assert not refused.successful
    assert "pen_color 'blurple' is not a colour" in refused.reason
    assert set_color('#00ff00').successful
    request, plan = _planned(turtle_system, 'text', {'text': 'L', 'height': 0.5})
    assert turtle_system.call(DrawText, 'draw_text', request).success
    strokes = drawn_strokes(plan.path)
    assert (
        _ink(turtle_system, np.concatenate([_along(s) for s in strokes]), (0, 255, 0)).mean()
        > 0.97
    )
    pen = _turtle_pen(turtle_system)  # left down in the node's (new) pen
    assert (pen.on, pen.r, pen.g, pen.b) == (True, 0, 255, 0)

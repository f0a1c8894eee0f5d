"""The simulator node on the wire: what a client written for real turtlesim sees."""

import math
import os
import subprocess
import sys

import pytest
import rclpy
from geometry_msgs.msg import Twist
from PIL import Image
from rcl_interfaces.msg import Parameter as ParameterMsg
from rcl_interfaces.msg import ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from rclpy.action import ActionClient
from rclpy.executors import SingleThreadedExecutor
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Empty
from turtle_traj_interfaces.srv import SaveImage
from turtlesim.action import RotateAbsolute
from turtlesim.msg import Color, Pose
from turtlesim.srv import Kill, SetPen, Spawn, TeleportAbsolute, TeleportRelative

from turtle_traj.core.turtlesim_contract import SPAWN_XY_M, STEP_S, WORLD_SIZE_M
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.rosutils.runtime import spin_until
from turtle_traj.sim.canvas import to_pixel
from turtle_traj.testing.processes import program, terminate


class PoseRecorder:
    """Subscribes like any turtlesim client and keeps every pose."""

    def __init__(self, turtle_sim, turtle='turtle1'):
        self.poses: list[Pose] = []
        self.colors: list[Color] = []
        turtle_sim.client.create_subscription(Pose, f'{turtle}/pose', self.poses.append,
                                       TURTLE_TOPIC_QOS)
        turtle_sim.client.create_subscription(Color, f'{turtle}/color_sensor', self.colors.append,
                                       TURTLE_TOPIC_QOS)
        assert turtle_sim.spin_until(lambda: self.poses and self.colors)

    @property
    def last(self) -> Pose:
        return self.poses[-1]


class LogRecorder:
    """The simulator's log lines, as its console output shows them (/rosout is unreliable
    within one test process: rcl keeps one rosout publisher per node name, and the
    destruction of an earlier `turtlesim` node unregisters it)."""

    def __init__(self, turtle_sim, capfd):
        self.sim, self.capfd, self.text = turtle_sim, capfd, ''

    def wait_for(self, text: str) -> bool:
        """`text` has been (or is soon) logged by the simulator."""
        def seen() -> bool:
            self.text += self.capfd.readouterr().err
            return any(line.split('[turtlesim]: ', 1)[-1].startswith(text)
                       for line in self.text.splitlines() if '[turtlesim]: ' in line)
        return self.sim.spin_until(seen, timeout_s=5.0)


def _drive(turtle_sim, publisher, linear=0.0, angular=0.0, linear_y=0.0):
    twist = Twist()
    twist.linear.x, twist.linear.y, twist.angular.z = linear, linear_y, angular
    publisher.publish(twist)


def test_graph_has_turtlesims_names_and_types(turtle_sim):
    def graph_complete():
        topics = dict(turtle_sim.client.get_topic_names_and_types())
        services = dict(turtle_sim.client.get_service_names_and_types())
        return '/turtle1/rotate_absolute/_action/status' in topics and \
            '/turtle1/teleport_relative' in services

    assert turtle_sim.spin_until(graph_complete)
    topics = dict(turtle_sim.client.get_topic_names_and_types())
    services = dict(turtle_sim.client.get_service_names_and_types())
    assert topics['/turtle1/pose'] == ['turtlesim/msg/Pose']
    assert topics['/turtle1/color_sensor'] == ['turtlesim/msg/Color']
    assert topics['/turtle1/cmd_vel'] == ['geometry_msgs/msg/Twist']
    assert topics['/clock'] == ['rosgraph_msgs/msg/Clock']
    for name, type_name in [
        ('/clear', 'std_srvs/srv/Empty'), ('/reset', 'std_srvs/srv/Empty'),
        ('/spawn', 'turtlesim/srv/Spawn'), ('/kill', 'turtlesim/srv/Kill'),
        ('/turtle1/set_pen', 'turtlesim/srv/SetPen'),
        ('/turtle1/teleport_absolute', 'turtlesim/srv/TeleportAbsolute'),
        ('/turtle1/teleport_relative', 'turtlesim/srv/TeleportRelative'),
        ('/turtle1/rotate_absolute/_action/send_goal',
         'turtlesim/action/RotateAbsolute_SendGoal'),
        ('/turtlesim/save_image', 'turtle_traj_interfaces/srv/SaveImage'),
        ('/turtlesim/set_parameters', 'rcl_interfaces/srv/SetParameters'),
    ]:
        assert services[name] == [type_name]
    parameters = set(turtle_sim.sim.list_parameters([], 0).names)
    assert {'background_r', 'background_g', 'background_b', 'holonomic'} <= parameters


def test_pose_starts_at_turtlesim_spawn_point(turtle_sim):
    recorder = PoseRecorder(turtle_sim)
    first = recorder.poses[0]
    assert (first.x, first.y, first.theta) == (SPAWN_XY_M, SPAWN_XY_M, 0.0)
    assert recorder.colors[0] == Color(r=255, g=255, b=255)


def test_one_second_command_moves_one_metre_then_stops(turtle_sim):
    recorder = PoseRecorder(turtle_sim)
    publisher = turtle_sim.client.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
    _drive(turtle_sim, publisher, linear=1.0)
    assert turtle_sim.spin_until(lambda: recorder.last.linear_velocity == 1.0)
    assert turtle_sim.spin_until(lambda: recorder.last.linear_velocity == 0.0)
    stopped_x = recorder.last.x
    turtle_sim.spin_sim_seconds(0.3)
    assert recorder.last.x == stopped_x
    assert stopped_x - SPAWN_XY_M == pytest.approx(1.0, abs=STEP_S)
    # The pen drew under the turtle, so the color sensor reads the default pen colour.
    assert recorder.colors[-1] == Color(r=179, g=184, b=255)


def test_turtle_stops_at_the_wall(turtle_sim):
    recorder = PoseRecorder(turtle_sim)
    publisher = turtle_sim.client.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
    _drive(turtle_sim, publisher, linear=8.0)  # 8 m in 1 s would end far past the right wall
    assert turtle_sim.spin_until(lambda: recorder.last.linear_velocity == 0.0 and
                          recorder.last.x > SPAWN_XY_M)
    assert recorder.last.x == pytest.approx(WORLD_SIZE_M)
    assert recorder.last.y == pytest.approx(SPAWN_XY_M)


def test_a_single_command_drives_63_steps_as_on_turtlesim(turtle_sim):
    recorder = PoseRecorder(turtle_sim)
    publisher = turtle_sim.client.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
    _drive(turtle_sim, publisher, linear=2.0)  # once, as `ros2 topic pub --once`
    assert turtle_sim.spin_until(lambda: recorder.last.linear_velocity == 2.0)
    assert turtle_sim.spin_until(lambda: recorder.last.linear_velocity == 0.0)
    moving = [pose for pose in recorder.poses if pose.linear_velocity == 2.0]
    assert len(moving) == 63  # turtlesim 1.8.2 measured: 63 steps, 2.016 m, 5 runs of 5
    assert recorder.last.x - SPAWN_XY_M == pytest.approx(2.016, abs=1e-5)


def test_a_non_finite_command_stops_the_turtle_and_says_so(turtle_sim, capfd):
    recorder, logs = PoseRecorder(turtle_sim), LogRecorder(turtle_sim, capfd)
    publisher = turtle_sim.client.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
    _drive(turtle_sim, publisher, linear=1.0, angular=0.5)
    assert turtle_sim.spin_until(lambda: recorder.last.linear_velocity == 1.0)
    _drive(turtle_sim, publisher, linear=math.nan, angular=math.inf)
    assert turtle_sim.spin_until(lambda: recorder.last.linear_velocity == 0.0)
    stopped = len(recorder.poses)
    turtle_sim.spin_sim_seconds(0.2)
    assert all(pose.linear_velocity == 0.0 and pose.angular_velocity == 0.0
               for pose in recorder.poses[stopped:])
    assert all(math.isfinite(p.x) and math.isfinite(p.theta) for p in recorder.poses)
    assert logs.wait_for('Ignoring cmd_vel for [turtle1]: non-finite velocity (linear.x=nan')


def test_teleports_and_holonomic_parameter(turtle_sim):
    recorder = PoseRecorder(turtle_sim)
    turtle_sim.call(TeleportAbsolute, 'turtle1/teleport_absolute',
             TeleportAbsolute.Request(x=2.0, y=3.0, theta=0.5))
    turtle_sim.call(TeleportRelative, 'turtle1/teleport_relative',
             TeleportRelative.Request(linear=1.0, angular=math.pi / 2 - 0.5))
    assert turtle_sim.spin_until(lambda: abs(recorder.last.y - 4.0) < 1e-5)
    assert (recorder.last.x, recorder.last.theta) == pytest.approx((2.0, math.pi / 2), abs=1e-5)

    result = _set_parameter(turtle_sim, 'holonomic', ParameterValue(
        type=ParameterType.PARAMETER_BOOL, bool_value=True))
    assert result.successful
    publisher = turtle_sim.client.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
    _drive(turtle_sim, publisher, linear_y=1.0)  # heading up, so sideways is towards -x
    assert turtle_sim.spin_until(lambda: recorder.last.linear_velocity == 0.0 and
                          recorder.last.x < 1.5)
    assert recorder.last.x == pytest.approx(1.0, abs=STEP_S)


def _set_parameter(turtle_sim, name, value):
    request = SetParameters.Request(parameters=[ParameterMsg(name=name, value=value)])
    return turtle_sim.call(SetParameters, '/turtlesim/set_parameters', request).results[0]


@pytest.mark.parametrize(('name', 'value', 'reason'), [
    ('background_r', ParameterValue(type=ParameterType.PARAMETER_INTEGER, integer_value=256),
     'Parameter background_r out of range. Min: 0, Max: 255, value: 256'),
    ('background_g', ParameterValue(type=ParameterType.PARAMETER_INTEGER, integer_value=-1),
     'Parameter background_g out of range. Min: 0, Max: 255, value: -1'),
    ('background_b', ParameterValue(type=ParameterType.PARAMETER_STRING, string_value='blue'),
     'Wrong parameter type'),
    ('holonomic', ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=1.0),
     'Wrong parameter type'),
    ('time_scale', ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=2.0),
     'read-only'),
    ('motor_gains', ParameterValue(type=ParameterType.PARAMETER_STRING,
                                   string_value='turtle1=1.5'),
     "motor_gains: 'turtle1=1.5' is not name=gain with a gain in (0, 1]"),
    ('motor_gains', ParameterValue(type=ParameterType.PARAMETER_STRING, string_value='turtle1'),
     "motor_gains: 'turtle1' is not name=gain"),
])
def test_invalid_parameters_are_refused_with_a_reason(turtle_sim, name, value, reason):
    """The parameter layer's refusals (rclcpp's words in turtlesim, rclpy's here)."""
    before = turtle_sim.sim.get_parameter(name).value
    result = _set_parameter(turtle_sim, name, value)
    assert not result.successful
    assert reason in result.reason, result.reason
    assert turtle_sim.sim.get_parameter(name).value == before


def test_background_parameter_repaints_live(turtle_sim):
    assert _set_parameter(turtle_sim, 'background_r', ParameterValue(
        type=ParameterType.PARAMETER_INTEGER, integer_value=10)).successful
    assert turtle_sim.sim.render().getpixel((5, 5)) == (10, 86, 255)


def test_spawn_kill_and_reset(turtle_sim):
    spawned = turtle_sim.call(Spawn, 'spawn', Spawn.Request(x=1.0, y=2.0, theta=0.0))
    assert spawned.name == 'turtle2'
    assert turtle_sim.call(Spawn, 'spawn', Spawn.Request(x=1.0, y=2.0, name='turtle2')).name == ''
    assert turtle_sim.call(Spawn, 'spawn', Spawn.Request(x=math.nan, y=2.0)).name == ''
    assert (
        turtle_sim.call(Spawn, 'spawn', Spawn.Request(x=1.0, y=2.0, name='bad name!')).name == ''
    )
    assert turtle_sim.call(Spawn, 'spawn', Spawn.Request(x=3.0, y=3.0, name='leo')).name == 'leo'
    leo = PoseRecorder(turtle_sim, 'leo')
    assert (leo.last.x, leo.last.y) == pytest.approx((3.0, 3.0))
    turtle_sim.call(Kill, 'kill', Kill.Request(name='turtle2'))
    turtle_sim.call(Kill, 'kill', Kill.Request(name='nobody'))  # logged, answered, nothing breaks
    assert sorted(turtle_sim.sim.world.turtles) == ['leo', 'turtle1']
    assert turtle_sim.spin_until(
        lambda: '/turtle2/pose' not in dict(turtle_sim.client.get_topic_names_and_types())
    )
    turtle_sim.call(
        TeleportAbsolute,
        'turtle1/teleport_absolute',
        TeleportAbsolute.Request(x=1.0, y=1.0, theta=1.0),
    )
    turtle_sim.call(Empty, 'reset')
    assert sorted(turtle_sim.sim.world.turtles) == ['turtle1']
    recorder = PoseRecorder(turtle_sim)
    assert (recorder.last.x, recorder.last.y, recorder.last.theta) == (SPAWN_XY_M, SPAWN_XY_M, 0.0)
    assert turtle_sim.call(Spawn, 'spawn', Spawn.Request(x=1.0, y=2.0)).name == 'turtle2'


def _rotate(turtle_sim, theta, *, cancel_after_s=None):
    client = turtle_sim.action_client(RotateAbsolute, 'turtle1/rotate_absolute')
    assert client.wait_for_server(timeout_sec=10.0) or turtle_sim.spin_until(
        client.server_is_ready
    )
    feedback = []
    goal_future = client.send_goal_async(
        RotateAbsolute.Goal(theta=theta), feedback_callback=lambda m: feedback.append(m)
    )
    assert turtle_sim.spin_until(goal_future.done)
    handle = goal_future.result()
    assert handle.accepted
    if cancel_after_s is not None:
        turtle_sim.spin_sim_seconds(cancel_after_s)
        cancel = handle.cancel_goal_async()
        assert turtle_sim.spin_until(cancel.done)
    result = handle.get_result_async()
    assert turtle_sim.spin_until(result.done)
    return result.result(), feedback


def test_rotate_absolute_reaches_the_goal(turtle_sim):
    recorder = PoseRecorder(turtle_sim)
    outcome, feedback = _rotate(turtle_sim, 1.57)
    assert outcome.status == 4  # GoalStatus.STATUS_SUCCEEDED
    assert outcome.result.delta == pytest.approx(-1.552, abs=0.02)
    assert feedback and feedback[-1].feedback.remaining < 0.02
    assert turtle_sim.spin_until(lambda: recorder.last.angular_velocity == 0.0)
    assert recorder.last.theta == pytest.approx(1.57, abs=0.02)


def test_log_lines_use_turtlesims_words(turtle_sim, capfd):
    logs = LogRecorder(turtle_sim, capfd)
    turtle_sim.call(Spawn, 'spawn', Spawn.Request(x=1.0, y=1.0, name='turtle1'))
    assert logs.wait_for('A turtle named [turtle1] already exists')
    turtle_sim.call(Kill, 'kill', Kill.Request(name='nobody'))
    assert logs.wait_for('Tried to kill turtle [nobody], which does not exist')
    _rotate(turtle_sim, 0.5)
    assert logs.wait_for('Rotation goal completed successfully')
    client = turtle_sim.action_client(RotateAbsolute, 'turtle1/rotate_absolute')
    assert turtle_sim.spin_until(client.server_is_ready)
    sent = client.send_goal_async(RotateAbsolute.Goal(theta=-2.0))
    assert turtle_sim.spin_until(sent.done) and sent.result().accepted
    publisher = turtle_sim.client.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
    turtle_sim.spin_sim_seconds(0.1)
    _drive(turtle_sim, publisher, angular=0.1)
    assert logs.wait_for('Velocity command received during rotation goal. Aborting goal')
    result = sent.result().get_result_async()
    assert turtle_sim.spin_until(result.done) and result.result().status == 6  # ABORTED


def test_rotate_absolute_can_be_canceled(turtle_sim):
    recorder = PoseRecorder(turtle_sim)
    outcome, _ = _rotate(turtle_sim, 3.0, cancel_after_s=0.5)
    assert outcome.status == 5  # GoalStatus.STATUS_CANCELED
    assert turtle_sim.spin_until(lambda: recorder.last.angular_velocity == 0.0)
    assert 0.3 < recorder.last.theta < 1.5


def test_clock_follows_simulated_time(turtle_sim):
    stamps = []
    turtle_sim.client.create_subscription(Clock, '/clock', stamps.append, 10)
    assert turtle_sim.spin_until(lambda: len(stamps) > 10)
    seconds = stamps[-1].clock.sec + stamps[-1].clock.nanosec * 1e-9
    assert seconds == pytest.approx(turtle_sim.sim.world.time_s, abs=10 * STEP_S)
    # The use_sim_time client's clock is driven by /clock, not by the wall clock.
    assert turtle_sim.client.get_clock().ros_time_is_active
    client_now = turtle_sim.client.get_clock().now().nanoseconds * 1e-9
    assert client_now == pytest.approx(turtle_sim.sim.world.time_s, abs=10 * STEP_S)


def test_pen_trails_show_in_the_saved_image(turtle_sim, tmp_path):
    recorder = PoseRecorder(turtle_sim)
    publisher = turtle_sim.client.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
    turtle_sim.call(SetPen, 'turtle1/set_pen', SetPen.Request(r=255, g=0, b=0, width=4))
    _drive(turtle_sim, publisher, linear=2.0)  # drawn: 2 m to the right
    assert turtle_sim.spin_until(
        lambda: recorder.last.x > SPAWN_XY_M + 1.9 and recorder.last.linear_velocity == 0.0
    )
    turtle_sim.call(SetPen, 'turtle1/set_pen', SetPen.Request(off=1))
    turtle_sim.call(
        TeleportAbsolute,
        'turtle1/teleport_absolute',
        TeleportAbsolute.Request(x=2.0, y=2.0, theta=0.0),
    )
    _drive(turtle_sim, publisher, linear=2.0)  # not drawn: 2 m along y = 2
    assert turtle_sim.spin_until(lambda: recorder.last.x > 3.9 and recorder.last.y < 2.1)

    response = turtle_sim.call(
        SaveImage, '/turtlesim/save_image', SaveImage.Request(filename='a.png')
    )
    assert response.success, response.message
    image = Image.open(response.path).convert('RGB')
    assert image.size == (500, 500)
    drawn = to_pixel(SPAWN_XY_M + 1.0, SPAWN_XY_M)
    undrawn = to_pixel(3.0, 2.0)
    assert image.getpixel((round(drawn[0]), round(drawn[1]))) == (255, 0, 0)
    assert image.getpixel((round(undrawn[0]), round(undrawn[1]))) == (69, 86, 255)

    for bad in ['../escape.png', '/tmp/abs.png', 'notes.txt', '']:
        refused = turtle_sim.call(
            SaveImage, '/turtlesim/save_image', SaveImage.Request(filename=bad)
        )
        assert not refused.success and refused.message
    assert not (tmp_path / 'escape.png').exists()


def test_a_teleport_far_off_the_canvas_with_the_pen_down_draws_to_the_edge(turtle_sim, tmp_path):
    """A 1 px pen teleported to x = 1e9 m used to walk 4.5e10 pixels: the simulator froze."""
    recorder = PoseRecorder(turtle_sim)
    turtle_sim.call(SetPen, 'turtle1/set_pen', SetPen.Request(r=255, g=0, b=0, width=1))
    turtle_sim.call(
        TeleportAbsolute,
        'turtle1/teleport_absolute',
        TeleportAbsolute.Request(x=1e9, y=SPAWN_XY_M, theta=0.0),
    )
    assert turtle_sim.spin_until(lambda: recorder.last.x > 11.0, timeout_s=10.0)  # at the wall
    response = turtle_sim.call(
        SaveImage, '/turtlesim/save_image', SaveImage.Request(filename='f.png'), timeout_s=10.0
    )
    image = Image.open(response.path).convert('RGB')
    row = math.floor(to_pixel(0.0, SPAWN_XY_M)[1])  # a 1 px line: the row holding it
    start = math.ceil(to_pixel(SPAWN_XY_M, 0.0)[0])
    # the line runs to the wall, where the turtle now sits (its icon covers the last 23 px)
    assert {image.getpixel((column, row)) for column in range(start, 476)} == {(255, 0, 0)}


def test_window_shows_the_canvas_on_a_headless_driver(turtle_sim, monkeypatch):
    pytest.importorskip('pygame')
    monkeypatch.setenv('SDL_VIDEODRIVER', 'dummy')
    from turtle_traj.sim.gui import Window

    window = Window()
    try:
        frame = turtle_sim.sim.render()
        window.show(frame)
        center = to_pixel(SPAWN_XY_M, SPAWN_XY_M)
        assert window.pixel(3, 3) == (69, 86, 255)
        assert window.pixel(round(center[0]), round(center[1])) == frame.getpixel(
            (round(center[0]), round(center[1]))
        )
        assert window.pixel(round(center[0]), round(center[1])) != (69, 86, 255)
    finally:
        window.close()


def _run_sim(*args, env_update=None, timeout=20):
    env = {
        k: v
        for k, v in os.environ.items()
        if k not in ('DISPLAY', 'WAYLAND_DISPLAY', 'SDL_VIDEODRIVER')
    }
    env.update(env_update or {})
    return subprocess.run(
        [sys.executable, '-m', 'turtle_traj.sim', *args],
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


@pytest.mark.system
def test_gui_without_display_fails_with_a_clear_message():
    result = _run_sim('--gui')
    assert result.returncode == 2
    assert 'no display' in result.stderr
    assert 'Traceback' not in result.stderr


@pytest.mark.system
def test_sigterm_ends_the_program_cleanly_and_writes_the_snapshot(tmp_path):
    snapshot = tmp_path / 'last.png'
    with program('turtle_traj.sim', '--snapshot', str(snapshot)) as process:
        stderr = terminate(process)
    assert process.returncode == 0
    assert 'Traceback' not in stderr
    assert Image.open(snapshot).size == (500, 500)


@pytest.mark.system
def test_the_simulator_program_serves_on_its_events_executor(rclpy_context, tmp_path):
    """`python -m turtle_traj.sim` spins rclpy's experimental EventsExecutor: all it relies on,
    through the real program."""
    with program('turtle_traj.sim', cwd=tmp_path) as process:
        node = rclpy.create_node('checker', context=rclpy_context)
        executor = SingleThreadedExecutor(context=rclpy_context)
        executor.add_node(node)
        poses: list[Pose] = []
        node.create_subscription(Pose, 'turtle1/pose', poses.append, TURTLE_TOPIC_QOS)
        assert spin_until(executor, lambda: len(poses) > 5, timeout_s=10.0)  # the timer
        publisher = node.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
        twist = Twist()
        twist.linear.x = 1.0
        assert spin_until(executor, lambda: publisher.get_subscription_count() > 0, timeout_s=10.0)
        publisher.publish(twist)  # a subscription
        assert spin_until(executor, lambda: poses[-1].linear_velocity == 1.0, timeout_s=10.0)

        def call(service_type, name, request):
            client = node.create_client(service_type, name)
            assert client.wait_for_service(timeout_sec=10.0)
            future = client.call_async(request)
            assert spin_until(executor, future.done, timeout_s=10.0)
            return future.result()

        assert call(Spawn, 'spawn', Spawn.Request(x=2.0, y=2.0)).name == 'turtle2'
        refused = call(
            SetParameters,
            '/turtlesim/set_parameters',
            SetParameters.Request(
                parameters=[
                    ParameterMsg(
                        name='background_r',
                        value=ParameterValue(
                            type=ParameterType.PARAMETER_INTEGER, integer_value=300
                        ),
                    )
                ]
            ),
        ).results[0]
        assert not refused.successful

        rotate = ActionClient(node, RotateAbsolute, 'turtle1/rotate_absolute')
        assert rotate.wait_for_server(timeout_sec=10.0)

        def goal(theta: float, cancel: bool = False) -> int:
            sent = rotate.send_goal_async(RotateAbsolute.Goal(theta=theta))
            assert spin_until(executor, sent.done, timeout_s=10.0)
            if cancel:
                spin_until(executor, lambda: False, timeout_s=0.3)
                cancelled = sent.result().cancel_goal_async()
                assert spin_until(executor, cancelled.done, timeout_s=10.0)
            result = sent.result().get_result_async()
            assert spin_until(executor, result.done, timeout_s=10.0)
            return result.result().status

        assert goal(0.5) == 4  # SUCCEEDED: the awaited future was resolved from the timer
        assert goal(-2.5, cancel=True) == 5  # CANCELED
        executor.shutdown()
        rotate.destroy()
        node.destroy_node()
        stderr = terminate(process)
    assert process.returncode == 0, stderr
    assert 'Traceback' not in stderr

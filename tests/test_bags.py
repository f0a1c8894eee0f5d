"""Runs on record: rosbag2 bags written, read back by two independent readers, replayed and
plotted, and every bad bag refused with what is wrong."""

from __future__ import annotations

import errno
import os
import random
import shutil
import signal
import struct
import subprocess
import sys
import time

import numpy as np
import pytest

from turtle_traj.bags.reader import Bag
from turtle_traj.bags.writer import BagError
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M

pytest.importorskip('rosbags')


@pytest.fixture
def recorded(rclpy_context, tmp_path):
    """A draw_square run in lock-step, recorded by the node itself (record_dir), with its
    action feedback: (the bag, the poses the test's own client saw)."""
    from turtle_traj_interfaces.action import Draw

    from turtle_traj.apps.in_process import InProcessSystem
    system = InProcessSystem(context=rclpy_context, output_dir=tmp_path / 'output',
                             record_dir=str(tmp_path / 'bags'))
    try:
        action = system.action_client(Draw, '/turtle_traj/draw')
        assert system.spin_until(action.server_is_ready, timeout_s=60.0)
        system.poses.clear()
        sent = action.send_goal_async(Draw.Goal(trajectory='square', size=1.5))
        assert system.spin_until(sent.done, timeout_s=10.0)
        result = sent.result().get_result_async()
        assert system.spin_until(result.done, timeout_s=60.0)
        assert result.result().result.success
        seen = list(system.poses)
    finally:
        system.close()
    (bag,) = (tmp_path / 'bags').iterdir()
    return bag, seen


def test_a_run_is_recorded_with_types_rising_times_and_qos(recorded):
    path, seen = recorded
    assert path.name.startswith('square_')
    with Bag(path) as bag:
        assert bag.topics == {
            '/turtle1/pose': 'turtlesim/msg/Pose', '/turtle1/cmd_vel': 'geometry_msgs/msg/Twist',
            '/turtle_traj/plan': 'nav_msgs/msg/Path',
            '/turtle_traj/draw/_action/feedback':
                'turtle_traj_interfaces/action/Draw_FeedbackMessage',
            '/turtle_traj/draw/_action/status': 'action_msgs/msg/GoalStatusArray'}
        counts = bag.counts
        assert counts['/turtle_traj/plan'] == 1 and counts['/turtle1/cmd_vel'] > 300
        # every pose the run had (the test's client saw them too), the last one or two aside
        assert len(seen) - 2 <= counts['/turtle1/pose'] <= len(seen)
        assert counts['/turtle_traj/draw/_action/feedback'] > 30
        for topic in bag.topics:
            times = [m.time_ns for m in bag.messages([topic])]
            assert times == sorted(times), topic
        pose_qos = bag.offered_qos('/turtle1/pose')
        assert pose_qos and pose_qos[0].reliability.name == 'RELIABLE'
        assert bag.offered_qos('/turtle_traj/plan')[0].durability.name == 'TRANSIENT_LOCAL'
        assert bag.custom_data['trajectory'] == 'square'
        # the plan, made beside the executor and stamped as it was published: the square
        (plan,) = [m.value for m in bag.messages(['/turtle_traj/plan'], deserialize=True)]
        corners = np.array([(p.pose.position.x, p.pose.position.y) for p in plan.poses])
        assert np.ptp(corners, axis=0) == pytest.approx([1.5, 1.5], abs=1e-6)
        assert np.allclose(corners[0], corners[-1])
        assert plan.header.stamp.sec > 0 or plan.header.stamp.nanosec > 0
        assert all(p.header.stamp == plan.header.stamp for p in plan.poses)
        feedback = [m.value.feedback.progress for m in bag.messages(
            ['/turtle_traj/draw/_action/feedback'], deserialize=True)]
        assert feedback == sorted(feedback) and 0.0 < feedback[0] < feedback[-1] <= 1.0
    metadata = (path / 'metadata.yaml').read_text()
    assert 'version: 9' in metadata and 'storage_identifier: mcap' in metadata
    assert 'type_description_hash: RIHS01_' in metadata.replace('\n', ' ').replace('  ', ' ') \
        or 'RIHS01_' in metadata


def test_the_mcap_file_is_what_rosbag2s_reader_needs(recorded):
    """Read with `mcap` and `mcap-ros2-support`, independently of the writer."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory

    path, _ = recorded
    (mcap_file,) = path.glob('*.mcap')
    with open(mcap_file, 'rb') as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        assert summary is not None and summary.statistics is not None
        assert summary.statistics.message_count > 0
        for channel in summary.channels.values():
            assert channel.message_encoding == 'cdr'
            assert summary.schemas[channel.schema_id].encoding == 'ros2msg'
        poses = [(message.x, message.y) for _, channel, _, message
                 in reader.iter_decoded_messages(topics=['/turtle1/pose'])]
    with Bag(path) as bag:
        expected = [(m.value.x, m.value.y)
                    for m in bag.messages(['/turtle1/pose'], deserialize=True)]
    assert poses == expected and len(poses) > 300


def test_recorded_commands_replayed_in_lockstep_give_the_same_poses_to_the_bit(recorded,
                                                                               rclpy_context,
                                                                               tmp_path):
    from geometry_msgs.msg import Twist
    from turtlesim.msg import Pose

    from turtle_traj.apps.in_process import LockstepSim
    from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
    path, _ = recorded
    with Bag(path) as bag:
        commands = [(m.time_ns, m.raw) for m in bag.messages(['/turtle1/cmd_vel'])]
        recorded_poses = {m.time_ns: (m.value.x, m.value.y, m.value.theta)
                          for m in bag.messages(['/turtle1/pose'], deserialize=True)}
    sim = LockstepSim(context=rclpy_context, output_dir=tmp_path / 'replay')
    try:
        publisher = sim.client.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
        replayed = {}
        sim.client.create_subscription(
            Pose, 'turtle1/pose', lambda pose: replayed.__setitem__(
                round(sim.sim_time_s * 1e9), (pose.x, pose.y, pose.theta)), TURTLE_TOPIC_QOS)
        assert sim.spin_until(lambda: publisher.get_subscription_count() > 0 and replayed)
        pending = list(commands)
        end_ns = max(recorded_poses)
        while round(sim.sim_time_s * 1e9) < end_ns:
            now_ns = round(sim.sim_time_s * 1e9)
            while pending and pending[0][0] <= now_ns:  # at its recorded time
                publisher.publish(pending.pop(0)[1])
            sim.spin_sim_seconds(0.016)
    finally:
        sim.close()
    common = sorted(set(recorded_poses) & set(replayed))
    assert len(common) >= len(recorded_poses) - 2
    assert [replayed[t] for t in common] == [recorded_poses[t] for t in common]


def test_the_player_says_how_late_its_latest_message_went(recorded, rclpy_context):
    """A wait that overruns once (a stalled publish() or process) shows in `latest_s`: open
    loop, the command before acted that much longer."""
    from rclpy.node import Node

    from turtle_traj.bags.player import Player
    path, _ = recorded
    stall_s, waits = 0.15, []

    def wait(seconds: float) -> None:
        waits.append(seconds)
        time.sleep(seconds + (stall_s if len(waits) == 5 else 0.0))
    node = Node('player_under_test', context=rclpy_context)
    try:
        with Bag(path) as bag:
            player = Player(node, bag)
            assert player.latest_s == 0.0
            count = player.play(rate=20.0, wait=wait)
            assert count == bag.counts['/turtle1/cmd_vel']
    finally:
        node.destroy_node()
    assert len(waits) > 5 and player.latest_s >= stall_s


def test_the_plots_show_the_recorded_run(recorded, tmp_path):
    from turtle_traj.bags.plots import PANELS, panel, read_run, write_plots
    path, _ = recorded
    written = write_plots(path, tmp_path / 'plots')
    assert [file.name for file in written] == [f'{name}.png' for name in PANELS]
    assert all(file.stat().st_size > 5000 for file in written)
    run = read_run(path)
    figure = panel(run, 'path')
    (axes,) = figure.axes
    driven = [line for line in axes.lines if line.get_label() == 'driven'][0]
    with Bag(path) as bag:  # the poses, read apart from the plot's own reading
        poses = np.array([(m.value.x, m.value.y) for m in bag.messages(
            ['/turtle1/pose'], deserialize=True)])
    assert np.array_equal(driven.get_xydata(), poses)
    assert axes.get_xlabel() == 'x [m]' and axes.get_ylabel() == 'y [m]'
    speeds = panel(run, 'speeds').axes[0]
    limits = sorted({line.get_ydata()[0] for line in speeds.lines if line.get_linestyle() == ':'})
    assert limits == [-2.0, -1.0, 1.0, 2.0]  # the node's speed limits, from the bag
    progress = panel(run, 'progress').axes[0].lines[0].get_ydata()
    assert progress[-1] > 90.0


def test_a_full_disk_ends_the_recording_and_keeps_what_came_before(tmp_path, monkeypatch):
    from turtle_traj.bags.writer import BagWriter, Topic
    writer = BagWriter(tmp_path / 'bag', [Topic('/chatter', 'std_msgs/msg/String')])
    real_write = writer._writer.write
    written = []

    def write(connection, time_ns, data):
        if len(written) == 5:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        written.append(time_ns)
        real_write(connection, time_ns, data)
    monkeypatch.setattr(writer._writer, 'write', write)
    message = b'\x00\x01\x00\x00\x03\x00\x00\x00hi\x00\x00'  # CDR of std_msgs/String 'hi'
    results = [writer.write('/chatter', index, message) for index in range(8)]
    writer.close()
    assert results == [True] * 5 + [False] * 3
    assert 'No space left on device' in writer.error
    with Bag(tmp_path / 'bag') as bag:
        assert [m.time_ns for m in bag.messages()] == [0, 1, 2, 3, 4]


@pytest.mark.parametrize('problem', ['missing', 'a file', 'no metadata', 'corrupt',
                                     'a huge record', 'truncated'])
def test_a_bad_bag_is_refused_saying_what_is_wrong(recorded, tmp_path, problem):
    path, _ = recorded
    bad = tmp_path / 'bad'
    expected = {'missing': 'no bag at', 'a file': 'is not a bag folder',
                'no metadata': 'has no metadata.yaml', 'corrupt': 'is not a readable bag',
                'a huge record': 'is not a readable bag',
                'truncated': 'is not a readable bag'}[problem]
    if problem == 'a file':
        bad.write_text('hello')
    elif problem != 'missing':
        shutil.copytree(path, bad)
        (mcap_file,) = bad.glob('*.mcap')
        if problem == 'no metadata':
            (bad / 'metadata.yaml').unlink()
        elif problem == 'corrupt':
            mcap_file.write_bytes(b'\x89MCAP0\r\n' + random.Random(7).randbytes(4000))
        elif problem == 'a huge record':  # a header record claiming 2**63 - 1 bytes
            mcap_file.write_bytes(b'\x89MCAP0\r\n\x01' + struct.pack('<Q', 2**63 - 1)
                                  + bytes(4000))
        else:
            mcap_file.write_bytes(mcap_file.read_bytes()[:len(mcap_file.read_bytes()) // 2])
    with pytest.raises(BagError, match=expected):
        with Bag(bad) as bag:
            list(bag.messages())


def test_nothing_is_written_over_and_an_unwritable_place_is_refused(recorded, tmp_path):
    from turtle_traj.bags.writer import BagWriter, Topic
    path, _ = recorded
    before = sorted((file.name, file.stat().st_size) for file in path.iterdir())
    with pytest.raises(BagError, match='exists: a bag is never written over'):
        BagWriter(path, [Topic('/chatter', 'std_msgs/msg/String')])
    assert sorted((file.name, file.stat().st_size) for file in path.iterdir()) == before
    blocker = tmp_path / 'a_file'
    blocker.write_text('')
    with pytest.raises(BagError, match='cannot write a bag at'):
        BagWriter(blocker / 'bag', [Topic('/chatter', 'std_msgs/msg/String')])


def _cli(*args: str, **kwargs) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, '-m', 'turtle_traj.cli', *args], capture_output=True,
                          text=True, timeout=120, **kwargs)


@pytest.mark.system
def test_the_command_line_refuses_unknown_topics_and_bad_bags(recorded, tmp_path):
    path, _ = recorded
    done = _cli('play', str(path), '--topics', '/turtle9/cmd_vel')
    assert done.returncode == 2 and 'has no topic /turtle9/cmd_vel; it has:' in done.stderr
    done = _cli('play', str(tmp_path / 'nothing'))
    assert done.returncode == 2 and 'no bag at' in done.stderr
    done = _cli('plot', str(tmp_path))
    assert done.returncode == 2 and 'has no metadata.yaml' in done.stderr
    done = _cli('record', '--output', str(path))
    assert done.returncode == 2 and 'exists: a bag is never written over' in done.stderr
    done = _cli('record', '--output', str(tmp_path / 'new'), '/no/such/topic')
    assert done.returncode == 2 and 'no publisher on /no/such/topic' in done.stderr
    assert not (tmp_path / 'new').exists()


def _replay_report(radial: np.ndarray, applied: np.ndarray, played: str) -> str:
    """What the simulator did with the replayed commands, step by step (each pose echoes the
    velocities it applied), and what the player said of its timing. (Once 0.185 m off: one of
    the circle's first commands acted at least 9 steps, as when a publish() waits 333 ms on a
    shared-memory port's health check; our Fast DDS profile now sends by UDP only.)"""
    first = int(np.argmax(radial > 0.05))
    changes = np.flatnonzero(np.any(np.diff(applied, axis=0) != 0, axis=1))
    runs = np.diff(np.concatenate(([-1], changes, [len(applied) - 1])))
    longest = int(np.argmax(runs))
    return (f'{radial.max():.3f} m off the circle, past 0.05 m from pose {first} of '
            f'{len(radial)}; applied turn rate mean {applied[:, 1].mean():.3f} rad/s (the '
            f'circle: 1.0 at 1 m/s), first ones {np.round(applied[:12, 1], 3).tolist()}; the '
            f'longest one command acted: {runs[longest]} steps, from pose '
            f'{int(runs[:longest].sum())}; the player: {played.strip()}')


@pytest.mark.system
def test_record_and_play_on_the_real_programs(tmp_path, rclpy_context):
    """`turtle-traj record` ended by SIGINT mid-run keeps every pose it received; `turtle-traj
    play` of its cmd_vel into a fresh simulator drives the turtle along the recorded path."""
    from turtle_traj.api.ros_interface import make_goal
    from turtle_traj.client.traj_client import TrajClient
    from turtle_traj.core.registry import BY_NAME
    from turtle_traj.testing.processes import program
    bag = tmp_path / 'run'
    with program('turtle_traj', '--with-sim', cwd=tmp_path):
        with TrajClient(connect_timeout_s=30.0) as client:
            assert client.call('reset').success
            recorder = subprocess.Popen([sys.executable, '-m', 'turtle_traj.cli', 'record',
                                         '--output', str(bag)], stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, text=True)
            line = recorder.stdout.readline()
            assert line.startswith('recording 7 topics'), line + recorder.stderr.read()
            client.draw(make_goal(BY_NAME['circle'], {'size': 1.0}), timeout_s=2.5)
            recorder.send_signal(signal.SIGINT)  # mid-run: the circle was cancelled at 2.5 s
            said = recorder.communicate(timeout=30)[0]
    assert recorder.returncode == 0, said
    with Bag(bag) as recording:
        times = np.array([m.time_ns for m in recording.messages(['/turtle1/pose'])]) * 1e-9
        poses = [m.value for m in recording.messages(['/turtle1/pose'], deserialize=True)]
        path = np.array([(pose.x, pose.y) for pose in poses])
        speeds = np.array([pose.linear_velocity for pose in poses])
        assert f'/turtle1/pose {len(times)}' in said
    # Stamped on arrival: a starved recorder (or simulator) takes them late, never out of order.
    assert np.all(np.diff(times) >= 0.0)
    # Every recorded pose is one the simulator published: on the circle of radius 1 m left of
    # the spawn pose, in the order the turtle drove it. (How many arrived is up to DDS under
    # load: turtlesim's publisher keeps only its last 7, as for `ros2 bag record`.)
    offset = path - (SPAWN_XY_M, SPAWN_XY_M + 1.0)
    assert np.abs(np.hypot(*offset.T) - 1.0).max() < 0.02
    around = np.unwrap(np.arctan2(offset[:, 1], offset[:, 0]))
    assert np.all(np.diff(around) >= -1e-9) and around[-1] - around[0] > 1.0
    assert len(times) > 100

    with program('turtle_traj.sim', cwd=tmp_path):
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.node import Node
        from turtlesim.msg import Pose

        from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
        from turtle_traj.rosutils.runtime import spin_until
        node = Node('replay_observer', context=rclpy_context)
        executor = SingleThreadedExecutor(context=rclpy_context)
        executor.add_node(node)
        replayed = []
        node.create_subscription(Pose, 'turtle1/pose', replayed.append, TURTLE_TOPIC_QOS)
        try:
            player = subprocess.Popen([sys.executable, '-m', 'turtle_traj.cli', 'play',
                                       str(bag)], stdout=subprocess.PIPE, text=True)
            assert spin_until(executor, lambda: player.poll() is not None, timeout_s=60.0)
            spin_until(executor, lambda: False, timeout_s=1.5)  # the last command runs out
            played = player.stdout.read()
            assert player.returncode == 0 and 'played' in played
        finally:
            executor.shutdown()
            node.destroy_node()
    from turtle_traj.core.geometry.projection import NearestOnPolyline
    moved = np.array([(p.x, p.y) for p in replayed if p.linear_velocity > 0])
    assert len(moved) > 100
    # Open loop on the wall clock, a command acts for as long as the next one takes to come. A
    # loaded machine mostly moves the turtle further or less far along the path (63 mm and 209
    # mm from the recorded path seen with both cores busy): every command turns it on about the
    # same circle, and only the controller's small corrections, now acting for other durations,
    # move it off (23 mm seen). So: on the recorded circle, the same way round, most of the
    # recorded sweep; and a figure against the recorded path itself (0-15 mm when quiet). The
    # lock-step replay above is the exact check.
    replay_offset = moved - (SPAWN_XY_M, SPAWN_XY_M + 1.0)
    radial = np.abs(np.hypot(*replay_offset.T) - 1.0)
    applied = np.array([(p.linear_velocity, p.angular_velocity) for p in replayed
                        if p.linear_velocity > 0])
    assert radial.max() < 0.1, _replay_report(radial, applied, played)
    swept = np.unwrap(np.arctan2(replay_offset[:, 1], replay_offset[:, 0]))
    assert np.all(np.diff(swept) >= -1e-9)
    assert swept[-1] - swept[0] > 0.8 * (around[-1] - around[0])
    off = NearestOnPolyline(path).distances(moved[:int(np.count_nonzero(speeds > 0))])
    print(f'real-time replay: {1e3 * off.max():.1f} mm at most from the recorded path, '
          f'median {1e3 * np.median(off):.1f} mm')


def test_a_run_on_a_base_records_its_odometry_and_stamped_commands(rclpy_context, tmp_path):
    """On a base the node drives by nav_msgs/Odometry and commands geometry_msgs/TwistStamped:
    those are what it records, and what `plot` draws."""
    pytest.importorskip('mujoco')
    from turtle_traj_interfaces.srv import Move

    from turtle_traj.apps.base_system import BaseSystem
    from turtle_traj.bags.plots import read_run
    system = BaseSystem(context=rclpy_context, output_dir=tmp_path / 'output',
                        record_dir=str(tmp_path / 'bags'))
    try:
        assert system.call(Move, 'move', Move.Request(distance=0.3)).success
        odometry = np.array([(x, y) for _t, x, y, _yaw in system.odometry])
    finally:
        system.close()
    (bag,) = (tmp_path / 'bags').iterdir()
    with Bag(bag) as reader:
        assert reader.topics['/odom'] == 'nav_msgs/msg/Odometry'
        assert reader.topics['/cmd_vel'] == 'geometry_msgs/msg/TwistStamped'
        commands = [m.value.twist.linear.x for m in reader.messages(['/cmd_vel'],
                                                                   deserialize=True)]
    assert max(commands) > 0.1 and commands[-1] == 0.0
    run = read_run(bag)
    assert run.poses[-1, 1] == pytest.approx(odometry[-1, 0], abs=1e-3)  # where it drove
    assert run.poses[:, 1].max() == pytest.approx(0.3, abs=0.003)

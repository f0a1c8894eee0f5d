"""A drawing judged from our simulator's own record, through ROS (lock-step, in-process): what
the pen drew and what the run called are the simulator's, never the driver's word."""

import json

from turtle_traj_interfaces.srv import DrawShape
from turtlesim.srv import TeleportAbsolute

from tests.test_grading import SQUARE_TASK
from turtle_traj.apps.in_process import InProcessSystem
from turtle_traj.core.grading.judge import Record, judge
from turtle_traj.core.grading.task import read_task
from turtle_traj.sim.run_record import RunRecord


def test_a_square_drawn_through_ros_is_judged_from_the_simulators_record(rclpy_context,
                                                                         tmp_path):
    system = InProcessSystem(context=rclpy_context, output_dir=tmp_path)
    try:
        system.sim.record = RunRecord()
        square = system.call(DrawShape, 'draw_square', DrawShape.Request(size=2.0))
        assert square.success, square.message
        system.spin_sim_seconds(0.2)
        path = tmp_path / 'record.json'
        system.sim.record.save(path)
        record = Record.from_simulator(json.loads(path.read_text()))
        checks = judge(read_task(SQUARE_TASK), record)
        assert all(check.passed for check in checks), [check.message for check in checks]
        assert len(record.strokes) == 1  # one stroke: the pen never lifted
        system.call(TeleportAbsolute, '/turtle1/teleport_absolute',
                    TeleportAbsolute.Request(x=2.0, y=2.0, theta=0.0))
        cheated = Record.from_simulator(system.sim.record.as_dict())
        no_teleport = next(check for check in judge(read_task(SQUARE_TASK), cheated)
                           if check.name == 'no_teleport')
        assert not no_teleport.passed and 'teleport_absolute' in no_teleport.message
    finally:
        system.close()


def test_the_simulator_program_refuses_a_record_it_cannot_write_as_json(capsys):
    from turtle_traj.apps.sim import main
    assert main(['--record', 'run.txt']) == 2
    assert '--record must name a .json file, got run.txt' in capsys.readouterr().err

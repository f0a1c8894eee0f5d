"""Grading a class: the square lab's sample submissions, each run in its own room against the
grader's simulator, in parallel, and judged from the simulator's record.

Every sample gets the grade `expected_grades.yaml` gives it; the hostile ones are contained:
the snoop sees no other run and changes nothing of the grader's, the socket reaches no port on
this machine (the suite listens on the one it tries), the fork bomb is held by the tasks limit
and its run ends at the time limit, the kill is seen in the simulator's record. The reports
(class page, spreadsheet, summary, Gradescope's results) carry every student.
"""

import csv
import json
import os
import shutil
import socket
import time
from pathlib import Path

import numpy as np
import pytest
import yaml

from turtle_traj.apps.grade import load_task
from turtle_traj.core.grading.task import read_task
from turtle_traj.core.turtlesim_contract import PIXELS_PER_METER
from turtle_traj.grading import sandbox
from turtle_traj.grading.grader import ROOM_GRACE_S, grade_class
from turtle_traj.grading.reports import exit_status, write_reports
from turtle_traj.grading.sandbox import RunGroup, RunLimits, student_command
from turtle_traj.rosutils.priority import NICE

LAB = Path(__file__).resolve().parents[1] / 'src' / 'turtle_traj' / 'labs' / 'square'
SOCKET_PORT = 47815  # where samples/hostile_socket knocks
# Linux's sched_prio_to_weight for nice -10 to 0 (kernel/sched/core.c)
_NICE_WEIGHTS = {-10: 9548, -9: 7620, -8: 6100, -7: 4904, -6: 3906, -5: 3121, -4: 2501,
                 -3: 1991, -2: 1586, -1: 1277, 0: 1024}


def test_the_students_sandbox_hides_the_grader_and_binds_only_its_work(tmp_path):
    """The command as bubblewrap gets it: the grader's folders empty and read-only, the work
    folder bound after them (the only writable place besides its own /tmp), a process
    namespace of its own, no network for a build, the limits before the program."""
    work, secret = tmp_path / 'out' / 'alice' / 'work', tmp_path / 'out'
    work.mkdir(parents=True)
    argv = student_command(['python3', 'square.py'], work, [secret], {'ROS_DOMAIN_ID': '7'},
                           RunLimits(cpu_s=9, tasks=33), network=False)
    line = ' '.join(argv)
    assert argv[0] == shutil.which('bwrap') and '--unshare-pid' in argv
    assert '--unshare-net' in argv and '--clearenv' in argv
    hide, bind, read_only = (line.index(f'--tmpfs {secret}'),
                             line.index(f'--bind {work} {work}'),
                             line.index(f'--remount-ro {secret}'))
    assert hide < bind < read_only
    assert '--remount-ro /tmp ' not in line  # its scratch space stays writable
    assert argv[-2:] == ['python3', 'square.py']
    assert '--cpu=9' in argv and '--nproc=33' in argv  # without a control group
    grouped = student_command(['true'], work, [secret], {}, RunLimits(), network=True)
    assert '--unshare-net' not in grouped  # a run shares its room's loopback


def test_a_task_may_take_a_package_or_a_script():
    task = load_task(LAB / 'task.yaml')
    assert (task.entry_point, task.script) == ('turtle_square/square', 'square.py')
    assert task.max_score == 11 and task.settle_s == 5.0
    assert read_task({'run': {'script': 'a.py'}, 'expected': {'shape': 'circle', 'size': 1},
                      'checks': {'shape': 1}}).entry_point == ''


@pytest.mark.skipif(not RunGroup.available(), reason='needs root and cgroup v1 controllers')
def test_a_run_s_cpu_quota_holds_four_of_the_kernel_s_slices_at_a_control_program_s_weight():
    """A core draws a group's quota a slice at a time: with two slices of quota, a flood on one
    core took them and the student's node on the other stalled mid-side. Within its quota a
    run weighs what a program at our control programs' nice does (the kernel's weight table)."""
    group = RunGroup(f'{os.getpid()}-quota', RunLimits())
    try:
        quota = int((group.paths['cpu'] / 'cpu.cfs_quota_us').read_text())
        period = int((group.paths['cpu'] / 'cpu.cfs_period_us').read_text())
        weight = int((group.paths['cpu'] / 'cpu.shares').read_text())
    finally:
        group.remove()
    slice_us = int(Path('/proc/sys/kernel/sched_cfs_bandwidth_slice_us').read_text())
    assert quota == pytest.approx(RunLimits().cpu_share * period, abs=1)
    assert quota >= 4 * slice_us
    assert period - quota <= 60_000  # a throttled run waits at most this long
    assert weight == _NICE_WEIGHTS[NICE]


@pytest.fixture(scope='module')
def graded(tmp_path_factory):
    """The samples graded once, with a listener on the port the socket sample tries."""
    sandbox.bubblewrap()  # fails here, with the reason, where bubblewrap is missing
    out = tmp_path_factory.mktemp('grades')
    listener = socket.create_server(('127.0.0.1', SOCKET_PORT))
    listener.setblocking(False)
    task = load_task(LAB / 'task.yaml')
    started = time.monotonic()
    try:
        results = grade_class(task, LAB / 'samples', out)
        seconds = time.monotonic() - started
        try:
            listener.accept()
            knocked = True
        except BlockingIOError:
            knocked = False
    finally:
        listener.close()
    page = write_reports(task, results, out)
    return task, {result.name: result for result in results}, out, page, seconds, knocked


@pytest.mark.system
@pytest.mark.timeout(400)
def test_every_sample_gets_its_expected_grade(graded):
    task, results, _out, _page, _seconds, _knocked = graded
    expected = yaml.safe_load((LAB / 'samples' / 'expected_grades.yaml').read_text())
    got = {name: result.score for name, result in results.items()}
    assert got == expected, {name: results[name].ended for name in got
                             if got[name] != expected.get(name)}
    assert exit_status(list(results.values())) == 1
    assert 'did not build' in results['not_building'].ended
    assert "package directory 'source/turtle_square' does not exist" in \
        results['not_building'].ended
    never = results['never_stops']
    assert 'time limit' in never.ended
    assert [check.message for check in never.checks if not check.passed][0].startswith(
        'the turtle never stopped: still turning at 1.00 rad/s')


@pytest.mark.system
def test_hostile_samples_are_contained(graded):
    task, results, out, _page, seconds, knocked = graded
    snoop = results['hostile_snoop'].log
    assert 'snoop: wrote /tmp/intruder.txt' in snoop  # its own /tmp, gone with the run
    assert not Path('/tmp/intruder.txt').exists()
    runs_line = next(line for line in snoop.splitlines() if line.startswith(
        f'snoop: {out / "runs"}:'))
    assert runs_line.endswith("['hostile_snoop']")  # no other run's folder
    for target in ('record.json', 'outcome.json'):
        assert f'cannot write {out / "runs" / "hostile_snoop" / target}: Read-only' in snoop
    assert not (out / 'runs' / 'intruder.txt').exists()
    assert not knocked, 'a run reached a port of this machine'
    assert 'socket: no connection to 127.0.0.1:47815' in results['hostile_socket'].log
    fork = results['hostile_fork']
    assert 'time limit' in fork.ended and 'refused more processes' in fork.ended
    # its room ended within the grace after the time limit (the grader's own time on it
    # counts the wait for a room's slot too, which other graders' rooms may hold)
    assert task.time_limit_s <= fork.room_s < task.time_limit_s + ROOM_GRACE_S
    kill = {check.name: check for check in results['hostile_kill'].checks}['no_teleport']
    assert kill.score == 0 and 'called kill' in kill.message
    leftovers = [path for controller in RunGroup.CONTROLLERS
                 for path in (sandbox.CGROUP_ROOT / controller).glob(
                     f'{sandbox.GROUP_PREFIX}{os.getpid()}-*')] if RunGroup.available() else []
    assert leftovers == []
    assert seconds < 4 * task.time_limit_s  # the slowest runs end at the time limit


@pytest.mark.system
def test_the_reports_carry_every_student(graded):
    task, results, out, page, _seconds, _knocked = graded
    html = page.read_text()
    for name, result in results.items():
        assert f'id="{name}"' in html
        assert (result.run_dir / 'picture.png').stat().st_size > 1000
        gradescope = json.loads((result.run_dir / 'results.json').read_text())
        assert gradescope['score'] == result.score
        assert [test['name'] for test in gradescope['tests']] == list(task.points)
        assert all({'name', 'score', 'max_score', 'output'} <= set(test)
                   for test in gradescope['tests'])
    with (out / 'grades.csv').open() as file:
        rows = list(csv.DictReader(file))
    assert {row['student']: float(row['score']) for row in rows} == {
        name: result.score for name, result in results.items()}
    summary = json.loads((out / 'summary.json').read_text())
    assert len(summary['students']) == len(results) and summary['max_score'] == 11


@pytest.mark.system
def test_a_run_replays_in_the_browser_as_the_simulator_saw_it(graded):
    """The replay page, in headless chromium: at the end the canvas holds the pen's white
    strokes where the record has them; at the start, none; the checks are listed."""
    import base64
    import io

    from PIL import Image

    from turtle_traj.core.turtlesim_contract import CANVAS_HEIGHT_M
    from turtle_traj.testing.browser import chromium

    _task, results, out, page, _seconds, _knocked = graded
    right = results['right']
    assert 'runs/right/replay.html' in page.read_text()
    record = json.loads((right.run_dir / 'record.json').read_text())
    _time, x0, y0, x1, y1 = record['segments'][len(record['segments']) // 2]
    middle = (round((x0 + x1) / 2 * PIXELS_PER_METER),
              round((CANVAS_HEIGHT_M - (y0 + y1) / 2) * PIXELS_PER_METER))

    def canvas(driver) -> np.ndarray:
        url = driver.execute_script("return document.getElementById('view').toDataURL()")
        image = Image.open(io.BytesIO(base64.b64decode(url.split(',', 1)[1])))
        return np.asarray(image.convert('RGB'))

    with chromium() as driver:
        driver.get((right.run_dir / 'replay.html').as_uri())
        at_end = canvas(driver)
        x, y = middle
        assert (at_end[y - 1:y + 2, x - 1:x + 2] > 240).all(axis=2).any()  # a white stroke
        driver.execute_script("const s = document.getElementById('time'); s.value = 0;"
                              "s.dispatchEvent(new Event('input'))")
        assert not (canvas(driver)[y - 1:y + 2, x - 1:x + 2] > 240).all(axis=2).any()
        checks = driver.execute_script(
            "return [...document.querySelectorAll('#checks li')].map(li => li.textContent)")
    assert len(checks) == 6 and checks[0].startswith('\u2713 shape 4/4: the drawing lies')

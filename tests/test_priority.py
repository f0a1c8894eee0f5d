"""The node's and the simulator's programs ask for a scheduling priority ahead of ordinary work,
with a short slice, for every thread, and say why not when they may not have it
(`turtle_traj.rosutils.priority`). Each case runs in a Python of its own: the test process keeps
its own priority."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from turtle_traj.rosutils.priority import NICE, SLICE_S
from turtle_traj.testing.processes import program_nice

_PROBE = '''
import json, os, sys, threading, time
from unittest import mock
from turtle_traj.rosutils import priority
from turtle_traj.testing.processes import program_nice
started = threading.Event()
early = threading.Thread(target=lambda: (started.set(), time.sleep(5)), daemon=True)
early.start()  # a thread a library started before: it is raised too
started.wait()
if sys.argv[1] == 'refused':
    with mock.patch.object(os, 'setpriority', side_effect=PermissionError(1, 'Not permitted')):
        said = priority.raise_priority(-10)
else:
    said = priority.raise_priority(int(sys.argv[1]))
late, listed = [], threading.Event()
after = threading.Thread(target=lambda: (late.append(os.getpriority(os.PRIO_PROCESS, 0)),
                                         listed.wait(5)))
after.start()
nice = program_nice(os.getpid())
slices = set()
for thread in os.listdir('/proc/self/task'):  # the scheduler's own account (CONFIG_SCHED_DEBUG)
    try:
        with open(f'/proc/self/task/{thread}/sched') as sched:
            slices |= {int(line.split(':')[1]) for line in sched if line.startswith('se.slice')}
    except OSError:
        pass
listed.set()
after.join()
print(json.dumps([said.nice, said.granted, str(said), sorted(nice), late[0], sorted(slices)]))
'''


def _probe(asked: str) -> list:
    done = subprocess.run([sys.executable, '-c', _PROBE, asked], capture_output=True, text=True,
                          check=True, timeout=60)
    return json.loads(done.stdout)


@pytest.mark.skipif(os.geteuid() != 0, reason='a negative nice value needs root here')
def test_every_thread_and_those_started_later_run_at_the_nice_value_asked_for():
    nice, granted, said, threads, later, slices = _probe('-7')
    assert (nice, granted, threads, later) == (-7, True, [-7], -7)
    if slices:  # the scheduler shows its slices: every thread has the one asked for
        assert slices == [round(SLICE_S * 1e9)]
        assert said == f'scheduling priority: nice -7, slice {SLICE_S * 1e3:g} ms'
    else:
        assert said.startswith('scheduling priority: nice -7')


def test_a_priority_refused_is_said_with_the_way_to_allow_it():
    nice, granted, said, threads, _, _ = _probe('refused')
    assert not granted and nice == threads[0] == os.getpriority(os.PRIO_PROCESS, 0)
    assert 'nice -10 refused: Not permitted' in said and 'CAP_SYS_NICE' in said
    assert '--nice 0' in said


def test_a_priority_already_as_high_is_kept():
    nice, granted, _, threads, _, _ = _probe('19')
    assert granted and nice == threads[0] == os.getpriority(os.PRIO_PROCESS, 0)


@pytest.mark.system
@pytest.mark.parametrize('program', ['turtle_traj', 'turtle_traj.sim'])
def test_the_node_alone_and_the_simulator_run_ahead_of_ordinary_work_and_say_so(
        tmp_path, program):
    node = subprocess.Popen([sys.executable, '-m', program, '--ros-args', '-r',
                             '__ns:=/priority_test'], cwd=tmp_path, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)
    try:
        said = []
        for line in node.stderr:  # the line comes as the node is made
            said.append(line)
            if 'scheduling priority' in line:
                break
        nice = program_nice(node.pid)
    finally:
        node.kill()
        node.communicate(timeout=15)
    if os.geteuid() == 0:
        assert nice == {NICE} and f'scheduling priority: nice {NICE}' in said[-1], said
    else:
        assert 'refused' in said[-1] and 'CAP_SYS_NICE' in said[-1], said

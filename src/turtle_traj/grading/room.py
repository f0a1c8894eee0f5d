"""`python -m turtle_traj.grading.room SPEC`: one student's run, inside its room (see
`grading.sandbox`).

It runs the grader's simulator (a recording `SimNode`, in real time) and, beside it, the
student's command in the student's sandbox; it ends the run when the student's program has
ended and the turtle stands, when the turtle has stood `settle_s` after moving (a node that
spins on after its drawing), or at the wall-time limit (the program is killed). Then it saves
what the simulator saw (`record.json`), the canvas (`canvas.png`) and how the run ended
(`outcome.json`) into the run's folder, where the student cannot write. The student's output
goes to `student.log`, of at most the sandbox's file size. Asked for, it serves the
simulator's live view, watch only, on a Unix socket (`grading.forward` reaches it).
"""

from __future__ import annotations

import contextlib
import gc
import json
import os
import signal
import subprocess
import sys
import time
from collections import deque
from dataclasses import asdict, dataclass
from pathlib import Path

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.task import Future

from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.rosutils.fastdds_profile import keep_to_this_machine
from turtle_traj.rosutils.runtime import events_executor
from turtle_traj.sim.live_view import SimLiveView, turtle_icon_png
from turtle_traj.sim.node import SimNode
from turtle_traj.web.server import WebServer

WATCH_PERIOD_S = 0.05
_RECENT_STEPS = 16  # a step's lateness shows in one; a skipped step in all that follow
AFTER_EXIT_S = 1.5  # the simulator goes on after the program ends, while the turtle moves
MOVING = (1e-3, 1e-3)  # m/s, rad/s


@dataclass(frozen=True)
class RoomSpec:
    """What the grader asks of the room (written as JSON into the run's folder)."""

    command: list[str]
    run_dir: str
    wall_s: float
    settle_s: float
    domain_id: int
    live_view: str = ''  # a Unix socket to serve the simulator's live view on (watch only)


@dataclass
class Outcome:
    """How the run ended."""

    ended: str  # 'exited', 'settled', 'time limit', 'no start'
    exit_code: int | None
    student_s: float  # from the program's start to the run's end
    lost_steps: int = 0  # the simulator's steps too late to be taken while the program ran

    def describe(self) -> str:
        if self.ended == 'exited':
            return f'the program exited with status {self.exit_code} after {self.student_s:.1f} s'
        if self.ended == 'settled':
            return (f'the program still ran when the turtle had settled ({self.student_s:.1f} s)'
                    '; it was stopped')
        if self.ended == 'time limit':
            return f'the program was stopped at the time limit ({self.student_s:.1f} s)'
        return 'the program could not be started'


class Watch:
    """Ends the run (see the module), on the simulator's timer."""

    def __init__(self, sim: SimNode, spec: RoomSpec, log) -> None:
        self.sim, self.spec = sim, spec
        self.done = Future()
        self.started = time.monotonic()
        self.first_step: float | None = None
        self.steps = 0
        self.lowest_deficit = 0
        self.recent_deficits: deque[int] = deque(maxlen=_RECENT_STEPS)
        sim.step_listeners.append(self._stepped)
        self.moved = False
        self.still_since = self.started
        self.exited_at: float | None = None
        self.process = subprocess.Popen(spec.command, stdin=subprocess.DEVNULL, stdout=log,
                                        stderr=subprocess.STDOUT, start_new_session=True)
        sim.create_timer(WATCH_PERIOD_S, self.check)

    def check(self) -> None:
        if self.done.done():
            return
        now = time.monotonic()
        moving = self._turtle_moving()
        self.moved = self.moved or moving
        if moving:
            self.still_since = now
        code = self.process.poll()
        if code is not None:
            self.exited_at = self.exited_at or now
            if not moving or now - self.exited_at >= AFTER_EXIT_S:
                self._end('exited', code, self.exited_at)
        elif now - self.started >= self.spec.wall_s:
            self._end('time limit', None, now)
        elif self.moved and now - self.still_since >= self.spec.settle_s:
            self._end('settled', None, now)

    def _stepped(self) -> None:
        """A step: how many steps behind the wall's schedule the simulator is (a late step
        that is taken is behind only until the next; a skipped one stays behind)."""
        now = time.monotonic()
        if self.first_step is None:
            self.first_step = now
        else:
            self.steps += 1
        deficit = round((now - self.first_step) / STEP_S) - self.steps
        self.lowest_deficit = min(self.lowest_deficit, deficit)  # the first step's lateness
        self.recent_deficits.append(deficit)

    @property
    def missed(self) -> int:
        """The steps the simulator's timer skipped since the program started."""
        if not self.recent_deficits:
            return 0
        return max(0, min(self.recent_deficits) - self.lowest_deficit)

    def _turtle_moving(self) -> bool:
        turtle = self.sim.world.turtles.get('turtle1')
        return turtle is not None and (abs(turtle.linear_speed) > MOVING[0]
                                       or abs(turtle.omega) > MOVING[1])

    def _end(self, ended: str, code: int | None, at: float) -> None:
        self.stop_program()
        self.done.set_result(Outcome(ended, code, round(at - self.started, 3)))

    def stop_program(self) -> None:
        """Kill the student's sandbox (its process namespace goes with its first process)."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGKILL)
            self.process.wait()


def leave_real_time() -> None:
    """Every thread of this process back on the ordinary policy (the grader put them on the
    real-time one for the run): what follows a run (the record, the canvas and the shutdown,
    33 ms of CPU here, then the interpreter's exit, about 0.1 s) must not hold up the
    simulators of the rooms still running, nor any other program."""
    for thread in os.listdir('/proc/self/task'):
        with contextlib.suppress(OSError):  # one that ended meanwhile
            os.sched_setscheduler(int(thread), os.SCHED_OTHER, os.sched_param(0))


def run(spec: RoomSpec) -> Outcome:
    """The run `spec` asks for (see the module)."""
    run_dir = Path(spec.run_dir)
    os.environ['ROS_LOG_DIR'] = str(run_dir / 'ros-log')  # the system is read-only
    keep_to_this_machine()
    rclpy.init(args=['--ros-args'], domain_id=spec.domain_id)
    sim = SimNode(record=True)
    executor = events_executor()
    executor.add_node(sim)
    if spec.live_view:
        server = WebServer('127.0.0.1', 0, turtle_icon_png, unix_socket=spec.live_view)
        executor.add_node(SimLiveView(sim, server, watch_only=True))
        server.start()
    with (run_dir / 'student.log').open('wb') as log:
        try:
            watch = Watch(sim, spec, log)
        except OSError:
            outcome = Outcome('no start', None, 0.0)
        else:
            # No collection while the program runs: the record grows by a pose a step, and a
            # full collection of a start-up's objects takes 26-32 ms, two of the simulator's
            # steps (see rosutils.runtime.run_nodes); the room lives for one run.
            gc.collect()
            gc.freeze()
            gc.disable()
            (run_dir / 'started').touch()  # the grader may start the next room
            try:
                while not watch.done.done():
                    executor.spin_until_future_complete(watch.done, timeout_sec=0.5)
            except (KeyboardInterrupt, ExternalShutdownException):
                watch._end('time limit', None, time.monotonic())
            finally:
                leave_real_time()
                watch.stop_program()
            outcome = watch.done.result()
            outcome.lost_steps = watch.missed
    sim.record.save(run_dir / 'record.json')
    sim.render().save(run_dir / 'canvas.png')
    (run_dir / 'outcome.json').write_text(json.dumps(asdict(outcome)))
    executor.shutdown()
    sim.destroy_node()
    rclpy.try_shutdown()
    return outcome


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    spec = RoomSpec(**json.loads(Path(args[0]).read_text()))
    run(spec)
    return 0


if __name__ == '__main__':
    sys.exit(main())

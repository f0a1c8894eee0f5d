"""turtle_traj's pytest plugin (registered as `turtle_traj` in the `pytest11` entry points, so
`pip install turtle_traj` brings it to every pytest run; `-p no:turtle_traj` turns it off).

Fixtures:

- `ros_domain_id`: a ROS domain of this test process's own (`claim_domain_id`);
- `rclpy_context`: the process's one rclpy context in that domain, shut down after the session;
- `turtle_sim`: our simulator and a client node in one lock-step executor (`LockstepSim`);
- `turtle_system`: the simulator, the trajectory node and a client recording the turtle's poses
  (`InProcessSystem`; `turtle_system.call(DrawShape, 'draw_square', request)`).

Lock-step: simulated time advances only as the executor spins, so a run's figures are the same
on a quiet or a loaded machine. Everything a fixture made is destroyed after its test.
Importing this module loads no ROS; the fixtures load it when a test asks for them.

A run ended by SIGTERM (`kill`, `timeout`, a CI job cancelled) ends as Ctrl-C ends it: the
test is interrupted, and fixtures, `finally` blocks and `atexit` still run, so the programs,
browsers and network namespaces the tests started are not left behind (the default action
ends the process at once). A SIGTERM handler of the user's own is left in place.
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import pytest

from turtle_traj.testing.domain import claim_domain_id

if TYPE_CHECKING:
    from rclpy.context import Context

    from turtle_traj.apps.in_process import InProcessSystem, LockstepSim


def pytest_configure(config: pytest.Config) -> None:
    """SIGTERM interrupts the run as SIGINT does (see the module's docstring)."""
    if (threading.current_thread() is threading.main_thread()
            and signal.getsignal(signal.SIGTERM) is signal.SIG_DFL):
        signal.signal(signal.SIGTERM, _Interrupter(config))
        config.add_cleanup(lambda: signal.signal(signal.SIGTERM, signal.SIG_DFL))


class _Interrupter:
    """The SIGTERM handler: interrupt this process, once (a second signal, as a process group
    and its xdist controller both send, would cut the teardown short). A pytest-xdist
    controller first passes the signal to its workers (its only children), each of which
    interrupts its own test and tears it down; interrupted alone, the controller waits 10 s for
    them and then kills them, leaving what their tests started running."""

    def __init__(self, config: pytest.Config) -> None:
        self.config = config
        self.interrupted = False

    def __call__(self, signum: int, _frame: object) -> None:
        if self.interrupted:
            return
        self.interrupted = True
        if self.config.pluginmanager.getplugin('dsession') is not None:
            for worker in _children():
                with contextlib.suppress(ProcessLookupError):
                    os.kill(worker, signum)
        raise KeyboardInterrupt(f'{signal.Signals(signum).name} received')


def _children() -> list[int]:
    """This process's child processes (Linux; none elsewhere)."""
    children: list[int] = []
    for task in Path(f'/proc/{os.getpid()}/task').glob('*'):
        with contextlib.suppress(OSError):
            children += [int(pid) for pid in (task / 'children').read_text().split()]
    return children


@pytest.fixture(scope='session')
def ros_domain_id() -> int:
    """This test process's own ROS_DOMAIN_ID (its other processes inherit it)."""
    return claim_domain_id()


@pytest.fixture(scope='session')
def rclpy_context(ros_domain_id: int) -> Iterator[Context]:
    """The process's one rclpy context (one DDS participant while it has nodes)."""
    import rclpy

    from turtle_traj.rosutils.runtime import process_context

    context, _ = process_context()
    yield context
    rclpy.try_shutdown()


@pytest.fixture
def turtle_sim(rclpy_context: Context, tmp_path) -> Iterator[LockstepSim]:
    """Our simulator and a sim-time client node in one lock-step executor."""
    from turtle_traj.apps.in_process import LockstepSim

    harness = LockstepSim(context=rclpy_context, output_dir=tmp_path / 'output',
                          client_name='test_client')
    try:
        yield harness
    finally:
        harness.close()


@pytest.fixture
def turtle_system(rclpy_context: Context, tmp_path) -> Iterator[InProcessSystem]:
    """Our simulator, the trajectory node and a pose-recording client, lock-step."""
    from turtle_traj.apps.in_process import InProcessSystem

    harness = InProcessSystem(context=rclpy_context, output_dir=tmp_path / 'output')
    try:
        yield harness
    finally:
        harness.close()

"""Test-session isolation (a private ROS domain, local discovery, logs kept out of $HOME), one
rclpy context per test process with nothing left alive between tests, and a bound on every
test's time."""

import fcntl
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

_LOCK_DIR = Path(tempfile.gettempdir()) / 'turtle_traj_domains'
# Domain ids 1..101 map onto ports every Linux machine leaves free (ROS 2 docs, "Domain ID").
_DOMAIN_IDS = range(1, 102)


def _claim_domain_id() -> tuple[int, object]:
    """Hold an exclusive lock on a free domain id for the life of this process."""
    _LOCK_DIR.mkdir(exist_ok=True)
    start = os.getpid() % len(_DOMAIN_IDS)
    for offset in range(len(_DOMAIN_IDS)):
        domain_id = _DOMAIN_IDS[(start + offset) % len(_DOMAIN_IDS)]
        lock = open(_LOCK_DIR / f'{domain_id}.lock', 'w')  # noqa: SIM115 - held until exit
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            lock.close()
            continue
        return domain_id, lock
    raise RuntimeError('no free ROS_DOMAIN_ID for this test session')


# Set before any test imports rclpy, so every context of this session uses them.
DOMAIN_ID, _domain_lock = _claim_domain_id()
os.environ['ROS_DOMAIN_ID'] = str(DOMAIN_ID)
os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
os.environ.setdefault('ROS_LOG_DIR', tempfile.mkdtemp(prefix='turtle_traj_ros_logs_'))

from tests import ros_lifecycle  # noqa: E402 - rclpy reads the environment set above
from tests.hang_watchdog import HangWatchdog  # noqa: E402

ros_lifecycle.track()
# A test whose own time limit (pytest-timeout, a Python signal) has not ended it this much later
# is stuck where Python cannot run: the watchdog process ends it. (tests/test_hang.py shortens it
# for the suites it runs.)
_HANG_GRACE_S = float(os.environ.get('TURTLE_TRAJ_HANG_GRACE_S', '30'))
_watchdog: HangWatchdog | None = None


def pytest_timeout_set_timer(item, settings) -> None:
    global _watchdog
    if _watchdog is None:
        _watchdog = HangWatchdog()
    _watchdog.arm(settings.timeout + _HANG_GRACE_S, item.nodeid)


def pytest_timeout_cancel_timer(item) -> None:
    if _watchdog is not None:
        _watchdog.disarm()


def pytest_unconfigure(config) -> None:
    if _watchdog is not None:
        _watchdog.close()


@pytest.fixture(scope='session')
def ros_context() -> Iterator[object]:
    """This test process's one rclpy context (one DDS participant while it has nodes)."""
    import rclpy

    from turtle_traj.rosutils.runtime import process_context

    context, _ = process_context()
    yield context
    rclpy.try_shutdown()


@pytest.fixture(autouse=True)
def _nothing_of_rclpy_left() -> Iterator[None]:
    """Fail a test that leaves a node, action server or client, or executor alive (after
    destroying them: never the garbage collector's job)."""
    yield
    left = ros_lifecycle.take_leftovers()
    if left:
        pytest.fail('the test left alive: ' + '; '.join(left), pytrace=False)


@pytest.fixture
def sim(ros_context, tmp_path):
    """Our simulator and a sim-time client node in one lock-step executor."""
    from turtle_traj.apps.in_process import LockstepSim

    harness = LockstepSim(context=ros_context, output_dir=tmp_path / 'output',
                          client_name='test_client')
    try:
        yield harness
    finally:
        harness.close()


@pytest.fixture
def traj(ros_context, tmp_path):
    """Simulator, trajectory node and a pose-recording client in one lock-step executor."""
    from turtle_traj.apps.in_process import InProcessSystem

    harness = InProcessSystem(context=ros_context, output_dir=tmp_path / 'output')
    try:
        yield harness
    finally:
        harness.close()


@pytest.fixture(scope='module')
def running_system(tmp_path_factory):
    """`python -m turtle_traj --with-sim` at 2x real time, in this test session's domain.

    Wall-clock time, as users run it: slow enough that a loaded machine cannot make the node
    fall many simulator steps behind.
    """
    from tests.ros_helpers import program
    from turtle_traj.client.traj_client import TrajClient

    with program('turtle_traj', '--with-sim', '--time-scale', '2',
                 cwd=tmp_path_factory.mktemp('system')) as process:
        with TrajClient(connect_timeout_s=30.0) as client:  # answers once poses reach the node
            try:
                assert client.call('reset').success
            except Exception as error:  # what the program said tells why
                raise AssertionError(f'{error}; the program said:\n{process.said()}') from error
        yield process

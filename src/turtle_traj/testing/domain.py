"""A ROS domain of this process's own, so that parallel test processes never hear each other."""

from __future__ import annotations

import fcntl
import os
import tempfile
from pathlib import Path
from typing import IO

from turtle_traj.rosutils.fastdds_profile import keep_to_this_machine

LOCK_DIR = Path(tempfile.gettempdir()) / 'turtle_traj_domains'
# Domain ids 1..101 map onto ports every Linux machine leaves free (ROS 2 docs, "Domain ID").
DOMAIN_IDS = range(1, 102)
_claimed: tuple[int, IO] | None = None


def claim_domain_id() -> int:
    """Claim a free ROS_DOMAIN_ID for the life of this process (a lock file held open) and set
    the environment every later rclpy context and child process reads: the domain, discovery
    kept to this machine (`keep_to_this_machine`), and logs kept out of $HOME. Calling it
    again returns the same id.

    Call it before rclpy is initialised: a context reads the domain when it is created.

    :raises RuntimeError: all 101 ids are held by other processes.
    """
    global _claimed
    if _claimed is None:
        _claimed = _lock_a_free_id()
        os.environ['ROS_DOMAIN_ID'] = str(_claimed[0])
        keep_to_this_machine(os.environ)
        os.environ.setdefault('ROS_LOG_DIR', tempfile.mkdtemp(prefix='turtle_traj_ros_logs_'))
    return _claimed[0]


def _lock_a_free_id() -> tuple[int, IO]:
    LOCK_DIR.mkdir(exist_ok=True)
    start = os.getpid() % len(DOMAIN_IDS)
    for offset in range(len(DOMAIN_IDS)):
        domain_id = DOMAIN_IDS[(start + offset) % len(DOMAIN_IDS)]
        lock = open(LOCK_DIR / f'{domain_id}.lock', 'w')  # noqa: SIM115 - held until exit
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            lock.close()
            continue
        return domain_id, lock
    raise RuntimeError(f'no free ROS_DOMAIN_ID: {len(DOMAIN_IDS)} test processes hold them all')

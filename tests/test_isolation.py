"""Test sessions never share a ROS domain: a second session gets a different one."""

import os
import subprocess
import sys

from tests import conftest


def test_a_concurrent_session_claims_another_domain():
    other = subprocess.run(
        [sys.executable, '-c', 'import tests.conftest as c; print(c.DOMAIN_ID)'],
        capture_output=True, text=True, timeout=30, cwd=os.path.dirname(conftest.__file__) + '/..')
    assert other.returncode == 0, other.stderr
    assert int(other.stdout) != conftest.DOMAIN_ID
    assert os.environ['ROS_DOMAIN_ID'] == str(conftest.DOMAIN_ID)
    assert os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] == 'LOCALHOST'

"""Test processes never share a ROS domain: a second process gets a different one."""

import os
import subprocess
import sys

from turtle_traj.testing.domain import claim_domain_id


def test_a_concurrent_process_claims_another_domain(ros_domain_id):
    other = subprocess.run(
        [sys.executable, '-c', 'from turtle_traj.testing.domain import claim_domain_id as c; '
         'print(c(), c())'], capture_output=True, text=True, timeout=30)
    assert other.returncode == 0, other.stderr
    first, again = (int(word) for word in other.stdout.split())
    assert first == again != ros_domain_id  # one claim per process, held for its life
    assert claim_domain_id() == ros_domain_id
    assert os.environ['ROS_DOMAIN_ID'] == str(ros_domain_id)
    # discovery kept to this machine: test_fastdds_profile checks the profile it takes

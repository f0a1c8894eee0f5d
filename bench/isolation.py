"""What every benchmark does first: a ROS domain of its own, local discovery, logs out of $HOME.

Call `isolate` before rclpy is initialised and before starting ROS programs. The domain ids lie
above the 1..101 that test sessions claim, so a benchmark never talks to a running test.
"""

import os
import tempfile

DOMAIN_IDS = {'sim': 230, 'accuracy': 231, 'latency': 232, 'soak': 229, 'cli': 228,
              'speed': 227, 'web': 226, 'lifecycle': 225, 'base': 224, 'physics': 223,
              'network': 222, 'realtime': 221, 'planning': 220, 'corners': 219}


def isolate(benchmark: str) -> None:
    """Environment for a benchmark's ROS nodes (an explicit ROS_DOMAIN_ID is kept)."""
    os.environ.setdefault('ROS_DOMAIN_ID', str(DOMAIN_IDS[benchmark]))
    os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    os.environ.setdefault('ROS_LOG_DIR', tempfile.mkdtemp(prefix='turtle_traj_bench_logs_'))

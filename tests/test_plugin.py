"""The pytest plugin as a user meets it: the README's test, in a folder of its own outside the
repository, run by a plain `pytest` that finds the plugin through its entry point."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / 'README.md'


def _readme_user_test() -> str:
    section = README.read_text().split('### Testing your own trajectories with pytest', 1)[1]
    return re.search(r'```python\n(.*?)```', section, re.S).group(1)


def test_the_plugin_is_registered_for_pytest():
    from importlib.metadata import entry_points

    (entry,) = [e for e in entry_points(group='pytest11') if e.name == 'turtle_traj']
    plugin = entry.load()
    assert {'ros_domain_id', 'rclpy_context', 'turtle_sim', 'turtle_system'} <= set(vars(plugin))


@pytest.mark.system
def test_the_readmes_user_test_passes_outside_the_repository(tmp_path):
    (tmp_path / 'test_mine.py').write_text(_readme_user_test())
    done = subprocess.run([sys.executable, '-m', 'pytest', '-q', '-p', 'no:cacheprovider',
                           'test_mine.py'], cwd=tmp_path, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert '1 passed' in done.stdout

"""ament_python build of turtle_traj for colcon: the same sources as the pip project (src/).

`colcon build` at the repository root builds this package and turtle_traj_interfaces; the
executables go to lib/turtle_traj/ (for `ros2 run`), package.xml and the launch file to
share/turtle_traj/. The version is the pip project's (pyproject.toml).
"""

import re
from pathlib import Path

from setuptools import find_packages, setup

HERE = Path(__file__).resolve().parent
PYPROJECT = (HERE / '../../pyproject.toml').resolve().read_text()
VERSION = re.search(r'^version = "([^"]+)"', PYPROJECT, re.MULTILINE).group(1)

setup(
    name='turtle_traj',
    version=VERSION,
    packages=find_packages('src'),
    package_dir={'': 'src'},
    package_data={'turtle_traj': ['drawings/*.svg', 'fastdds.xml', 'web/static/*']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/turtle_traj']),
        ('share/turtle_traj', ['package.xml']),
        ('share/turtle_traj/launch', ['launch/turtle_traj.launch.py']),
    ],
    install_requires=['setuptools'],
    zip_safe=False,
    description='Closed-loop turtle trajectories for ROS 2 Jazzy, with a pure-Python turtlesim',
    license='Apache-2.0',
    entry_points={'console_scripts': [
        'trajectory_node = turtle_traj.apps.node:main',
        'sim = turtle_traj.apps.sim:main',
        'turtle_traj = turtle_traj.cli.main:main',
        'teleop = turtle_traj.cli.teleop:main',
    ]},
)

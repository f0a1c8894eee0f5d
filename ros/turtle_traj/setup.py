"""ament_python build of turtle_traj for colcon: the same sources as the pip project (src/).

`colcon build` at the repository root builds this package and turtle_traj_interfaces; the
executables go to lib/turtle_traj/ (for `ros2 run`), package.xml and the launch file to
share/turtle_traj/. The version, description, licence and package data are the pip project's,
read from pyproject.toml: one list of the files the package carries, for both builds.
"""

from pathlib import Path

from setuptools import find_packages, setup
from setuptools.config.pyprojecttoml import load_file

HERE = Path(__file__).resolve().parent
PYPROJECT = load_file((HERE / '../../pyproject.toml').resolve())
PROJECT = PYPROJECT['project']

setup(
    name='turtle_traj',
    version=PROJECT['version'],
    packages=find_packages('src'),
    package_dir={'': 'src'},
    package_data=PYPROJECT['tool']['setuptools']['package-data'],
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/turtle_traj']),
        ('share/turtle_traj', ['package.xml']),
        ('share/turtle_traj/launch', ['launch/turtle_traj.launch.py']),
    ],
    install_requires=['setuptools'],
    zip_safe=False,
    description=PROJECT['description'],
    license=PROJECT['license']['text'],
    entry_points={'console_scripts': [
        'trajectory_node = turtle_traj.apps.node:main',
        'sim = turtle_traj.apps.sim:main',
        'turtle_traj = turtle_traj.cli.main:main',
        'teleop = turtle_traj.cli.teleop:main',
        'fleet = turtle_traj.apps.fleet:main',
        'controller_server = turtle_traj.apps.controller_server:main',
    ]},
)

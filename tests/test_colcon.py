"""The ROS user's path: `colcon build` at the repository root, then the installed tree.

colcon finds the repository's two packages at its root; `turtle_traj` (ros/) is built into a
temporary directory against the venv's ROS prefix, as a user with a sourced ROS install builds
it, with the interface package that `make setup` built and installed there from the same CMake
package (`interfaces/build.sh`): its rosidl generation, the slow part of a colcon build (70 s
here), runs once per change of the interface files, not once per test run. The launch packages
are not on PyPI: the launch file is checked by reading.
"""

import ast
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from turtle_traj.client.traj_client import TrajClient
from turtle_traj.rosutils.fastdds_profile import PROFILE_VARIABLES, RANGE_VARIABLE

pytestmark = [pytest.mark.system, pytest.mark.timeout(300)]
ROOT = Path(__file__).resolve().parents[1]
PREFIX = Path(sys.prefix)
EXECUTABLES = {'trajectory_node', 'sim', 'turtle_traj', 'teleop'}


@pytest.fixture(scope='module')
def install(tmp_path_factory) -> Path:
    colcon = shutil.which('colcon', path=str(PREFIX / 'bin'))
    if colcon is None:
        pytest.fail('colcon is not installed: `make setup` installs the dev extra')
    work = tmp_path_factory.mktemp('colcon')
    env = {**os.environ, 'CMAKE_PREFIX_PATH': str(PREFIX), 'AMENT_PREFIX_PATH': str(PREFIX)}
    built = subprocess.run(
        [colcon, '--log-base', str(work / 'log'), 'build', '--base-paths', str(ROOT / 'ros'),
         '--build-base', str(work / 'build'), '--install-base', str(work / 'install'),
         '--cmake-args', '-DBUILD_TESTING=OFF', f'-DPython3_EXECUTABLE={sys.executable}'],
        cwd=work, env=env, capture_output=True, text=True, timeout=600)
    assert built.returncode == 0, built.stdout[-3000:] + built.stderr[-3000:]
    return work / 'install'


def test_colcon_finds_both_packages_and_not_turtlesim():
    """What `colcon build` at the root builds: ours, by their build types (interfaces/turtlesim
    is for machines without ROS, and carries a COLCON_IGNORE)."""
    import argparse

    from colcon_core.package_discovery import add_package_discovery_arguments, discover_packages
    from colcon_core.package_identification import get_package_identification_extensions

    parser = argparse.ArgumentParser()
    add_package_discovery_arguments(parser)
    found = discover_packages(parser.parse_args(['--base-paths', str(ROOT)]),
                              get_package_identification_extensions())
    assert {(package.name, package.type) for package in found} == {
        ('turtle_traj', 'ros.ament_python'), ('turtle_traj_interfaces', 'ros.ament_cmake')}


def test_the_package_is_built_against_the_installed_interfaces(install):
    assert {path.name for path in install.iterdir() if path.is_dir()} == {'turtle_traj'}
    index = 'share/ament_index/resource_index/packages'
    assert (install / 'turtle_traj' / index / 'turtle_traj').is_file()
    assert (PREFIX / index / 'turtle_traj_interfaces').is_file()  # from `make setup`


def test_the_executables_package_xml_and_launch_file_are_installed(install):
    lib = install / 'turtle_traj' / 'lib' / 'turtle_traj'
    assert {path.name for path in lib.iterdir() if os.access(path, os.X_OK)} >= EXECUTABLES
    share = install / 'turtle_traj' / 'share' / 'turtle_traj'
    assert (share / 'package.xml').is_file()
    # the SVG files draw_svg reads by default (the svg_dir parameter) come along
    assert list(install.glob('turtle_traj/lib/python3*/site-packages/turtle_traj/drawings/'
                             'turtle.svg'))
    assert (share / 'launch' / 'turtle_traj.launch.py').is_file()


def test_the_installed_package_carries_the_pip_packages_data(install):
    """One list of package data (pyproject.toml's) for both builds: every file it names in
    src/ is in the installed tree too (the programs read rosutils/fastdds.xml at start)."""
    from setuptools.config.pyprojecttoml import load_file  # as setup.py reads it

    patterns = load_file(ROOT / 'pyproject.toml')['tool']['setuptools']['package-data'][
        'turtle_traj']
    source = ROOT / 'src' / 'turtle_traj'
    wanted = {path.relative_to(source) for pattern in patterns for path in source.glob(pattern)
              if path.is_file() and '__pycache__' not in path.parts}
    assert Path('rosutils/fastdds.xml') in wanted
    [installed] = install.glob('turtle_traj/lib/python3*/site-packages/turtle_traj')
    assert {path for path in wanted if not (installed / path).is_file()} == set()


def test_one_version_number_for_pip_and_colcon():
    pyproject = re.search(r'^version = "(.+)"', (ROOT / 'pyproject.toml').read_text(), re.M)
    package = re.search(r'<version>(.+)</version>',
                        (ROOT / 'ros/turtle_traj/package.xml').read_text())
    assert pyproject.group(1) == package.group(1)


def test_the_launch_file_parses_and_names_installed_executables(install):
    launch = install / 'turtle_traj' / 'share' / 'turtle_traj' / 'launch' / 'turtle_traj.launch.py'
    tree = ast.parse(launch.read_text())
    started = set()
    for call in ast.walk(tree):
        if isinstance(call, ast.Call) and getattr(call.func, 'id', '') == 'Node':
            keywords = {k.arg: k.value.value for k in call.keywords
                        if isinstance(k.value, ast.Constant)}
            started.add((keywords['package'], keywords['executable']))
    ours = {executable for package, executable in started if package == 'turtle_traj'}
    assert ours == {'sim', 'trajectory_node'} and ours <= EXECUTABLES
    assert ('turtlesim', 'turtlesim_node') in started  # use_real_turtlesim:=true
    arguments = {node.args[0].value for node in ast.walk(tree) if isinstance(node, ast.Call)
                 and getattr(node.func, 'id', '') == 'DeclareLaunchArgument'}
    assert arguments == {'time_scale', 'gui', 'web', 'web_host', 'web_port', 'turtle_name',
                         'namespace', 'use_real_turtlesim'}


def test_the_launch_files_simulator_arguments_parse():
    """What web:=true/false and gui:=true/false become (--web or --no-web ...) is what the
    simulator program takes."""
    from turtle_traj.apps.sim import build_parser
    from turtle_traj.sim.options import options_from

    for gui, web in [('false', 'false'), ('true', 'true'), ('False', 'TRUE')]:
        flags = [f'--{name}' if value.lower() == 'true' else f'--no-{name}'
                 for name, value in (('gui', gui), ('web', web))]
        options = options_from(build_parser().parse_args(
            [*flags, '--web-host', '127.0.0.1', '--web-port', '8080']))
        assert (options.gui, options.web) == (gui.lower() == 'true', web.lower() == 'true')
        assert options.problem() is None


def test_the_installed_executables_draw_a_square(install, tmp_path):
    """`ros2 run turtle_traj sim` and `ros2 run turtle_traj trajectory_node`, sourced, in the
    environment of a user who keeps ROS to this machine: LOCALHOST and no profile file of their
    own, so the installed programs read the installed fastdds.xml."""
    user = {name: value for name, value in os.environ.items() if name not in PROFILE_VARIABLES}
    user[RANGE_VARIABLE] = 'LOCALHOST'

    def start(executable: str, *args: str) -> subprocess.Popen:
        command = (f'. "{install}/setup.sh" && exec '
                   f'"{install}/turtle_traj/lib/turtle_traj/{executable}" ' + ' '.join(args))
        return subprocess.Popen(['sh', '-c', command], cwd=tmp_path, env=user,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)

    # At real time, as `ros2 run` users run them (scaled time makes a starved node on a busy
    # machine miss more poses: it aborted twice under two busy loops at 2x).
    sim = start('sim')
    node = start('trajectory_node')
    try:
        with TrajClient(connect_timeout_s=30.0) as client:
            from turtle_traj_interfaces.srv import DrawShape
            # Ready once a reset succeeds (the simulator's pose is in and it hears the node):
            # a reset is sent again while unanswered, a trajectory is not. A refusal comes at
            # once, sooner than the node may match a new client's reply reader, whose answer
            # is then dropped (see client/answers.py): the likely cause of one loaded full run's
            # "draw_square did not answer within 60 s", when refusals were asked for here.
            deadline = time.monotonic() + 30.0
            while not (reset := client.call('reset', timeout_s=30.0)).success:
                assert time.monotonic() < deadline, reset.message
                time.sleep(0.2)
            response = client.call('draw_square', DrawShape.Request(size=0.5), timeout_s=60.0)
        assert response.success, response.message
        assert response.path_length == pytest.approx(2.0)
    finally:
        for process in (node, sim):
            process.terminate()
        for process in (node, sim):
            output = process.communicate(timeout=15)[0]
            assert process.returncode == 0, output[-2000:]
    # and what ran is the installed tree's code, not the venv's editable install
    where = subprocess.run(['sh', '-c', f'. "{install}/setup.sh" && "{sys.executable}" -c '
                            '"import turtle_traj.apps.sim as m; print(m.__file__)"'],
                           capture_output=True, text=True, check=True).stdout
    assert where.startswith(str(install / 'turtle_traj')), where

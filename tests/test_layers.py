"""The architecture holds: import-linter's contracts (pyproject.toml), and what programs load.

The contracts are static (every import, function-level ones too); the tests below check what a
fresh interpreter really loads, which the contracts cannot see.
"""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / 'src' / 'turtle_traj'
ROS = {'rclpy', 'rcl_interfaces', 'turtlesim', 'geometry_msgs', 'nav_msgs', 'std_srvs',
       'turtle_traj_interfaces'}


def _modules(package: str) -> list[str]:
    folder = PACKAGE / package.replace('.', '/')
    return sorted('turtle_traj.' + '.'.join(path.relative_to(PACKAGE).with_suffix('').parts)
                  for path in folder.rglob('*.py') if path.name not in ('__init__.py',
                                                                        '__main__.py'))


def test_the_contracts_hold():
    linter = Path(sys.executable).with_name('lint-imports')
    if not linter.exists():
        linter = shutil.which('lint-imports')
    assert linter, 'import-linter is a dev dependency: make setup'
    checked = subprocess.run([str(linter), '--no-cache', '--no-logo'], cwd=ROOT,
                             capture_output=True, text=True)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    assert 'BROKEN' not in checked.stdout


def _loaded_by(imports: str, matching: str) -> str:
    """The modules a fresh interpreter has loaded after `imports`, among those `matching` (a
    Python condition on the module name m), comma-separated."""
    code = (f'import sys\n{imports}\n'
            f'print(",".join(sorted(m for m in sys.modules if {matching})))')
    return subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                          check=True).stdout.strip()


@pytest.mark.parametrize('package', ['core', 'web'])
def test_the_pure_packages_load_no_ros(package):
    imports = '\n'.join(f'import {module}' for module in _modules(package))
    assert _loaded_by(imports, f'm.split(".")[0] in {ROS!r}') == ''


def test_the_simulator_loads_nothing_of_the_trajectory_side():
    imports = '\n'.join(f'import {module}' for module in _modules('sim'))
    assert _loaded_by(imports, 'm.startswith(("turtle_traj.core.registry", '
                               '"turtle_traj.core.planning", "turtle_traj.node", '
                               '"turtle_traj.client", "turtle_traj.api"))') == ''


def test_the_node_program_loads_no_simulator_without_with_sim():
    # (its command-line options it parses, from sim.options)
    assert _loaded_by('import turtle_traj.apps.node', 'm.startswith("turtle_traj.sim.") and '
                                                      'm != "turtle_traj.sim.options"') == ''


def test_the_command_line_parses_without_loading_ros_numpy_or_the_planner():
    # `turtle-traj --help` and a mistyped command answer at once: the parser is built from
    # the registry and the parameter table, which are plain data.
    assert _loaded_by('import turtle_traj.cli.main as cli\ncli.build_parser()',
                      'm.split(".")[0] in {"rclpy", "numpy", "PIL", "svgelements", '
                      '"HersheyFonts"} or m.startswith(("turtle_traj.core.planning.sketches", '
                      '"turtle_traj.core.planning.planner", "turtle_traj.client"))') == ''


def test_the_planner_loads_neither_shapely_nor_casadi_until_a_plan_asks():
    # a node, a client estimating a call and the command line import the planner; shapely
    # (some 80 ms here) loads with the first plan that checks a distance, CasADi with the first
    # minimum-time corner
    assert _loaded_by('import turtle_traj.core.planning.planner',
                      'm.split(".")[0] in {"shapely", "casadi"}') == ''

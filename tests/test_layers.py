"""The package's layers import downwards only, and the pure core does not load ROS."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / 'src' / 'turtle_traj'

# Lowest first. A module imports only modules of lower layers (none of its own layer), so each
# line below is a set of modules independent of each other.
LAYERS = [
    # turtlesim's contract, what requests may ask for, and plane geometry
    ['turtlesim_contract', 'limits', 'teleop_keys', 'geometry.angles', 'geometry.curves'],
    ['geometry.path', 'parameter_table'],
    ['geometry.shapes', 'geometry.drawing'],
    ['geometry.svg', 'geometry.text'],
    # the simulator's pure core (the controller never imports it: see below)
    ['sim.state', 'sim.raster', 'sim.delay', 'sim.options', 'sim.gui'],
    ['sim.physics', 'sim.canvas'],
    # control: a plan in, commands out
    ['control.commands', 'control.config'],
    ['control.latency', 'control.plan'],
    ['control.follower'],
    ['control.supervisor'],
    ['control.loop'],
    # planning: the parameter table, then requests to sketches, then to checked plans
    ['settings'],
    ['sketches.base'],
    ['sketches.motions', 'sketches.curves', 'sketches.drawings'],
    ['planning'],
    # the registry of trajectory kinds, and the live view's messages built from it
    ['trajectories'],
    ['web.protocol'],
    # the ROS shell: QoS, interface names, the program runner, nodes, executors
    ['wire', 'services', 'runtime', 'remote_parameters', 'liveness', 'web.server',
     'node.async_service', 'node.outcomes', 'node.pen_client', 'node.waiting',
     'node.pose_silence', 'bags.types'],
    ['node.parameters', 'node.draw_action', 'sim.rotation_goals', 'bags.writer'],
    ['sim.endpoints', 'bags.reader', 'bags.recorder'],
    ['sim.node', 'bags.plots', 'bags.player'],
    ['node.run_recording', 'bags.programs'],
    ['node.trajectory_node', 'lockstep', 'web.bridge'],
    # nodes put together, and the script-side client
    ['system', 'client', 'web.view'],
    ['sim.main'],
    ['node.with_sim'],
    ['node.main'],
    # what people run
    ['console'],
    ['menu'],
    ['teleop'],
    ['cli', 'demo'],
    ['__main__', 'sim.__main__'],
]
PURE = [module for layer in LAYERS[:LAYERS.index(['web.protocol']) + 1] for module in layer]
CONTROLLER = [module for layer in LAYERS[LAYERS.index(['control.commands', 'control.config']):
                                         LAYERS.index(['trajectories']) + 1]
              for module in layer] + ['node.parameters', 'node.trajectory_node', 'node.outcomes',
                                      'node.pen_client', 'node.waiting', 'node.draw_action',
                                      'node.pose_silence']
LAYER_OF = {module: index for index, modules in enumerate(LAYERS) for module in modules}


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE).with_suffix('').parts
    return '.'.join(parts[:-1] if parts[-1] == '__init__' else parts)


def _imports(path: Path) -> set[str]:
    """Our modules that `path` imports, anywhere in it (function-level imports too)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and \
                node.module.startswith('turtle_traj'):
            base = node.module.removeprefix('turtle_traj').lstrip('.')
            for alias in node.names:
                candidate = f'{base}.{alias.name}' if base else alias.name
                found.add(candidate if candidate in LAYER_OF else base)
        elif isinstance(node, ast.Import):
            found |= {alias.name.removeprefix('turtle_traj.') for alias in node.names
                      if alias.name.startswith('turtle_traj.')}
    return found - {''}


MODULES = {_module_name(path): path for path in PACKAGE.rglob('*.py')
           if _module_name(path) and not path.name == '__init__.py'}


def test_every_module_has_a_layer():
    assert sorted(set(MODULES) - set(LAYER_OF)) == []


@pytest.mark.parametrize('module', sorted(MODULES))
def test_imports_point_downwards(module):
    not_below = {imported for imported in _imports(MODULES[module])
                 if LAYER_OF.get(imported, -1) >= LAYER_OF[module]}
    assert not not_below, (f'{module} (layer {LAYER_OF[module]}) imports its own layer or '
                           f'higher ones: {not_below}')


@pytest.mark.parametrize('module', CONTROLLER)
def test_the_controller_imports_nothing_of_the_simulator(module):
    assert not {imported for imported in _imports(MODULES[module])
                if imported.startswith('sim.')}


def test_no_import_cycles():
    graph = {module: _imports(path) & set(MODULES) for module, path in MODULES.items()}
    state: dict[str, str] = {}

    def visit(module: str, trail: list[str]) -> None:
        if state.get(module) == 'open':
            raise AssertionError(' -> '.join(trail[trail.index(module):] + [module]))
        if state.get(module) == 'done':
            return
        state[module] = 'open'
        for imported in sorted(graph[module]):
            visit(imported, trail + [module])
        state[module] = 'done'

    for module in sorted(graph):
        visit(module, [])


def _loaded_by(imports: str, matching: str) -> str:
    """The modules a fresh interpreter has loaded after `imports`, among those `matching` (a
    Python condition on the module name m), comma-separated."""
    code = (f'import sys\n{imports}\n'
            f'print(",".join(sorted(m for m in sys.modules if {matching})))')
    return subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                          check=True).stdout.strip()


def test_the_pure_core_loads_no_ros():
    imports = '\n'.join(f'import turtle_traj.{module}' for module in PURE)
    assert _loaded_by(imports, 'm.split(".")[0] in {"rclpy", "rcl_interfaces", "turtlesim", '
                               '"geometry_msgs"}') == ''


def test_the_node_program_loads_no_simulator_without_with_sim():
    # (its command-line options it parses, from sim.options)
    assert _loaded_by('import turtle_traj.node.main', 'm.startswith("turtle_traj.sim.") and '
                                                      'm != "turtle_traj.sim.options"') == ''


def test_the_command_line_parses_without_loading_ros_numpy_or_the_planner():
    # `turtle-traj --help` and a mistyped command answer at once: the parser is built from
    # the registry and the parameter table, which are plain data.
    assert _loaded_by('import turtle_traj.cli as cli\ncli.build_parser()',
                      'm.split(".")[0] in {"rclpy", "numpy", "PIL", "svgelements", '
                      '"HersheyFonts"} or m.startswith("turtle_traj.sketches") '
                      'or m in {"turtle_traj.planning", "turtle_traj.client"}') == ''

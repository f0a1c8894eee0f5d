"""The package's layers import downwards only, and the pure core does not load ROS."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / 'src' / 'turtle_traj'

# Lowest first. A module may import modules of its own layer or of a lower one.
LAYERS = [
    # 0: the pure core: geometry, control and its run supervisor, planning, the registry of
    # trajectories, the settings table, the simulator's physics and its options
    ['geometry.angles', 'geometry.path', 'geometry.shapes', 'geometry.curves',
     'geometry.drawing', 'geometry.svg', 'geometry.text', 'control.commands',
     'control.latency', 'control.follower', 'control.supervisor', 'control.loop', 'planning',
     'trajectories',
     'settings', 'sim.physics', 'sim.delay', 'sim.canvas', 'sim.gui', 'sim.options'],
    # 1: what simulator and controller agree on over the wire
    ['wire', 'services'],
    # 2: the ROS shell: nodes, their parameters, executors and the program runner
    ['node.async_service', 'sim.node', 'node.parameters', 'node.trajectory_node', 'lockstep',
     'runtime'],
    # 3: nodes put together, and the script-side client
    ['system', 'sim.main', 'node.main', 'client'],
    # 4: what people run
    ['console', 'menu', 'cli', 'demo', '__main__', 'sim.__main__'],
]
LAYER_OF = {module: index for index, modules in enumerate(LAYERS) for module in modules}
PURE = LAYERS[0]


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
    upwards = {imported for imported in _imports(MODULES[module])
               if LAYER_OF.get(imported, -1) > LAYER_OF[module]}
    assert not upwards, f'{module} (layer {LAYER_OF[module]}) imports higher layers: {upwards}'


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


def test_the_pure_core_loads_no_ros():
    code = ('import sys\n'
            + ''.join(f'import turtle_traj.{module}\n' for module in PURE)
            + 'loaded = sorted(m for m in sys.modules if m.split(".")[0] in '
              '{"rclpy", "rcl_interfaces", "turtlesim", "geometry_msgs"})\n'
              'print(",".join(loaded))')
    loaded = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                            check=True).stdout.strip()
    assert loaded == ''


def test_the_controller_does_not_load_the_simulator():
    # (Pillow it may load: it reads pen colour names.)
    code = ('import sys\nimport turtle_traj.node.trajectory_node\n'
            'print(",".join(sorted(m for m in sys.modules '
            'if m.startswith("turtle_traj.sim.") and m != "turtle_traj.sim.physics")))')
    loaded = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                            check=True).stdout.strip()
    assert loaded == ''

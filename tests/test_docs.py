"""The documentation site: built as `make docs` builds it, it shows every parameter the running
node lists, every `turtle-traj` subcommand, every service and the action; and no page names a
file or a module that does not exist."""

import importlib
import importlib.util
import re
from pathlib import Path

import pytest

from turtle_traj.api.controllers import ENTRY_POINT_GROUP

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / 'README.md', *sorted((ROOT / 'docs').rglob('*.md'))]
PAGES = [page for page in PAGES if '_build' not in page.parts]


@pytest.fixture(scope='module')
def site(tmp_path_factory) -> str:
    """Every built page's text, together (warnings are errors, as in `make docs`)."""
    from sphinx.cmd.build import build_main
    out = tmp_path_factory.mktemp('site')
    assert build_main(['-q', '-E', '-W', '-b', 'html', str(ROOT / 'docs'), str(out)]) == 0
    return '\n'.join(page.read_text() for page in out.rglob('*.html'))


def test_the_site_shows_every_parameter_the_running_node_lists(site, rclpy_context):
    from turtle_traj.node.trajectory_node import TrajectoryNode
    node = TrajectoryNode(context=rclpy_context)
    try:
        listed = node.list_parameters([], 0).names
    finally:
        node.destroy_node()
    assert 'controller' in listed and 'linear_speed' in listed
    missing = [name for name in listed if name != 'use_sim_time'
               and f'<code class="docutils literal notranslate"><span class="pre">{name}</span>'
               not in site]
    assert missing == []


def test_the_architecture_page_lists_every_module_with_what_it_does(site):
    """The list is generated from the modules' docstrings: every module has one, and is on
    the page with its first sentence."""
    import ast
    package = ROOT / 'src' / 'turtle_traj'
    modules = [path for path in package.rglob('*.py')  # labs/ holds students' programs
               if not {'__pycache__', 'labs'} & set(path.relative_to(package).parts)
               and path.name not in ('__init__.py', '__main__.py')]
    assert len(modules) > 150
    undocumented = [str(path) for path in modules
                    if not ast.get_docstring(ast.parse(path.read_text()))]
    assert undocumented == []
    unlisted = [path.relative_to(package).as_posix() for path in modules
                if f'<span class="pre">{path.relative_to(package).as_posix()}</span>'
                not in site]
    assert unlisted == []


def test_the_site_shows_every_subcommand_every_service_and_the_action(site):
    from turtle_traj.cli.main import build_parser
    from turtle_traj.core.registry import TRAJECTORIES
    paths = _command_paths(build_parser())
    assert {('draw', 'square'), ('score',), ('up',), ('params',)} <= set(paths)
    # sphinx-argparse gives each (sub)command a section of its own
    assert [p for p in paths if f'<section id="turtle-traj-{"-".join(p)}">' not in site] == []
    services = [f'~/{kind.service}' for kind in TRAJECTORIES] + ['~/stop', '~/reset']
    assert [name for name in services if name not in site] == []
    assert '~/draw' in site and 'turtle_traj_interfaces/action/Draw' in site


def _command_paths(parser, words=()) -> list[tuple[str, ...]]:
    """Every subcommand, as its words ('draw', 'square')."""
    found = []
    for action in parser._actions:
        for name, sub in (getattr(action, 'choices', None) or {}).items():
            if hasattr(sub, '_actions'):
                found += [(*words, name), *_command_paths(sub, (*words, name))]
    return found


PATH = re.compile(r'(?<![/\w])((?:tests|bench|src/turtle_traj|interfaces|ros|docs)/[\w./-]+\.\w+)')
MODULE = re.compile(r'\b(turtle_traj(?:\.\w+)+)')
BUILT = 'docs/_build/'  # the site, as `make docs` builds it


def test_no_page_names_a_file_or_a_module_that_does_not_exist():
    named, missing = 0, []
    for page in PAGES:
        text = page.read_text()
        for path in PATH.findall(text):
            if path.startswith(BUILT):  # made by `make docs`: on a fresh clone, not yet
                continue
            named += 1
            if not (ROOT / path.rstrip('.')).exists():
                missing.append(f'{page.name}: {path}')
        for dotted in MODULE.findall(text):
            if dotted.endswith('.py') or dotted == ENTRY_POINT_GROUP:  # a file, a group's name
                continue
            named += 1
            if not _exists(dotted):
                missing.append(f'{page.name}: {dotted}')
    assert named > 50 and missing == []


def _exists(dotted: str) -> bool:
    """A module, or an attribute of one (a class, a function)."""
    parts = dotted.split('.')
    for cut in range(len(parts), 0, -1):
        try:
            found = importlib.util.find_spec('.'.join(parts[:cut])) is not None
        except ModuleNotFoundError:  # a name below a module that is no package
            found = False
        if found:
            if cut == len(parts):
                return True
            module = importlib.import_module('.'.join(parts[:cut]))
            target = module
            for name in parts[cut:]:
                if not hasattr(target, name):
                    return False
                target = getattr(target, name)
            return True
    return False


def test_the_controller_tutorial_names_everything_the_public_module_exports():
    """The tutorial lists what `turtle_traj.api.controller` gives a controller's author: every
    name it exports, and nothing it does not."""
    from turtle_traj.api import controller

    page = (ROOT / 'docs' / 'tutorials' / 'write-a-controller.md').read_text()
    listing = re.search(r'comes from one module, `turtle_traj.api.controller`:(.*?)\n\n', page,
                        re.S)
    assert listing is not None
    assert set(re.findall(r'`(\w+)`', listing[1])) == set(controller.__all__)

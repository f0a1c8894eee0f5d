"""Sphinx directives that write reference tables from the code, so they cannot go stale.

- ``parameters``: every node parameter from the parameter table, then the shipped controllers'
  tuning (type, default, unit, range, read-only, description).
- ``trajectories``: every trajectory service from the registry, with its request fields.
- ``interface``: one .srv or .action file of `interfaces/`, as it is.
- ``modules``: every module of `src/turtle_traj/`, package by package in the order of the
  import layers, with the first sentence of its docstring.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import Directive, directives

ROOT = Path(__file__).resolve().parents[2]


def _cell(text: str) -> nodes.entry:
    """A table cell from text in which ``code`` is set as code."""
    paragraph = nodes.paragraph()
    for index, part in enumerate(text.split('``')):
        if part:
            paragraph += nodes.literal(part, part) if index % 2 else nodes.Text(part)
    return nodes.entry('', paragraph)


def _table(_directive: Directive, header: list[str], rows: list[list[str]]) -> list[nodes.Node]:
    table = nodes.table()
    group = nodes.tgroup(cols=len(header))
    table += group
    for _ in header:
        group += nodes.colspec(colwidth=1)
    head, body = nodes.thead(), nodes.tbody()
    for target, lines in ((head, [header]), (body, rows)):
        for line in lines:
            row = nodes.row()
            for text in line:
                row += _cell(text)
            target += row
    group += head
    group += body
    return [table]


def _literal(text: str) -> str:
    return f'``{text}``' if text not in ('', None) else ''


class Parameters(Directive):
    def run(self):
        from turtle_traj.api.controllers import choose
        from turtle_traj.core.control.controllers.catalogue import SHIPPED
        from turtle_traj.core.parameters.table import PARAMETERS
        named = [(spec.name, spec) for spec in PARAMETERS]
        for controller in map(choose, SHIPPED):  # the shipped controllers' tuning
            named += [(f'{controller.prefix}.{spec.name}', spec) for spec in controller.tunables]
        rows = []
        for name, spec in named:
            kind = type(spec.default).__name__
            bounds = '' if spec.low is None else f'{spec.low:g} to {spec.high:g}'
            if spec.choices:
                bounds = ', '.join(_literal(choice) for choice in spec.choices)
            rows.append([_literal(name), kind, _literal(repr(spec.default)), spec.unit,
                         bounds, 'yes' if spec.read_only else '',
                         spec.description])
        return _table(self, ['name', 'type', 'default', 'unit', 'range', 'read-only',
                             'description'], rows)


class Trajectories(Directive):
    def run(self):
        from turtle_traj.core.registry import TRAJECTORIES
        rows = []
        for kind in TRAJECTORIES:
            fields = '; '.join(f'{_literal(f.name)}: {f.help}' + (f' [{f.unit}]' if f.unit else '')
                               for f in kind.fields)
            rows.append([_literal(f'~/{kind.service}'), _literal(kind.service_type),
                         _literal('turtle-traj ' + ' '.join(kind.command)), kind.summary,
                         fields])
        return _table(self, ['service', 'type', 'command line', 'what it does',
                             'request fields'], rows)


class Interface(Directive):
    required_arguments = 1  # a path under interfaces/turtle_traj_interfaces/

    def run(self):
        path = ROOT / 'interfaces' / 'turtle_traj_interfaces' / self.arguments[0]
        text = path.read_text()
        block = nodes.literal_block(text, text)
        block['language'] = 'text'
        return [nodes.rubric(text=f'turtle_traj_interfaces/{self.arguments[0]}'), block]


# The packages in the order of the import layers (pyproject.toml), the core's after them.
_LAYERS = ('cli', 'testing', 'apps', 'fleet', 'client', 'node', 'sim', 'base', 'bags', 'api',
           'rosutils', 'web', 'core', 'core/registry.py', 'core/fields.py', 'core/fleet',
           'core/planning', 'core/parameters', 'core/control', 'core/geometry')


def _summary(path: Path) -> str:
    """The first sentence of a module's docstring (its first paragraph where it has none)."""
    doc = ast.get_docstring(ast.parse(path.read_text(encoding='utf-8'))) or ''
    paragraph = ' '.join(doc.split('\n\n')[0].split())
    found = re.match(r'(.+?[.])(\s|$)', paragraph)
    return found[1] if found else paragraph


def _layer(relative: str) -> int:
    """The index of the most specific layer a module belongs to."""
    best = (-1, 0)
    for index, layer in enumerate(_LAYERS):
        if relative == layer or relative.startswith(layer + '/'):
            best = max(best, (len(layer), index))
    return best[1] if best[0] >= 0 else len(_LAYERS)


class Modules(Directive):
    def run(self):
        package = ROOT / 'src' / 'turtle_traj'
        modules = [path for path in package.rglob('*.py')  # labs/: students' programs
                   if not {'__pycache__', 'labs'} & set(path.relative_to(package).parts)
                   and path.name not in ('__init__.py', '__main__.py')]
        relative = {path: path.relative_to(package).as_posix() for path in modules}
        ordered = sorted(modules, key=lambda path: (_layer(relative[path]), relative[path]))
        rows = [[_literal(relative[path]), _summary(path)] for path in ordered]
        return _table(self, ['module', 'what it does'], rows)


def setup(app):
    directives.register_directive('parameters', Parameters)
    directives.register_directive('trajectories', Trajectories)
    directives.register_directive('interface', Interface)
    directives.register_directive('modules', Modules)
    return {'parallel_read_safe': True}

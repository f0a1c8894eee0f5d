"""Our interface contract: the .srv and .action files against the registry and the node.

Each request field a trajectory kind takes is in its service with the wire type and unit the
registry gives it, no service field is left unused, the Draw goal carries every service's
fields unchanged, and every response carries the outcome the node fills in. Read from the
interface sources and from the built types, so a stale build fails too.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
from ament_index_python.packages import get_package_share_directory, get_packages_with_prefixes

from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.supervisor import Outcome
from turtle_traj.core.fields import BOOL, FLOAT, INT, POINTS, STRING
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.table import PARAMETER
from turtle_traj.core.registry import TRAJECTORIES
from turtle_traj.rosutils.interfaces import interface

SOURCES = Path(__file__).resolve().parents[1] / 'interfaces' / 'turtle_traj_interfaces'
WIRE_TYPES = {FLOAT: {'float64'}, INT: {'uint8', 'uint32', 'int32', 'int64'}, BOOL: {'bool'},
              STRING: {'string'}, POINTS: {'geometry_msgs/Point[]'}}
# Units as a person enters them, and as the request carries them.
ON_THE_WIRE = {'deg': 'rad', 'cycles/m': '1/m'}
COUNTS = {'turns'}  # said in words ('number of turns'), not as a [unit]


def _sections(path: Path) -> list[dict[str, tuple[str, str]]]:
    """Each section of an interface file: field name -> (type, its comment, continuation
    lines included)."""
    sections: list[dict[str, tuple[str, str]]] = [{}]
    last = None
    for line in path.read_text().splitlines():
        if line.strip() == '---':
            sections.append({})
            last = None
            continue
        code, _, comment = line.partition('#')
        if code.strip():
            kind, name = code.split()[:2]
            sections[-1][name] = (kind, comment.strip())
            last = name
        elif last is not None and line.startswith(' '):  # a comment continued
            kind, text = sections[-1][last]
            sections[-1][last] = (kind, f'{text} {comment.strip()}')
        else:
            last = None
    return sections


def _source(ros_type: str) -> Path:
    package, folder, name = ros_type.split('/')
    return SOURCES / folder / f'{name}.{folder}'


SERVICE_TYPES = sorted({kind.service_type for kind in TRAJECTORIES})
DRAW_GOAL, _, _ = _sections(SOURCES / 'action' / 'Draw.action')


def test_ament_index_lists_both_packages():
    packages = get_packages_with_prefixes()
    assert packages['turtle_traj_interfaces'] == str(Path(sys.prefix).resolve())
    share = Path(get_package_share_directory('turtle_traj_interfaces'))
    assert (share / 'srv' / 'GoTo.srv').read_text() == (SOURCES / 'srv' / 'GoTo.srv').read_text()
    assert (Path(get_package_share_directory('turtlesim')) / 'action' /
            'RotateAbsolute.action').is_file()


@pytest.mark.parametrize('ros_type', SERVICE_TYPES)
def test_the_built_service_has_the_fields_of_its_source(ros_type):
    request, response = _sections(_source(ros_type))
    built = interface(ros_type)
    assert list(built.Request.get_fields_and_field_types()) == list(request)
    assert list(built.Response.get_fields_and_field_types()) == list(response)


@pytest.mark.parametrize('kind', TRAJECTORIES, ids=lambda kind: kind.name)
def test_each_field_is_in_the_request_with_its_wire_type_and_unit(kind):
    request, _ = _sections(_source(kind.service_type))
    for item in kind.fields:
        assert item.name in request, f'{kind.service_type} has no field {item.name}'
        wire_type, comment = request[item.name]
        assert wire_type in WIRE_TYPES[item.type], (item.name, wire_type)
        unit = ON_THE_WIRE.get(item.unit, item.unit)
        if unit in COUNTS:
            assert unit in comment, (kind.name, item.name, comment)
        elif item.type == FLOAT and unit:
            assert f'[{unit}]' in comment, (kind.name, item.name, unit, comment)
        if item.given:
            assert request[item.given][0] == 'bool', item.given


@pytest.mark.parametrize('ros_type', SERVICE_TYPES)
def test_every_request_field_is_used_by_a_kind(ros_type):
    request, _ = _sections(_source(ros_type))
    used = {name for kind in TRAJECTORIES if kind.service_type == ros_type
            for item in kind.fields for name in (item.name, item.given) if name}
    assert set(request) == used


@pytest.mark.parametrize('ros_type', SERVICE_TYPES)
def test_a_parameter_a_comment_names_backs_that_field(ros_type):
    """`0 = parameter X` in a comment: the registry sends 0 for that field by default and the
    node reads X instead (so the documentation cannot drift from the code)."""
    request, _ = _sections(_source(ros_type))
    for name, (_, comment) in {**request, **DRAW_GOAL}.items():
        for parameter in re.findall(r'parameter (\w+)', comment):
            if parameter == 'default' or parameter == 'svg_dir':
                continue  # 'the parameter default' (move/rotate); svg_dir: a folder, not 0
            assert parameter in PARAMETER, (name, parameter)
            # backed by the parameter, or (a colour, a width: "" and 0 mean unset) said so
            backed = {item.parameter or parameter * (f"the node's {parameter}" in item.help)
                      for kind in TRAJECTORIES for item in kind.fields if item.name == name}
            assert parameter in backed, (name, parameter, backed)


def test_the_draw_goal_carries_every_service_field_unchanged():
    carried = {'trajectory': ('string', DRAW_GOAL['trajectory'][1])}
    for ros_type in SERVICE_TYPES:
        request, _ = _sections(_source(ros_type))
        for name, (wire_type, comment) in request.items():
            assert DRAW_GOAL[name][0] == wire_type, (ros_type, name)
            units = re.findall(r'\[[^\]]+\]', comment)
            assert units == re.findall(r'\[[^\]]+\]', DRAW_GOAL[name][1]), (ros_type, name)
            carried[name] = DRAW_GOAL[name]
    assert set(DRAW_GOAL) == set(carried)  # nothing more
    goal = interface('turtle_traj_interfaces/action/Draw').Goal
    assert list(goal.get_fields_and_field_types()) == list(DRAW_GOAL)


@pytest.mark.parametrize('ros_type', [*SERVICE_TYPES, 'turtle_traj_interfaces/action/Draw'])
def test_the_node_fills_every_field_of_every_response(ros_type):
    """An outcome with a distinct value in each field: each lands in its response field, and
    no response field is left at its default."""
    from turtle_traj.node.outcomes import fill_response

    outcome = Outcome(True, 'done', Ending.NO_PROGRESS, Pose2D(1.0, 2.0, 3.0),
                      *(float(v) for v in range(4, 11)), driven_length=11.0)
    built = interface(ros_type)
    response = fill_response(built.Result() if hasattr(built, 'Result') else built.Response(),
                             outcome)
    ending = interface('turtle_traj_interfaces/msg/Ending')
    expected = {'success': True, 'message': 'done',
                'ending': ending(code=ending.NO_PROGRESS, label='no progress'),
                'final_x': 1.0, 'final_y': 2.0,
                'final_theta': 3.0, 'elapsed': 4.0, 'path_length': 5.0, 'max_deviation': 6.0,
                'final_error': 7.0, 'final_heading_error': 8.0, 'pen_up_length': 9.0,
                'pen_up_unordered': 10.0, 'driven_length': 11.0}
    filled = {name: getattr(response, name) for name in response.get_fields_and_field_types()}
    assert filled == {name: expected[name] for name in filled}
    assert set(filled) >= set(expected) - {'pen_up_length', 'pen_up_unordered'}


# turtlesim's interfaces as the real turtlesim defines them (shared turtlesim reference): field
# order and types decide the wire format, so a node built on our copy talks to the real one.
F32, U8 = 'float', 'uint8'
TURTLESIM = {
    'turtlesim/msg/Pose': [{'x': F32, 'y': F32, 'theta': F32, 'linear_velocity': F32,
                            'angular_velocity': F32}],
    'turtlesim/msg/Color': [{'r': U8, 'g': U8, 'b': U8}],
    'turtlesim/srv/Spawn': [{'x': F32, 'y': F32, 'theta': F32, 'name': 'string'},
                            {'name': 'string'}],
    'turtlesim/srv/Kill': [{'name': 'string'}, {}],
    'turtlesim/srv/SetPen': [{'r': U8, 'g': U8, 'b': U8, 'width': U8, 'off': U8}, {}],
    'turtlesim/srv/TeleportAbsolute': [{'x': F32, 'y': F32, 'theta': F32}, {}],
    'turtlesim/srv/TeleportRelative': [{'linear': F32, 'angular': F32}, {}],
    'turtlesim/action/RotateAbsolute': [{'theta': F32}, {'delta': F32}, {'remaining': F32}],
}


@pytest.mark.parametrize('ros_type', sorted(TURTLESIM))
def test_our_turtlesim_interfaces_are_the_real_ones(ros_type):
    built = interface(ros_type)
    kind = ros_type.split('/')[1]
    parts = [built] if kind == 'msg' else [
        getattr(built, part) for part in {'srv': ('Request', 'Response'),
                                          'action': ('Goal', 'Result', 'Feedback')}[kind]]
    assert [list(part.get_fields_and_field_types().items()) for part in parts] == \
        [list(fields.items()) for fields in TURTLESIM[ros_type]]


def test_every_ending_is_a_constant_of_the_message_and_back():
    """Each reason a run ends has its constant in turtle_traj_interfaces/msg/Ending under its
    name, with distinct codes, and the message has no constant the node never sends."""
    from turtle_traj.node.outcomes import ending_message

    built = interface('turtle_traj_interfaces/msg/Ending')
    constants = {name: value for name, value in vars(built).items()
                 if name.isupper() and isinstance(value, int)}
    assert set(constants) == {reason.name for reason in Ending}
    assert len(set(constants.values())) == len(constants)
    for reason in Ending:
        sent = ending_message(reason)
        assert (sent.code, sent.label) == (constants[reason.name], reason.value)

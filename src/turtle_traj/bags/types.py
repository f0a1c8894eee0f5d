"""Message definitions for rosbag2 bags: rosbags' Jazzy type store, plus the types it lacks
(turtlesim's, ours, an action's feedback and status messages) read from the ament index.

No rclpy: the installed interface files (`share/<package>/msg/*.msg`, `action/*.action`) are the
source, as `ros2 bag record` takes them from the type support.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from ament_index_python.packages import PackageNotFoundError, get_package_share_directory
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore


class UnknownType(LookupError):
    """A message type whose definition is installed nowhere; the message names it."""


def _share(package: str) -> Path:
    try:
        return Path(get_package_share_directory(package))
    except PackageNotFoundError:
        raise UnknownType(f'no package {package!r} is installed (ament index)') from None


def _definitions(typename: str) -> dict[str, str]:
    """Message text by type name for `typename` ('pkg/msg/Name' or an action's
    'pkg/action/Name_FeedbackMessage'), from the installed interface files."""
    package, kind, name = typename.split('/')
    if kind == 'msg':
        path = _share(package) / 'msg' / f'{name}.msg'
        if not path.is_file():
            raise UnknownType(f'{typename}: {path} is not installed')
        return {typename: path.read_text()}
    if kind == 'action':
        action, _, part = name.rpartition('_')
        path = _share(package) / 'action' / f'{action}.action'
        if not path.is_file():
            raise UnknownType(f'{typename}: {path} is not installed')
        goal, result, feedback = (path.read_text().split('\n---\n') + ['', ''])[:3]
        base = f'{package}/action/{action}'
        texts = {f'{base}_Goal': goal, f'{base}_Result': result, f'{base}_Feedback': feedback}
        if part == 'FeedbackMessage':
            texts[typename] = (f'unique_identifier_msgs/UUID goal_id\n'
                               f'{base}_Feedback feedback\n')
        if typename not in texts:
            raise UnknownType(f'{typename}: not a message of the action {base}')
        return texts
    raise UnknownType(f'{typename}: not a message type')


@cache
def typestore_for(typenames: tuple[str, ...]) -> Typestore:
    """Jazzy's standard types and every one of `typenames` (with what they use).

    :raises UnknownType: a type installed nowhere.
    """
    store = get_typestore(Stores.ROS2_JAZZY)
    for typename in typenames:
        if typename in store.fielddefs:
            continue
        for name, text in _definitions(typename).items():
            if name not in store.fielddefs:
                store.register(get_types_from_msg(text, name))
    return store


_SEPARATOR = '=' * 80


def message_definition(store: Typestore, typename: str) -> str:
    """The concatenated definition rosbag2 keeps for a topic (its `ros2msg` schema): the type's
    text, then `MSG: <type>` and the text of every type it uses."""
    if '/action/' not in typename:
        return store.generate_msgdef(typename, ros_version=2)[0]
    # rosbags writes definitions of `msg` types only: an action's feedback message is composed
    # here, in the same layout.
    texts = _definitions(typename)
    sections = [texts[typename].strip()]
    for line in texts[typename].splitlines():
        words = line.split('#', 1)[0].split()
        fieldtype = words[0].split('[')[0] if words else ''
        if '/' not in fieldtype:
            continue
        if '/action/' in fieldtype:
            sections.append(f'MSG: {fieldtype}\n{texts[fieldtype].strip()}')
        else:
            package, name = fieldtype.split('/')
            nested = store.generate_msgdef(f'{package}/msg/{name}', ros_version=2)[0]
            sections.append(f'MSG: {fieldtype}\n{nested.strip()}')
    return f'\n{_SEPARATOR}\n'.join(sections) + '\n'

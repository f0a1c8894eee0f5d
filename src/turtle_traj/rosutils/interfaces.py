"""ROS interfaces by name: the Python class of a message, service or action type."""

from __future__ import annotations

import importlib


def interface(type_name: str) -> type:
    """The Python class of a ROS interface named like 'turtle_traj_interfaces/srv/GoTo'."""
    package, kind, name = type_name.split('/')
    return getattr(importlib.import_module(f'{package}.{kind}'), name)


def message_type(type_name: str) -> type:
    """The Python class of a topic's type, an action's messages included
    ('turtle_traj_interfaces/action/Draw_FeedbackMessage': `Draw.Impl.FeedbackMessage`)."""
    package, kind, name = type_name.split('/')
    if kind != 'action' or '_' not in name:
        return interface(type_name)
    action, part = name.rsplit('_', 1)
    action_type = interface(f'{package}/action/{action}')
    return getattr(action_type, part, None) or getattr(action_type.Impl, part)

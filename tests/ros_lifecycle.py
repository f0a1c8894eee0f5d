"""A record of what each test left of rclpy, destroyed by us and named in a failure.

Every context is one DDS participant (Fast DDS makes it with the context's first node). Several
participants in one process deadlock inside Fast DDS when one is torn down while another
delivers to it (eProsima/Fast-DDS #1016, #6193), and a node nobody destroyed is torn down by
the garbage collector at whatever moment it runs. So a test process has one context, each test
makes and destroys its own nodes and executors, and a test that leaves one alive fails, naming
it, after its leftovers have been destroyed (never by the collector).
"""

from __future__ import annotations

import threading
from collections.abc import Callable

from rclpy.exceptions import InvalidHandle
from rclpy.executors import Executor
from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.node import Node

_lock = threading.Lock()
# Strong references, with what to call them: a leftover is destroyed by us, not collected.
_nodes: list[tuple[Node, str]] = []
_executors: list[tuple[object, str]] = []
_shut_down: set[int] = set()  # ids of EventsExecutors whose shutdown was called


def _wrap_init(cls: type, register: list) -> None:
    original = cls.__init__

    def __init__(self, *args, **kwargs) -> None:
        original(self, *args, **kwargs)
        with _lock:
            register.append((self, _describe(self)))
    cls.__init__ = __init__


def track() -> None:
    """Record every rclpy node and executor made from now on in this process."""
    _wrap_init(Node, _nodes)
    _wrap_init(Executor, _executors)
    events = rclpy_implementation.EventsExecutor  # C++, not an Executor: no _is_shutdown
    _wrap_init(events, _executors)
    original_shutdown = events.shutdown

    def shutdown(self, *args, **kwargs):
        _shut_down.add(id(self))
        return original_shutdown(self, *args, **kwargs)
    events.shutdown = shutdown


def _destroyed(node: Node) -> bool:
    try:
        with node.handle:
            return False
    except InvalidHandle:
        return True


def _is_shut_down(executor: object) -> bool:
    if isinstance(executor, Executor):
        return executor._is_shutdown
    return id(executor) in _shut_down


def _describe(thing: object) -> str:
    if isinstance(thing, Node):
        return f'node {thing.get_fully_qualified_name()} ({type(thing).__name__})'
    return f'executor {type(thing).__name__}'


def take_leftovers() -> list[str]:
    """Shut down and destroy what was made since the last call and is still alive; name it."""
    with _lock:
        nodes, executors = list(_nodes), list(_executors)
        _nodes.clear()
        _executors.clear()
    left: list[str] = []

    def tidy(name: str, destroy: Callable[[], object]) -> None:
        """Name what was left and destroy it; a failure to destroy one stops no other."""
        left.append(name)
        try:
            destroy()
        except Exception as error:  # noqa: BLE001 - reported with the leftovers
            left.append(f'(destroying it failed: {error!r})')

    for executor, name in executors:
        if not _is_shut_down(executor):
            tidy(name, executor.shutdown)
    for node, name in nodes:
        if not _destroyed(node):
            tidy(name, node.destroy_node)
        # An action server or client is a waitable that holds its node's handle: the node lives
        # on (and with it the participant) until it is destroyed too.
        for waitable in list(node.waitables):
            tidy(f'{type(waitable).__name__} of {name}', waitable.destroy)
    _shut_down.clear()
    return left

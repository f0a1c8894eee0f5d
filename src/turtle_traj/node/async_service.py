"""Services answered by a coroutine, on rclpy's own executors and on its EventsExecutor alike."""

from __future__ import annotations

import inspect
from collections.abc import Callable, Coroutine
from typing import Any

from rclpy.node import Node
from rclpy.service import Service
from rclpy.task import Future


def create_async_service(node: Node, srv_type: type, name: str,
                         handler: Callable[[Any, Any], Coroutine[Any, Any, Any]],
                         **kwargs: Any) -> Service:
    """Create a service whose `handler` is a coroutine function; it answers when that returns.

    rclpy's Python executors await a coroutine handler before sending its response. Jazzy's
    EventsExecutor (rclpy 7.1.6) sends whatever the handler returned at once, here a coroutine
    object, which `send_response` refuses. The response is therefore sent through this
    service's own `send_response`, which runs a coroutine as a task of the node's executor
    first and answers when the task is done. tests/test_lockstep_contract.py pins both paths,
    and the failure itself: ros2/rclpy#1473, fixed upstream (#1478) and backported to Jazzy
    (#1613) after 7.1.6, the only Jazzy rclpy on PyPI. Remove this when the pin moves past it.
    """
    service = node.create_service(srv_type, name, handler, **kwargs)
    send_now = service.send_response

    def send_when_done(response: Any, header: Any) -> None:
        if not inspect.iscoroutine(response):
            send_now(response, header)
            return

        def answer(task: Future) -> None:
            send_now(task.result(), header)
        node.executor.create_task(response).add_done_callback(answer)

    service.send_response = send_when_done
    return service

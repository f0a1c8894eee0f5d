"""One lock over a node's state, for nodes whose callbacks may run on several threads."""

from __future__ import annotations

from collections.abc import Callable
from functools import wraps
from typing import Any, TypeVar

_Method = TypeVar('_Method', bound=Callable[..., Any])


def serialized(method: _Method) -> _Method:
    """Run `method` holding its object's `_state_lock` (a threading.RLock)."""
    @wraps(method)
    def locked(self: Any, *args: Any, **kwargs: Any) -> Any:
        with self._state_lock:
            return method(self, *args, **kwargs)
    return locked  # type: ignore[return-value]

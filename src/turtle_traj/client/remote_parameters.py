"""Another node's parameters read and set as text, converted to the types it declared."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from rcl_interfaces.msg import Parameter as ParameterMsg
from rcl_interfaces.msg import ParameterType, ParameterValue
from rclpy.parameter import Parameter, get_parameter_value, parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient
from rclpy.task import Future


class UnknownParameter(LookupError):
    """A name the node has no parameter of; the message names those it has."""


def typed_value(declared: int, text: str) -> ParameterValue:
    """A parameter value of the declared type from text (other types: read as YAML, as
    `ros2 param set` does).

    :raises ValueError: text that is not of the declared type.
    """
    if declared == ParameterType.PARAMETER_DOUBLE:
        try:
            return ParameterValue(type=declared, double_value=float(text))
        except ValueError:
            raise ValueError(f'expects a number, got {text!r}') from None
    if declared == ParameterType.PARAMETER_INTEGER:
        try:
            return ParameterValue(type=declared, integer_value=int(text))
        except ValueError:
            raise ValueError(f'expects a whole number, got {text!r}') from None
    if declared == ParameterType.PARAMETER_STRING:
        return ParameterValue(type=declared, string_value=text)
    return get_parameter_value(text)


def parameter_from_text(name: str, declared: int, text: str) -> Parameter:
    """The parameter `name` set from text, as the declared type (see `typed_value`).

    :raises ValueError: text that is not of the declared type.
    """
    return Parameter.from_parameter_msg(ParameterMsg(name=name,
                                                     value=typed_value(declared, text)))


class RemoteParameters:
    """The parameters of `client`'s node; `ask(send, what)` sends a request (`send()` returns
    its future), spins until it is answered and returns the answer (or raises). Every request
    here may be sent again: reading a parameter, or setting it to the same value, twice is the
    same as once."""

    def __init__(self, client: AsyncParameterClient, node_name: str,
                 ask: Callable[[Callable[[], Future], str], Any]) -> None:
        self._client, self._node_name, self._ask = client, node_name, ask

    def get(self, names: list[str] | None = None) -> dict[str, object]:
        """Values by name (all, sorted by name, by default).

        :raises UnknownParameter: naming a parameter the node does not have.
        """
        known = sorted(self._ask(self._client.list_parameters, 'list_parameters')
                       .result.names)
        unknown = [name for name in names or [] if name not in known]
        if unknown:
            raise UnknownParameter(f'{self._node_name} has no parameter {", ".join(unknown)}; '
                                   f'it has: {", ".join(known)}')
        names = names or known
        values = self._ask(lambda: self._client.get_parameters(names), 'get_parameters').values
        return {name: parameter_value_to_python(value)
                for name, value in zip(names, values, strict=True)}

    def set(self, name: str, text: str) -> str | None:
        """Set a parameter from text, converted to the type the node declared it with (`2` to
        a double is 2.0, `1e-9` a number); the refusal, or None when it is set.

        :raises UnknownParameter: naming a parameter the node does not have.
        """
        self.get([name])  # exists, or the error names it
        declared = self._ask(lambda: self._client.describe_parameters([name]),
                             'describe_parameters').descriptors[0].type
        try:
            parameter = parameter_from_text(name, declared, text)
        except ValueError as error:
            return f'{name}: {error}'
        result = self._ask(lambda: self._client.set_parameters([parameter]), 'set_parameters')
        return None if result.results[0].successful else result.results[0].reason

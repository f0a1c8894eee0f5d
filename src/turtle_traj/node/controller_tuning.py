"""The tuning of the node's controllers as ROS parameters, as Nav2 serves its plugins':
`<controller>.<name>` (`pure_pursuit.lookahead_time`), one for each `Tunable` a controller's
class declares, with its default, range and description.

They are declared for the shipped controllers and the node's `controller` at start-up, and for
any other as a goal first names it (FollowPath's `controller_id`). rclpy checks each value
against its range; a run's controller reads the values in effect as each stroke starts.
"""

from __future__ import annotations

from dataclasses import replace
from functools import partial

from rclpy.node import Node

from turtle_traj.api.controllers import choose
from turtle_traj.core.control.controllers.catalogue import SHIPPED, ControllerChoice
from turtle_traj.node.answer_timer import ProcessAnswerTimer
from turtle_traj.node.parameters import descriptor


class ControllerTuning:
    """The tuning parameters of `node`'s controllers; `choose` hands out controllers that read
    them."""

    def __init__(self, node: Node, configured: str) -> None:
        self._node = node
        for name in dict.fromkeys([*SHIPPED, configured]):
            self.choose(name)

    def choose(self, name: str) -> ControllerChoice:
        """The controller `name` stands for, its answers timed, reading its tuning from the
        node's parameters (declared now if they are not yet).

        :raises UnknownController: with the reason.
        """
        chosen = choose(name)
        for spec in chosen.tunables:
            parameter = f'{chosen.prefix}.{spec.name}'
            if not self._node.has_parameter(parameter):
                self._node.declare_parameter(parameter, spec.default, descriptor(spec))
        return replace(chosen, timer=ProcessAnswerTimer(),
                       tuning=partial(self._values, chosen) if chosen.tunables else None)

    def _values(self, chosen: ControllerChoice) -> dict[str, float]:
        node, prefix = self._node, chosen.prefix
        return {spec.name: node.get_parameter(f'{prefix}.{spec.name}').value
                for spec in chosen.tunables}

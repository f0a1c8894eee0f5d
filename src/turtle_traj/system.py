"""Simulator, trajectory node and a client in one process and one executor.

For scripts that own their process (the demo, benchmarks): it spins the executor itself, so
never use it from inside another node's callback.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from turtlesim.msg import Pose

from turtle_traj.node.trajectory_node import TrajectoryNode
from turtle_traj.runtime import spin_until
from turtle_traj.sim.node import TURTLE_TOPIC_QOS, SimNode


class InProcessSystem:
    """SimNode + TrajectoryNode on simulated time, with a client node that records poses."""

    def __init__(self, *, context: Context | None = None, time_scale: float = 20.0,
                 output_dir: Path = Path('output'), **node_parameters: object) -> None:
        sim_time = [Parameter('use_sim_time', value=True)]
        self.sim = SimNode(context=context, parameter_overrides=[
            Parameter('time_scale', value=time_scale), Parameter('publish_clock', value=True),
            Parameter('output_dir', value=str(output_dir))])
        self.node = TrajectoryNode(context=context, parameter_overrides=sim_time + [
            Parameter(name, value=value) for name, value in node_parameters.items()])
        self.client = Node('turtle_traj_client', context=context, parameter_overrides=sim_time)
        self.executor = SingleThreadedExecutor(context=context)
        for node in (self.sim, self.node, self.client):
            self.executor.add_node(node)
        self.poses: list[Pose] = []
        self.client.create_subscription(Pose, 'turtle1/pose', self.poses.append,
                                        TURTLE_TOPIC_QOS)
        if not self.spin_until(lambda: self.node.ready and bool(self.poses), timeout_s=10.0):
            raise RuntimeError('the in-process system did not come up within 10 s')

    def spin_until(self, condition: Callable[[], bool], *, timeout_s: float = 20.0) -> bool:
        """Spin until condition() holds or timeout_s of wall time passed; return condition()."""
        return spin_until(self.executor, condition, timeout_s=timeout_s)

    def spin_sim_seconds(self, seconds: float) -> None:
        """Spin until the simulator has advanced by `seconds` of simulated time."""
        end = self.sim.world.time_s + seconds
        if not self.spin_until(lambda: self.sim.world.time_s >= end,
                               timeout_s=10.0 + 2.0 * seconds):
            raise RuntimeError('simulated time did not advance')

    def start(self, service_type, name: str, request=None):
        """Send a request and return its future; a relative name is one of the node's."""
        if not name.startswith('/'):
            name = f'{self.node.get_fully_qualified_name()}/{name}'
        client = self.client.create_client(service_type, name)
        if not self.spin_until(client.service_is_ready, timeout_s=10.0):
            raise RuntimeError(f'no service {name}')
        return client.call_async(request if request is not None else service_type.Request())

    def call(self, service_type, name: str, request=None, *, timeout_s: float = 120.0):
        """Call a service and return its response."""
        future = self.start(service_type, name, request)
        if not self.spin_until(future.done, timeout_s=timeout_s):
            raise RuntimeError(f'{name} did not answer within {timeout_s:g} s')
        return future.result()

    def run(self, service_type, name: str, request=None, *, timeout_s: float = 120.0):
        """Call a trajectory service; `poses` then holds exactly the poses of that run."""
        self.poses.clear()
        return self.call(service_type, name, request, timeout_s=timeout_s)

    def close(self) -> None:
        self.executor.shutdown()
        for node in (self.client, self.node, self.sim):
            node.destroy_node()

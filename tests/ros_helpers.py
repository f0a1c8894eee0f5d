"""Helpers for driving an in-process executor in tests, without sleeps."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter

from turtle_traj.runtime import spin_until
from turtle_traj.sim.node import SimNode
from turtle_traj.system import InProcessSystem

# Fast enough for whole trajectories in seconds, slow enough that a controller in the same
# executor still sees (almost) every pose.
TEST_TIME_SCALE = 20.0


class SimHarness:
    """Our simulator plus a client node on simulated time, in one in-process executor."""

    def __init__(self, context: Context, output_dir: Path, *, time_scale: float = TEST_TIME_SCALE):
        self.context = context
        self.sim = SimNode(context=context, parameter_overrides=[
            Parameter('time_scale', value=time_scale),
            Parameter('publish_clock', value=True),
            Parameter('output_dir', value=str(output_dir)),
        ])
        self.client = Node('test_client', context=context,
                           parameter_overrides=[Parameter('use_sim_time', value=True)])
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.sim)
        self.executor.add_node(self.client)

    def spin_until(self, condition: Callable[[], bool], *, timeout_s: float = 20.0) -> bool:
        return spin_until(self.executor, condition, timeout_s=timeout_s)

    def spin_sim_seconds(self, seconds: float) -> None:
        """Spin until the simulator has advanced by `seconds` of simulated time."""
        end = self.sim.world.time_s + seconds
        assert self.spin_until(lambda: self.sim.world.time_s >= end,
                               timeout_s=10.0 + 2.0 * seconds)

    def call(self, service_type, name: str, request=None, *, timeout_s: float = 20.0):
        """Call a service through the graph (as any other process would) and return the reply."""
        client = self.client.create_client(service_type, name)
        try:
            assert self.spin_until(client.service_is_ready, timeout_s=10.0), f'no service {name}'
            future = client.call_async(request if request is not None
                                       else service_type.Request())
            assert self.spin_until(future.done, timeout_s=timeout_s), f'{name} did not answer'
            return future.result()
        finally:
            self.client.destroy_client(client)

    def close(self) -> None:
        self.executor.shutdown()
        for node in (self.client, self.sim):
            node.destroy_node()


class TrajHarness(InProcessSystem):
    """The in-process system at the tests' time scale, plus extra nodes on its executor."""

    def __init__(self, context: Context, output_dir: Path, **node_parameters):
        super().__init__(context=context, time_scale=TEST_TIME_SCALE, output_dir=output_dir,
                         **node_parameters)


@contextmanager
def program(*args: str, cwd: Path | None = None) -> Iterator[subprocess.Popen]:
    """Run `python -m ARGS` until its turtle1 has spawned; always reaped afterwards."""
    process = subprocess.Popen([sys.executable, '-m', *args], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, cwd=cwd)
    try:
        for line in process.stderr:
            if 'Spawning turtle [turtle1]' in line:
                break
        yield process
    finally:
        process.kill()
        process.communicate(timeout=15)


def terminate(process: subprocess.Popen) -> str:
    """Send SIGTERM, wait for the exit and return what the program wrote to stderr."""
    process.terminate()
    return process.communicate(timeout=15)[1]

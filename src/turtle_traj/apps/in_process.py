"""Our simulator and other nodes in one process, on lock-step simulated time.

For scripts that own their process (the demo, benchmarks, tests): these classes spin their
executor themselves, so never use them from inside another node's callback.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from rclpy.action import ActionClient
from rclpy.client import Client
from rclpy.context import Context
from rclpy.node import Node
from rclpy.parameter import Parameter
from turtlesim.msg import Pose

from turtle_traj.fleet.coordinator import FleetCoordinator
from turtle_traj.node.trajectory_node import TrajectoryNode
from turtle_traj.rosutils.lockstep import LockstepExecutor
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.rosutils.runtime import spin_until
from turtle_traj.sim.base_adapter import BaseAdapter
from turtle_traj.sim.node import SimNode

# Lock-step runs many times faster than real time even on a loaded machine: a wait that has
# not ended after this much wall time is stuck, not slow (or the simulator was taken away).
_WALL_SAFETY_MIN_S = 60.0
# In-process endpoints still meet through DDS discovery: milliseconds when quiet, and once more
# than 10 s with both cores busy. Only a bound.
_DISCOVERY_TIMEOUT_S = 60.0
_WALL_SAFETY_PER_SIM_S = 0.5
SIM_TIME = Parameter('use_sim_time', value=True)


class LockstepSim:
    """Our simulator and a client node (on simulated time) in one lock-step executor.

    Every wait is bounded in simulated seconds, so no outcome depends on machine load.
    """

    def __init__(self, *, context: Context | None = None, output_dir: Path = Path('output'),
                 client_name: str = 'turtle_traj_client',
                 sim_parameters: dict[str, object] | None = None,
                 pace: float | None = None) -> None:
        """:param pace: keep simulated time to at most this many times the wall clock (as a
            program's `--time-scale`); None: as fast as the CPU allows."""
        self.nodes: list[Node] = []
        self.executor: LockstepExecutor | None = None
        self.node: TrajectoryNode | None = None  # relative service names are this node's
        self._service_clients: dict[tuple[type, str], Client] = {}
        self._action_clients: list[ActionClient] = []
        with self._closed_on_error():
            self.sim = self._create_simulator(context, [
                Parameter('output_dir', value=str(output_dir)),
                *(Parameter(name, value=value) for name, value in (sim_parameters or {}).items())])
            self.add_node(self.sim)
            # The client only calls and listens: no parameter services of its own to wait on.
            self.add_node(Node(client_name, context=context, parameter_overrides=[SIM_TIME],
                               start_parameter_services=False))
            self.client = self.nodes[-1]
            self.executor = LockstepExecutor(self.sim, context=context, pace=pace)
            for node in self.nodes:
                self.executor.add_node(node)

    def _create_simulator(self, context: Context | None, overrides: list[Parameter]) -> SimNode:
        """The simulator lock-step steps (subclasses may run another)."""
        return SimNode(context=context, lockstep=True, parameter_overrides=overrides)

    @contextmanager
    def _closed_on_error(self) -> Iterator[None]:
        """A constructor that fails destroys what it made (never the garbage collector)."""
        try:
            yield
        except BaseException:
            self.close()
            raise

    def add_node(self, node: Node) -> None:
        """Spin one more node in the same executor (it is destroyed by `close`)."""
        self.nodes.append(node)
        if self.executor is not None:
            self.executor.add_node(node)

    @property
    def sim_time_s(self) -> float:
        return self.sim.time_s

    def spin_until(self, condition: Callable[[], bool], *, timeout_s: float = 60.0) -> bool:
        """Spin until condition() holds or `timeout_s` of simulated time passed."""
        deadline = self.sim_time_s + timeout_s
        spin_until(self.executor, lambda: condition() or self.sim_time_s > deadline,
                   timeout_s=max(_WALL_SAFETY_MIN_S, _WALL_SAFETY_PER_SIM_S * timeout_s))
        return bool(condition())

    def spin_sim_seconds(self, seconds: float) -> None:
        """Spin until the simulator has advanced by `seconds` of simulated time."""
        end = self.sim_time_s + seconds
        if not self.spin_until(lambda: self.sim_time_s >= end, timeout_s=seconds + 1.0):
            raise RuntimeError('simulated time did not advance')

    def _resolve(self, name: str) -> str:
        """A relative service name is the trajectory node's, when there is one."""
        if self.node is None or name.startswith('/'):
            return name
        return f'{self.node.get_fully_qualified_name()}/{name}'

    def _add_trajectory_node(self, context: Context | None,
                             parameters: dict[str, object]) -> None:
        """Run a TrajectoryNode (on simulated time) beside the simulator."""
        self.node = TrajectoryNode(context=context, parameter_overrides=[SIM_TIME] + [
            Parameter(name, value=value) for name, value in parameters.items()])
        self.add_node(self.node)

    def _wait_until_up(self, heard: Callable[[], bool]) -> None:
        """Spin until the trajectory node is ready and `heard()`; RuntimeError if not."""
        if not self.spin_until(lambda: self.node.ready and heard(),
                               timeout_s=_DISCOVERY_TIMEOUT_S):
            raise RuntimeError(f'the in-process system did not come up within '
                               f'{_DISCOVERY_TIMEOUT_S:g} s')

    def action_client(self, action_type: type, name: str) -> ActionClient:
        """An action client on the client node, destroyed by `close` (rclpy's destroy_node
        leaves a node's action clients alive, and with them the node)."""
        client = ActionClient(self.client, action_type, self._resolve(name))
        self._action_clients.append(client)
        return client

    def start(self, service_type, name: str, request=None):
        """Send a request and return its future."""
        name = self._resolve(name)
        client = self._service_clients.get((service_type, name))
        if client is None:
            client = self.client.create_client(service_type, name)
            self._service_clients[service_type, name] = client
        if not self.spin_until(client.service_is_ready, timeout_s=_DISCOVERY_TIMEOUT_S):
            raise RuntimeError(f'no service {name}')
        return client.call_async(request if request is not None else service_type.Request())

    def call(self, service_type, name: str, request=None, *, timeout_s: float = 600.0):
        """Call a service and return its response; `timeout_s` is simulated time."""
        future = self.start(service_type, name, request)
        if not self.spin_until(future.done, timeout_s=timeout_s):
            raise RuntimeError(f'{name} did not answer within {timeout_s:g} s')
        return future.result()

    def close(self) -> None:
        """Shut the executor down, then destroy the nodes, newest first."""
        if self.executor is not None:
            self.executor.shutdown()
        while self._action_clients:
            self._action_clients.pop().destroy()
        while self.nodes:
            self.nodes.pop().destroy_node()


class InProcessSystem(LockstepSim):
    """LockstepSim plus a TrajectoryNode; the client records turtle1's poses in `poses`.

    Relative service names are the trajectory node's: `call(DrawShape, 'draw_square', ...)`.
    """

    def __init__(self, *, context: Context | None = None, output_dir: Path = Path('output'),
                 sim_parameters: dict[str, object] | None = None, base_adapter: bool = False,
                 pace: float | None = None, **node_parameters: object) -> None:
        """:param base_adapter: also run `BaseAdapter`, so the simulator is seen as a ROS 2
            base (Odometry on odom, TwistStamped on cmd_vel).
        :param pace: as `LockstepSim`'s."""
        super().__init__(context=context, output_dir=output_dir, sim_parameters=sim_parameters,
                         pace=pace)
        with self._closed_on_error():
            if base_adapter:
                self.add_node(BaseAdapter(context=context, parameter_overrides=[SIM_TIME]))
            self._add_trajectory_node(context, node_parameters)
            self.poses: list[Pose] = []
            self.client.create_subscription(Pose, 'turtle1/pose', self.poses.append,
                                            TURTLE_TOPIC_QOS)
            self._wait_until_up(lambda: bool(self.poses))

    def start(self, service_type, name: str, request=None):
        """Send a request; one to the trajectory node (a relative name) empties `poses` first,
        so that they then hold exactly the poses of that call."""
        if not name.startswith('/'):
            self.poses.clear()
        return super().start(service_type, name, request)


class InProcessFleet(LockstepSim):
    """LockstepSim with `turtles` turtles at `places` (x, y, theta each; turtle1 first), a
    trajectory node for each in its namespace and the fleet coordinator; the client records
    every turtle's poses in `poses`, by name."""

    def __init__(self, places: list[tuple[float, float, float]], *,
                 context: Context | None = None, output_dir: Path = Path('output'),
                 **node_parameters: object) -> None:
        super().__init__(context=context, output_dir=output_dir)
        with self._closed_on_error():
            self.names = [f'turtle{number}' for number in range(1, len(places) + 1)]
            self.poses: dict[str, list[Pose]] = {name: [] for name in self.names}
            self.sim.world.teleport_absolute('turtle1', *places[0])
            for name, place in zip(self.names[1:], places[1:], strict=True):
                self.sim.spawn_turtle(name, *place)
            self.turtle_nodes = {}
            for name in self.names:
                self.turtle_nodes[name] = TrajectoryNode(
                    context=context, namespace=f'/{name}', parameter_overrides=[
                        SIM_TIME, Parameter('turtle_name', value=''),
                        *(Parameter(key, value=value) for key, value in node_parameters.items())])
                self.add_node(self.turtle_nodes[name])
                self.client.create_subscription(Pose, f'/{name}/pose', self.poses[name].append,
                                                TURTLE_TOPIC_QOS)
            self.coordinator = FleetCoordinator(context=context, parameter_overrides=[SIM_TIME])
            self.add_node(self.coordinator)
            if not self.spin_until(lambda: all(node.ready for node in self.turtle_nodes.values())
                                   and all(self.poses.values()),
                                   timeout_s=_DISCOVERY_TIMEOUT_S):
                raise RuntimeError(f'the fleet did not come up within {_DISCOVERY_TIMEOUT_S:g} s')
            self.sim.canvas.clear()  # turtle1's teleport drew its way to its place

    def lose(self, name: str, how: str) -> None:
        """Take turtle `name` from the fleet mid-run: 'kill' removes it with turtlesim's /kill;
        'node' destroys its trajectory node (the turtle stays)."""
        if how == 'kill':
            from turtlesim.srv import Kill
            self.call(Kill, '/kill', Kill.Request(name=name))
            return
        node = self.turtle_nodes.pop(name)
        self.executor.remove_node(node)
        self.nodes.remove(node)
        node.destroy_node()

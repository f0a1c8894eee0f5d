"""A managed controller server, as Nav2's: the lifecycle node `controller_server`.

A Nav2 lifecycle manager brings it up through its `lifecycle_msgs` services, and it reads the
`controller_server:` section of a Nav2 parameter file (`core.parameters.nav2_file`). Its states
behave as Nav2's servers' do:

- unconfigured: nothing but the lifecycle services (and the parameters the file gave it);
- configure: the section read and checked (a value it cannot honour fails the transition, the
  log saying which and why; every key it does not use is listed once, in a warning), and the
  robot's follower made: a trajectory node (`<name>_follower`, in the same namespace) with the
  settings the file gives, which reads the odometry and publishes the commands;
- active: `follow_path` (nav2_msgs/action/FollowPath) on this node drives goals; a goal's
  `controller_id` names one of the file's `controller_plugins`, and its `goal_checker_id` the
  goal checker that judges where its run ended (`core.control.goal_check`); speed limits on
  `speed_limit_topic` (Nav2's speed filter's) cap the speed from the next control period;
- deactivate: a goal under way is aborted and the robot stopped at once; new goals are
  rejected until it is active again;
- cleanup and shutdown: the action server and the follower are destroyed.
"""

from __future__ import annotations

from lifecycle_msgs.srv import ChangeState
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from rclpy.parameter import Parameter
from rclpy.task import Future

from turtle_traj.api.controllers import choose, from_plugin_name
from turtle_traj.core.control.controllers.catalogue import parameter_prefix
from turtle_traj.core.control.ending import Ending
from turtle_traj.core.parameters.nav2_file import ServerConfig, read_server_section
from turtle_traj.node.nav2_follow_path import Nav2FollowPath
from turtle_traj.node.speed_limit import SpeedLimits
from turtle_traj.node.trajectory_node import TrajectoryNode

NODE_NAME = 'controller_server'
RETIRE_PERIOD_S = 0.01  # how often released parts look whether their goal's result is out


class ControllerServer(LifecycleNode):
    """Nav2's controller server, with our controllers (see the module's docstring); the
    follower it makes at configure spins in the executor that spins this node."""

    def __init__(self, node_name: str = NODE_NAME, **kwargs) -> None:
        super().__init__(node_name, allow_undeclared_parameters=True,
                         automatically_declare_parameters_from_overrides=True, **kwargs)
        self.config: ServerConfig | None = None
        self.configure_error: str | None = None  # why the last configure failed
        self.follower: TrajectoryNode | None = None
        self._follow_path = None
        self._speed_limits: SpeedLimits | None = None
        self._retired: list[_Retired] = []  # released, not yet all destroyed
        self._retire_timer = None
        self._active = False
        self._group = ReentrantCallbackGroup()
        self._change_state = self._service_change_state.callback
        self._service_change_state.callback = self._on_change_state
        self.get_logger().info(f'{self.get_fully_qualified_name()}: unconfigured, serving its '
                               'lifecycle services (configure, then activate it)')

    def _on_change_state(self, request: ChangeState.Request,
                         response: ChangeState.Response) -> ChangeState.Response:
        """rclpy's answer, for a transition the current state has; a refusal for any other
        (rclpy raises from the service's callback, which would end the program)."""
        available = {(transition[0], transition[1])
                     for transition in self._state_machine.available_transitions}
        wanted = request.transition
        if not any(wanted.id == number if not wanted.label else wanted.label == label
                   for number, label in available):
            state = self._state_machine.current_state[1]
            self.get_logger().warning(f'change_state: transition {wanted.label or wanted.id} '
                                      f'is not one the state {state} has: refused')
            response.success = False
            return response
        return self._change_state(request, response)

    @property
    def active(self) -> bool:
        return self._active

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.configure_error = None
        try:
            self.config = config = read_server_section(
                self._file_values(), controller_name=from_plugin_name,
                tunables=lambda name: choose(name).tunables, prefix=parameter_prefix)
            self.follower = self._make_follower(config)
        except ValueError as error:  # Nav2ConfigError, or a value rclpy refused
            return self._fail(str(error))
        self._follow_path = Nav2FollowPath(self, self.follower.runs, self._group,
                                           accepting=lambda: self._active,
                                           controller_ids=config.controllers,
                                           goal_checkers=config.goal_checkers)
        self._speed_limits = SpeedLimits(self, config.speed_limit_topic, self.follower)
        if config.ignored:
            self.get_logger().warning('keys of the controller_server section this server does '
                                      'not use: ' + '; '.join(config.ignored))
        controllers = ', '.join(f'{index} ({name})' for index, name in config.controllers.items())
        self.get_logger().info(f'configured: controllers {controllers}; commands at '
                               f"{config.node_parameters['control_rate']:g} Hz")
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._active = True
        return super().on_activate(state)

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._active = False
        if self.follower is not None:
            self.follower.abort_run('the controller server was deactivated', Ending.STOPPED)
        return super().on_deactivate(state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._release()
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._active = False
        if self.follower is not None:
            self.follower.abort_run('the controller server is shutting down',
                                    Ending.SHUTTING_DOWN)
        self._release()
        return TransitionCallbackReturn.SUCCESS

    def shutdown_turtle(self) -> Future | None:
        """End any goal and leave the robot standing (on program exit): what to wait for."""
        return self.follower.shutdown_turtle() if self.follower is not None else None

    def destroy_node(self) -> None:
        self._release(now=True)
        super().destroy_node()

    def _file_values(self) -> dict[str, object]:
        """Every parameter this node holds (the file's section), by its dotted name."""
        names = self.list_parameters([], 0).names
        return {parameter.name: parameter.value for parameter in self.get_parameters(names)}

    def _make_follower(self, config: ServerConfig) -> TrajectoryNode:
        """The trajectory node that drives the robot with the file's settings, spinning beside
        this node.

        :raises ValueError: a setting the node refuses, with rclpy's reason.
        """
        overrides = [Parameter(name, value=value)
                     for name, value in config.node_parameters.items()]
        overrides += [Parameter('controller', value=config.controllers[config.default_controller]),
                      Parameter('use_sim_time',
                                value=self.get_parameter('use_sim_time').value)]
        try:
            follower = TrajectoryNode(f'{self.get_name()}_follower', follow_path=False,
                                      namespace=self.get_namespace(), context=self.context,
                                      parameter_overrides=overrides)
        except Exception as error:  # rclpy's refusal of a value, with its reason
            raise ValueError(f'{type(error).__name__}: {error}') from None
        if self.executor is not None:
            self.executor.add_node(follower)
        return follower

    def _release(self, *, now: bool = False) -> None:
        """Let go of what configure made: the action server, the speed limits, the follower.
        They go in steps, on a timer (`_Retired`), unless `now` (the node itself is being
        destroyed, its executor no longer spinning)."""
        retired = _Retired(self._follow_path, self._speed_limits, self.follower)
        self._follow_path = self._speed_limits = self.follower = None
        self.config = None
        if not retired.gone:
            self._retired.append(retired)
        self._destroy_retired(now=now)

    def _destroy_retired(self, *, now: bool = False) -> None:
        self._retired = [retired for retired in self._retired if not retired.step(now)]
        if self._retired and self._retire_timer is None:
            # on the node clock: lock-step time steps while the executor works on
            self._retire_timer = self.create_timer(RETIRE_PERIOD_S, self._destroy_retired)
        elif not self._retired and self._retire_timer is not None:
            self.destroy_timer(self._retire_timer)
            self._retire_timer = None

    def _fail(self, message: str) -> TransitionCallbackReturn:
        self.configure_error = message
        self.get_logger().error(f'configure failed: {message}')
        self._release()
        return TransitionCallbackReturn.FAILURE


class _Retired:
    """What a configure made, released: a goal whose run was just aborted still has its
    result to send, so the action server goes once it has; the follower leaves the executor
    then, and is destroyed a step later, when no callback of its can still be on its way (an
    executor may run one it collected before the node left it)."""

    def __init__(self, follow_path, speed_limits, follower: TrajectoryNode | None) -> None:
        self.follow_path, self.speed_limits, self.follower = follow_path, speed_limits, follower
        self._removed = False

    @property
    def gone(self) -> bool:
        return self.follow_path is None and self.speed_limits is None and self.follower is None

    def step(self, now: bool) -> bool:
        """One step of letting go (every step, `now`); whether all is gone."""
        if self.follow_path is not None:
            if self.follow_path.running is not None and not now:
                return False
            self.follow_path.destroy()
            self.follow_path = None
        if self.speed_limits is not None:
            self.speed_limits.destroy()
            self.speed_limits = None
        follower = self.follower
        if follower is not None and not self._removed:
            self._removed = True
            follower.shutdown_turtle()
            if follower.executor is not None:
                follower.executor.remove_node(follower)
            if not now:
                return False
        if follower is not None:
            follower.destroy_node()
            self.follower = None
        return True

"""The fleet coordinator: one drawing shared out among several turtles, each driven by its own
trajectory node, kept apart by timing.

`~/draw` (turtle_traj_interfaces/action/FleetDraw) plans the drawing as the first turtle's node
would (with that node's parameters, from its pose, or where the last drawing started while it
stands parked after it: `core.fleet.anchor`), shares its pieces out (`core.fleet`), and sends
each turtle its moves one Draw goal at a time, each when the schedule allows: as soon as the
moves it waits for end (in their goals' result callbacks). A timer (`TICK_S`, node clock)
watches the turtles, publishes the feedback and completes the future the goal's handler
awaits once every piece is drawn and every turtle parked.
"""

from __future__ import annotations

from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.action.server import ServerGoalHandle
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node
from rclpy.parameter import parameter_value_to_python
from rclpy.task import Future
from turtle_traj_interfaces.action import FleetDraw

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.fleet.anchor import Anchor, drawing_start
from turtle_traj.core.fleet.pieces import pieces_in
from turtle_traj.core.fleet.run import FleetRun, closest
from turtle_traj.core.fleet.timing import Deadlock
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import (
    Settings,
    pen_style,
    settings_from_values,
)
from turtle_traj.core.parameters.table import PARAMETERS
from turtle_traj.core.planning.planner import PlanError, plan
from turtle_traj.core.turtlesim_contract import PenStyle
from turtle_traj.fleet.checks import colors, colors_problem, names_problem, too_close
from turtle_traj.fleet.in_progress import DrawingInProgress, progress, refusal, report
from turtle_traj.fleet.link import MoveEnd, TurtleLink, node_of
from turtle_traj.node.waiting import completion, result_within, wait_until
from turtle_traj.rosutils.clock_read import now_ns
from turtle_traj.rosutils.offload import Offloader

TICK_S = 0.02  # node clock: how often moves are started and turtles watched
FEEDBACK_EVERY = 5  # ticks: 10 Hz
READY_TIMEOUT_S = 10.0  # wall: for the turtles' nodes to be found
ANSWER_TIMEOUT_S = 5.0  # wall: for the first turtle's node to tell its parameters
# node clock: a node that sends its turtle no command for this long while it drives a move has
# stopped (it commands every control period); its turtle would run on with its last command for
# turtlesim's 1 s command timeout, pen down, so it is stopped and its pen lifted at once
COMMAND_SILENCE_S = 0.25


class Refused(Exception):
    """A goal that cannot be drawn: the message says why, `reason` is the Ending."""

    def __init__(self, message: str, reason: Ending) -> None:
        super().__init__(message)
        self.reason = reason


class FleetCoordinator(Node):
    """`fleet`: serves `~/draw` for the turtles whose trajectory nodes it finds."""

    def __init__(self, **kwargs) -> None:
        super().__init__('fleet', **kwargs)
        self.declare_parameter('clearance', 0.6, ParameterDescriptor(
            description='Least distance between two turtles\' centres, when a goal leaves it 0 '
                        '[m]', floating_point_range=[FloatingPointRange(from_value=0.05,
                                                                          to_value=5.0)]))
        self.declare_parameter('turtle_colors', '', ParameterDescriptor(
            description='Pen colours, comma-separated (names or #rrggbb), one for each turtle '
                        "in turn, to see who drew what; '': the drawing's pen for all"))
        self.add_on_set_parameters_callback(colors_problem)
        self._links: dict[str, TurtleLink] = {}
        self._planner = Offloader(self, 'fleet_plan')
        self._drawing: DrawingInProgress | None = None
        self._anchor: Anchor | None = None  # where the last drawing started
        self._claimed = False  # a goal is being prepared or drawn
        group = ReentrantCallbackGroup()
        self._server = ActionServer(self, FleetDraw, '~/draw', self._execute,
                                    goal_callback=lambda _: GoalResponse.ACCEPT,
                                    cancel_callback=self._on_cancel, callback_group=group)
        self._timer = self.create_timer(TICK_S, self._tick)

    def destroy_node(self) -> None:
        self._server.destroy()
        for link in self._links.values():
            link.destroy()
        super().destroy_node()

    # -- the goal ---------------------------------------------------------------------------

    async def _execute(self, goal_handle: ServerGoalHandle) -> FleetDraw.Result:
        if self._claimed:
            goal_handle.abort()
            return refusal('the fleet is drawing another request', Ending.BUSY)
        self._claimed = True
        received_s = self._now_s()
        try:
            drawing = await self._prepare(goal_handle, received_s)
            self._drawing = drawing
            held = self._elsewhere(drawing.links)
            for link in held:
                link.hold()
            try:
                await wait_until(self, lambda: all(link.held for link in held), READY_TIMEOUT_S)
                for link in held:
                    link.assert_hold()
                self._tick()
                await completion(self, drawing.finished)
            finally:
                for link in held:
                    link.release()
            drawing.goal.publish_feedback(progress(drawing, self._now_s()))
            if drawing.run.done and drawing.failure is None and drawing.links[0].present():
                self._anchor = Anchor(drawing.links[0].name, drawing.anchor,
                                      drawing.links[0].pose)
            return report(drawing, self._now_s())
        except Refused as refused:
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
            else:
                goal_handle.abort()
            return refusal(str(refused), refused.reason)
        finally:
            self._drawing, self._claimed = None, False

    async def _prepare(self, goal_handle: ServerGoalHandle,
                       received_s: float) -> DrawingInProgress:
        """The drawing planned and shared out, its turtles ready; Refused if it cannot be."""
        goal = goal_handle.request
        names, clearance = self._asked(goal)
        links = [self._link(name) for name in names]
        await wait_until(self, lambda: all(link.serves() for link in links), READY_TIMEOUT_S)
        left_out = [f'{link.name}: {why}' for link in links if (why := _unfit(link))]
        drawers = [link for link in links if not _unfit(link)]
        if not drawers:
            raise Refused('no turtle can draw: ' + '; '.join(left_out), Ending.NO_SIMULATOR)
        settings = await self._settings_of(drawers[0])
        standing = [link.pose for link in links if link not in drawers and link.present()]
        starts = [link.pose for link in drawers]
        if problem := too_close([(link.name, link.pose) for link in links if link.present()],
                                 clearance):
            raise Refused(problem, Ending.INVALID_REQUEST)

        anchor = drawing_start(self._anchor, drawers[0].name, drawers[0].pose)

        def shared() -> tuple[Plan, ControlConfig, FleetRun]:
            planned = plan(goal.drawing.trajectory, goal.drawing, anchor, settings)
            config = planned.control(settings.control)
            return planned, config, FleetRun(
                pieces_in(planned.path, config, corner_angle=settings.defaults.corner_angle),
                [link.name for link in drawers], starts,
                config, clearance, standing, settings.arena)
        # Planned beside the executor (seconds on a loaded machine): meanwhile this node still
        # answers its clients, and lock-step holds the simulator, as for a callback.
        try:
            planned, config, run = await completion(self, self._planner.submit(shared))
        except (PlanError, Deadlock) as error:
            raise Refused(str(error), Ending.INVALID_REQUEST) from None
        # The first moves go once each turtle has been heard from since, by the node clock (in
        # lock-step: at the next step, whatever the wall clock did meanwhile).
        planned_s = self._now_s()
        heard = Future()

        def fresh() -> None:
            if not heard.done() and all(link.heard_s > planned_s for link in drawers):
                heard.set_result(True)
        for link in drawers:
            link.on_pose = lambda: (fresh(), self._measure())
        await result_within(self, heard, READY_TIMEOUT_S)
        for link in drawers:
            link.on_pose = self._measure
        if goal_handle.is_cancel_requested:
            raise Refused('cancelled before it started', Ending.CANCELLED)
        return DrawingInProgress(run, drawers,
                                 self._pens(planned.pen or settings.pen, len(drawers)),
                                 config.linear_speed, goal_handle, received_s, left_out, starts,
                                 anchor, self._now_s())

    def _pens(self, pen: PenStyle, count: int) -> list[PenStyle]:
        """Each turtle's pen: the drawing's, or in `turtle_colors` (one colour per turtle, in
        turn), its width the drawing's."""
        chosen = colors(self.get_parameter('turtle_colors').value)
        return [pen_style(chosen[index % len(chosen)], pen.width) if chosen else pen
                for index in range(count)]

    def _asked(self, goal: FleetDraw.Goal) -> tuple[list[str], float]:
        """The turtles and the clearance the goal asks for; Refused if they will not do."""
        names = list(goal.turtles) or self._turtles_found()
        problem = names_problem(names, goal.drawing.trajectory)
        if problem:
            raise Refused(problem, Ending.INVALID_REQUEST)
        clearance = goal.clearance or self.get_parameter('clearance').value
        if not (0.05 <= clearance <= 5.0):
            raise Refused(f'clearance must be within 0.05 and 5 m, got {clearance:g}',
                          Ending.INVALID_REQUEST)
        return names, clearance

    def _elsewhere(self, links: list[TurtleLink]) -> list[TurtleLink]:
        """The turtles whose nodes run in another program: we hold their leases, so that they
        stop if this program dies (nodes in this one die with it; and DDS asserts no
        liveliness to a reader in its own participant, so a lease held here lapses at once)."""
        here = {node.get_fully_qualified_name()
                for node in (self.executor.get_nodes() if self.executor else [])}
        return [link for link in links if node_of(link.name) not in here]

    def _turtles_found(self) -> list[str]:
        """The turtles whose trajectory node is in the graph, turtle1 first."""
        found = [namespace.strip('/') for name, namespace in
                 self.get_node_names_and_namespaces()
                 if name == 'turtle_traj' and namespace.count('/') == 1 and namespace != '/']
        return sorted(set(found), key=lambda n: (not n.startswith('turtle'), len(n), n))

    def _link(self, name: str) -> TurtleLink:
        if name not in self._links:
            self._links[name] = TurtleLink(self, name)
        link = self._links[name]
        link.on_pose = self._measure
        return link

    async def _settings_of(self, link: TurtleLink) -> Settings:
        """The settings of `link`'s trajectory node: the drawing is planned as it plans."""
        names = [spec.name for spec in PARAMETERS]
        asked = link.parameters(names)
        answer = await result_within(self, asked, ANSWER_TIMEOUT_S)
        if answer is None:  # its node went between being found and answering
            link.forget(asked)
            raise Refused(f'{node_of(link.name)} did not tell its parameters within '
                          f'{ANSWER_TIMEOUT_S:g} s', Ending.NO_SIMULATOR)
        if answer is None or len(answer.values) != len(names):
            raise Refused(f'{node_of(link.name)} did not tell its parameters', Ending.NO_SIMULATOR)
        return settings_from_values({name: parameter_value_to_python(value)
                                     for name, value in zip(names, answer.values, strict=True)})

    def _on_cancel(self, _: ServerGoalHandle) -> CancelResponse:
        drawing = self._drawing
        if drawing is not None:
            drawing.failure = ('cancelled', Ending.CANCELLED)
            for link in drawing.links:
                link.cancel()
        return CancelResponse.ACCEPT

    # -- the timer: moves started, turtles watched --------------------------------------------

    def _tick(self) -> None:
        drawing = self._drawing
        if drawing is None or drawing.finished.done():
            return
        run = drawing.run
        for index, link in enumerate(drawing.links):
            if not run.driving(index):
                continue
            if link.silent_s() > COMMAND_SILENCE_S:
                link.halt()
                why = (f'its node {node_of(link.name)} sent it no command for '
                       f'{link.silent_s():.2f} s mid-move')
            elif link.liveness.gone():
                why = f'its node {node_of(link.name)} stopped answering'
            else:
                continue
            run.end_failed(index)
            link.cancel()
            self._lose(drawing, index, why)
        self._dispatch(drawing)
        drawing.ticks += 1
        if drawing.ticks % FEEDBACK_EVERY == 0:
            drawing.goal.publish_feedback(progress(drawing, self._now_s()))
        if any(run.driving(index) for index in range(len(drawing.links))):
            return
        if (run.done and run.parked) or drawing.failure is not None or not run.serving:
            drawing.ended_s = self._now_s()  # now: the awaiting handler may resume a step later
            drawing.finished.set_result(True)

    def _dispatch(self, drawing: DrawingInProgress) -> None:
        """Start every move the schedule allows now."""
        run = drawing.run
        if run.replan_due and drawing.failure is None:
            self._carry_lost(drawing)
            if not drawing.carrying:
                self._replan(drawing)
        if drawing.failure is None:
            for index in run.ready():
                move = run.start(index)
                drawing.links[index].drive(move, drawing.pens[index], drawing.linear_speed,
                                           lambda end, index=index: self._move_ended(index, end))

    def _move_ended(self, index: int, end: MoveEnd) -> None:
        drawing = self._drawing
        if drawing is None:
            return
        if end.ok:
            drawing.run.end(index, end.deviation)
        else:
            drawing.run.end_failed(index)
            if drawing.failure is None:
                self._lose(drawing, index, end.why)
        self._dispatch(drawing)

    def _lose(self, drawing: DrawingInProgress, index: int, why: str) -> None:
        """`index` serves no more: it is put out of the others' way once none drives."""
        drawing.run.lose(index, why)
        drawing.to_carry.add(index)

    def _carry_lost(self, drawing: DrawingInProgress) -> None:
        """Lost turtles still in the arena are put out of the way (no turtle that serves
        drives now: none can come near them as they go)."""
        run = drawing.run
        for index in sorted(drawing.to_carry):
            drawing.to_carry.discard(index)
            link = drawing.links[index]
            if not link.present():
                continue
            others = [drawing.links[other].pose for other in run.serving
                      if drawing.links[other].pose is not None]
            drawing.homes[index] = run.out_of_the_way(drawing.homes[index], others)
            drawing.carrying.add(index)
            link.carry(drawing.homes[index], lambda index=index: drawing.carrying.discard(index))

    def _replan(self, drawing: DrawingInProgress) -> None:
        run = drawing.run
        poses = {index: drawing.links[index].pose for index in run.serving}
        standing = self._lost_standing(drawing)
        try:
            run.replan(poses, standing)
        except (Deadlock, ValueError) as error:
            drawing.failure = (f'the drawing cannot be finished: {error}', Ending.NO_PROGRESS)

    def _lost_standing(self, drawing: DrawingInProgress) -> list[Pose2D]:
        """Where the lost turtles still in the arena stand (where they were put)."""
        return [drawing.homes[index] for index, link in enumerate(drawing.links)
                if index not in drawing.run.serving and link.present()]

    def _measure(self) -> None:
        """The least distance between two turtles of the drawing, from their latest poses."""
        drawing = self._drawing
        if drawing is None or drawing.finished.done():
            return
        poses = [(link.pose.x, link.pose.y) for link in drawing.links if link.present()]
        drawing.min_distance = min(drawing.min_distance, closest(poses))

    def _now_s(self) -> float:
        return now_ns(self.get_clock()) * 1e-9

def _unfit(link: TurtleLink) -> str:
    """Why `link`'s turtle cannot take part ('' if it can)."""
    if not link.serves():
        return f'no trajectory node {node_of(link.name)} with its turtle answers'
    if link.moving:
        return 'busy with a request of its own (it is moving)'
    return ''

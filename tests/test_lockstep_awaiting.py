"""Coroutines that await in lock-step resume at the step their future completes, whatever comes
next: a service's answer (`waiting.result_within`, whose future a done callback completes) and
work done beside the executor (`offload`, whose result a task hands over). rclpy 7.1.6's
EventsExecutor resumes them only after a callback of an entity, not of a task: without the
bell `waiting.completion` rings, they would wait for the next step's callbacks, or for a
wall-clock timer's beat that comes sooner in some runs."""

from rclpy.node import Node
from rclpy.parameter import Parameter
from std_srvs.srv import Trigger

from turtle_traj.apps.in_process import SIM_TIME
from turtle_traj.node.waiting import completion, result_within, wait_until
from turtle_traj.rosutils import offload
from turtle_traj.rosutils.lockstep import LockstepExecutor
from turtle_traj.rosutils.runtime import spin_until
from turtle_traj.sim.node import SimNode

STEP_S = 0.016


def _answer(_request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
    response.success = True
    return response


def _system(context, tmp_path):
    """A lock-step executor with the simulator, an answering node and an asking node that has a
    timer on simulated time (a callback every step, as a trajectory node's control tick)."""
    sim = SimNode(context=context, lockstep=True,
                  parameter_overrides=[Parameter('output_dir', value=str(tmp_path))])
    answerer = Node('answerer', context=context, parameter_overrides=[SIM_TIME],
                    start_parameter_services=False)
    answerer.create_service(Trigger, '/answerer/ask', _answer)
    asker = Node('asker', context=context, parameter_overrides=[SIM_TIME],
                 start_parameter_services=False)
    asker.create_timer(STEP_S, lambda: None)
    executor = LockstepExecutor(sim, context=context)
    for node in (sim, answerer, asker):
        executor.add_node(node)
    return executor, sim, [asker, answerer, sim]


async def _next_step(node: Node, sim: SimNode) -> None:
    begun_s = sim.time_s
    assert await wait_until(node, lambda: sim.time_s > begun_s, 5.0)


def _run(executor, coroutine) -> None:
    task = executor.create_task(coroutine)
    while not task.done() and executor.steps < 200:
        executor.spin_once(0.1)
    assert task.done(), 'the coroutine never ended'
    task.result()  # raises what it raised


def _close(executor, nodes) -> None:
    executor.shutdown()
    for node in nodes:
        node.destroy_node()


def test_an_answer_awaited_within_a_timeout_resumes_its_coroutine_in_the_same_step(
        rclpy_context, tmp_path):
    executor, sim, nodes = _system(rclpy_context, tmp_path)
    asker = nodes[0]
    client = asker.create_client(Trigger, '/answerer/ask')
    seen: list[tuple[float, float, object]] = []

    async def ask() -> None:
        for _ in range(5):
            asked_s = sim.time_s
            answer = await result_within(asker, client.call_async(Trigger.Request()), 5.0)
            seen.append((asked_s, sim.time_s, answer))
            await _next_step(asker, sim)
    try:
        # discovery, stepping meanwhile, and an answer: its way back is matched too
        assert spin_until(executor, client.service_is_ready, timeout_s=30.0)
        first = client.call_async(Trigger.Request())
        assert spin_until(executor, first.done, timeout_s=30.0)
        _run(executor, ask())
        assert len(seen) == 5
        for asked_s, answered_s, answer in seen:
            assert answer is not None and answer.success
            assert answered_s == asked_s, f'asked at {asked_s:.3f} s, resumed {answered_s:.3f} s'
        assert seen[-1][0] > seen[0][0]
    finally:
        client.destroy()
        _close(executor, nodes)


def test_work_done_beside_the_executor_resumes_its_coroutine_in_the_step_it_was_asked(
        rclpy_context, tmp_path):
    """Lock-step holds the step while the work is in flight, and the coroutine that awaits it
    resumes before the next step."""
    executor, sim, nodes = _system(rclpy_context, tmp_path)
    worker = offload.Offloader(nodes[0], 'offload_test')
    seen: list[tuple[float, float, int]] = []

    async def compute() -> None:
        for value in range(5):
            asked_s = sim.time_s
            doubled = await completion(nodes[0], worker.submit(lambda value=value: 2 * value))
            seen.append((asked_s, sim.time_s, doubled))
            await _next_step(nodes[0], sim)
    try:
        _run(executor, compute())
        assert [doubled for _, _, doubled in seen] == [0, 2, 4, 6, 8]
        for asked_s, answered_s, _ in seen:
            assert answered_s == asked_s, f'asked at {asked_s:.3f} s, resumed {answered_s:.3f} s'
        assert seen[-1][0] > seen[0][0]  # and the steps went on between them
    finally:
        _close(executor, nodes)

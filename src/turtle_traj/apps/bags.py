"""`turtle-traj record`, `play` and `plot`: bags from the command line."""

from __future__ import annotations

import time
from collections.abc import Callable
from datetime import datetime
from pathlib import Path

import rclpy
from rclpy.node import Node
from rclpy.parameter_client import AsyncParameterClient
from rclpy.task import Future

from turtle_traj.bags.reader import Bag
from turtle_traj.bags.recorder import TopicRecorder, default_topics
from turtle_traj.bags.writer import BagError
from turtle_traj.rosutils.fastdds_profile import use_our_fastdds_profile
from turtle_traj.rosutils.runtime import events_executor, fail, run_nodes

DISCOVERY_S = 2.0  # how long the recorder looks for the topics before it starts
BAGS = Path('bags')  # where bags go by default (and where --last looks)
LIMITS = ('linear_speed', 'angular_speed')  # noted in the bag for the plots


def new_bag_path(name: str, folder: Path = BAGS) -> Path:
    return folder / f'{name}_{datetime.now():%Y%m%d-%H%M%S}'


class _Recording:
    """The recorder node's life: look for the topics, then record until stopped."""

    def __init__(self, output: Path, topics: list[str], node_name: str,
                 defaults: list[str]) -> None:
        self.output, self.asked, self.node_name = output, topics, node_name
        self.defaults = defaults
        self.error: str | None = None
        self.counts: dict[str, int] = {}

    def create(self, stop: Callable[[], None]) -> list[Node]:
        node = rclpy.create_node('turtle_traj_recorder')
        recorder = TopicRecorder(node, self.asked or self.defaults)
        parameters = AsyncParameterClient(node, self.node_name)
        asked: list[Future] = []  # the node's speed limits, noted in the bag for the plots
        began = time.monotonic()

        def look() -> None:
            if not asked and parameters.services_are_ready():
                asked.append(parameters.get_parameters(list(LIMITS)))
            found = recorder.published()
            if time.monotonic() - began < DISCOVERY_S and len(found) < len(recorder.topics):
                return
            timer.cancel()
            limits = {}
            if asked and asked[0].done():
                limits = {name: str(value.double_value) for name, value in
                          zip(LIMITS, asked[0].result().values, strict=True)}
            try:
                recorded = recorder.start(self.output, required=self.asked, custom_data=limits)
            except BagError as error:
                self.error = str(error)
                stop()
                return
            print(f'recording {len(recorded)} topics into {self.output} '
                  f'({", ".join(t.name for t in recorded)}); Ctrl-C ends it', flush=True)
        timer = node.create_timer(0.05, look)
        self.recorder = recorder
        return [node]

    def finish(self) -> None:
        try:
            self.counts = self.recorder.stop()
        except BagError as error:
            self.error = str(error)


def record(output: Path | None, topics: list[str], node_name: str,
           turtle: str = 'turtle1', defaults: list[str] | None = None) -> int:
    """Record `topics` (each must be there), or else `defaults` (those there: by default
    `turtle`'s and the node's), until stopped."""
    output = output or new_bag_path('run')
    if output.exists():
        return fail(f'{output} exists: a bag is never written over')
    recording = _Recording(output, topics, node_name,
                           defaults or default_topics(turtle, node_name))
    code = run_nodes(recording.create, on_exit=recording.finish)
    if recording.error is not None:
        return fail(recording.error)
    total = sum(recording.counts.values())
    print(f'{output}: {total} messages ' + ', '.join(
        f'{topic} {count}' for topic, count in recording.counts.items()))
    return code


def play(path: Path, topics: list[str], rate: float) -> int:
    from turtle_traj.bags.player import Player
    if not rate > 0:
        return fail(f'--rate must be above 0, got {rate}')
    try:
        bag = Bag(path)
    except BagError as error:
        return fail(str(error))
    use_our_fastdds_profile()
    rclpy.init()
    node = rclpy.create_node('turtle_traj_player')
    executor = events_executor()
    executor.add_node(node)

    def wait(seconds: float) -> None:
        executor.spin_until_future_complete(Future(), timeout_sec=seconds)
    try:
        player = Player(node, bag, topics)
        deadline = time.monotonic() + 5.0
        while not player.connected() and time.monotonic() < deadline:
            wait(0.05)
        if not player.connected():
            print(f'(nothing subscribes to {", ".join(player.topics)} yet: playing anyway)')
        count = player.play(rate, wait=wait)
        print(f'played {count} messages of {", ".join(player.topics)} from {path}, each at '
              f'most {1e3 * player.latest_s:.0f} ms after its time')
        return 0
    except BagError as error:
        return fail(str(error))
    except KeyboardInterrupt:
        return 130
    finally:
        bag.close()
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()


def last_bag(folder: Path = BAGS) -> Path | None:
    bags = sorted((p for p in folder.glob('*') if (p / 'metadata.yaml').is_file()),
                  key=lambda p: p.stat().st_mtime)
    return bags[-1] if bags else None


def plot(path: Path | None, output: Path | None) -> int:
    if path is None:
        path = last_bag()
        if path is None:
            return fail(f'no bag in {BAGS}/ to plot (record one with `turtle-traj record`)')
    from turtle_traj.bags.plots import write_plots
    try:
        written = write_plots(path, output or path / 'plots')
    except BagError as error:
        return fail(str(error))
    print('\n'.join(str(file) for file in written))
    return 0

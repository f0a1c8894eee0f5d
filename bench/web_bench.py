"""The live view: frames per second at each page, pose-to-page latency, the simulator's CPU.

Run: .venv/bin/python bench/web_bench.py [--seconds S]

`python -m turtle_traj.sim --web` at real time, its turtle driving a circle (a cmd_vel every
0.5 s from this process). Pages are WebSocket clients in a process of their own (1, then 20),
each counting the frames it receives; the latency is measured in headless chromium, from a
frame's stamp (taken as the simulator publishes the step's poses) to the page drawing it. The
simulator program's CPU is read from /proc with 0, 1 and 20 pages.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import socket
import statistics
import subprocess
import sys
import time
from pathlib import Path

from isolation import isolate
from process_cpu import cpu_share

ROOT = Path(__file__).resolve().parents[1]
TARGET_FPS, TARGET_P95_MS, TARGET_CPU_RATIO = 30.0, 50.0, 2.0
ROUNDS = 3


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


async def _pages(url: str, count: int, seconds: float) -> list[float]:
    """Frames per second each of `count` pages received over `seconds`."""
    import aiohttp

    async def page(session: aiohttp.ClientSession) -> float:
        async with session.ws_connect(url) as socket_:
            frames, start = 0, None
            while True:
                message = await socket_.receive(timeout=10)
                if json.loads(message.data)['type'] != 'frame':
                    continue
                now = time.monotonic()
                if start is None:
                    start = now
                elif now - start >= seconds:
                    return frames / (now - start)
                frames += 1

    async with aiohttp.ClientSession() as session:
        return list(await asyncio.gather(*(page(session) for _ in range(count))))


def pages_main(url: str, count: int, seconds: float) -> None:
    """In a process of its own: the pages, then their frame rates as JSON."""
    print(json.dumps(asyncio.run(_pages(url, count, seconds))))


def _start_pages(url: str, count: int, seconds: float) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, __file__, '--pages', str(count), '--url', url,
                             '--seconds', str(seconds)], stdout=subprocess.PIPE, text=True)


def _drive(port_seconds: float) -> None:
    """Keep turtle1 circling (a command every 0.5 s) for `port_seconds`."""
    import rclpy
    from geometry_msgs.msg import Twist

    from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
    from turtle_traj.rosutils.runtime import events_executor, spin_until
    rclpy.init()
    node = rclpy.create_node('web_bench_driver')
    executor = events_executor()
    executor.add_node(node)
    publisher = node.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
    spin_until(executor, lambda: publisher.get_subscription_count() > 0, timeout_s=20.0)
    end = time.monotonic() + port_seconds
    twist = Twist()
    twist.linear.x, twist.angular.z = 1.0, 0.8
    while time.monotonic() < end:
        publisher.publish(twist)
        time.sleep(0.5)
    rclpy.shutdown()


def _browser_latency(url: str, seconds: float) -> list[float]:
    """Pose-to-page latencies (s) of the frames a headless chromium page drew."""
    from turtle_traj.testing.browser import browser_missing, chromium
    if browser_missing():
        return []
    with chromium() as driver:
        driver.get(url)
        time.sleep(2.0)  # connected, the snapshot drawn
        driver.execute_script('window.turtleTraj.stats().latencies.length = 0')
        start = driver.execute_script('return window.turtleTraj.stats().latencies.length')
        time.sleep(seconds)
        return driver.execute_script('return window.turtleTraj.stats().latencies')[start:]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=10.0, help='length of each window')
    parser.add_argument('--pages', type=int, help=argparse.SUPPRESS)
    parser.add_argument('--url', help=argparse.SUPPRESS)
    parser.add_argument('--drive', type=float, help=argparse.SUPPRESS)
    options = parser.parse_args()
    isolate('web')
    if options.pages:
        pages_main(options.url, options.pages, options.seconds)
        return
    if options.drive:
        _drive(options.drive)
        return
    port = _free_port()
    url = f'http://127.0.0.1:{port}/'
    sim = subprocess.Popen([sys.executable, '-m', 'turtle_traj.sim', '--web', '--web-port',
                            str(port)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    seconds = options.seconds
    driver = subprocess.Popen([sys.executable, __file__, '--drive', str(10 * seconds + 60)])
    try:
        time.sleep(3.0)
        print(f'turtle_traj live view benchmark: the simulator program at real time, its turtle '
              f'circling; {seconds:g} s windows, CPU the median of {ROUNDS} (20 pages: one)')
        # CPU with none and with one page in turn, ROUNDS times (the machine's load drifts);
        # medians of each.
        shares: dict[int, list[float]] = {0: [], 1: [], 20: []}
        fps = {}
        for count in [0, 1] * ROUNDS + [20]:
            if not count:
                shares[0].append(cpu_share(sim.pid, seconds))
                continue
            pages = _start_pages(url + 'ws', count, seconds + 2.0)
            time.sleep(1.5)  # connected, snapshots sent
            shares[count].append(cpu_share(sim.pid, seconds))
            fps[count] = json.loads(pages.communicate(timeout=seconds * 3 + 30)[0])
        cpu = {count: statistics.median(values) for count, values in shares.items()}
        latencies = _browser_latency(url, seconds)
        for count in (1, 20):
            print(f'  frames per second at each page, {count:2d} page(s): min '
                  f'{min(fps[count]):5.1f}, median {statistics.median(fps[count]):5.1f} '
                  f'(target: at least {TARGET_FPS:g} at every page)')
        if latencies:
            ordered = sorted(latencies)
            p50 = 1e3 * ordered[len(ordered) // 2]
            p95 = 1e3 * ordered[int(0.95 * (len(ordered) - 1))]
            print(f'  pose to page (chromium, {len(ordered)} frames drawn): p50 {p50:.1f} ms, '
                  f'p95 {p95:.1f} ms (target: p95 at most {TARGET_P95_MS:g} ms)')
        else:
            print('  pose to page: not measured (chromium and chromedriver are not installed)')
        for count in (0, 1, 20):
            print(f'  simulator program CPU, {count:2d} page(s): {100 * cpu[count]:5.1f}% of a '
                  f'core' + (f' ({cpu[count] / cpu[0]:.2f}x its CPU with none; target: at most '
                             f'{TARGET_CPU_RATIO:g}x with one)' if count else ''))
    finally:
        for process in (driver, sim):
            process.terminate()
            process.wait(timeout=15)


if __name__ == '__main__':
    sys.path.insert(0, str(Path(__file__).parent))
    main()

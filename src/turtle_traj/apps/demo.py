"""`python -m turtle_traj.apps.demo` (`make demo`): draw every trajectory, save pictures, print
a table.

Runs the simulator and the trajectory node in this process on lock-step simulated time, so it
needs no display and no other program, and prints the same table on every run, however busy
the machine is. Pictures go to output/demo/ (one PNG per trajectory, its plots as
<name>-plot.png, and gallery.png).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path

import numpy as np
import rclpy
from PIL import Image, ImageDraw
from std_srvs.srv import Trigger
from turtle_traj_interfaces.srv import SaveImage
from turtlesim.srv import SetPen, TeleportAbsolute

from turtle_traj.api.ros_interface import make_request, service_type
from turtle_traj.apps.in_process import InProcessSystem
from turtle_traj.bags.plots import Run, write_overview
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.registry import TRAJECTORIES, TrajectoryKind
from turtle_traj.core.turtlesim_contract import STEP_S


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog='python -m turtle_traj.apps.demo', description=__doc__)
    parser.add_argument('--output-dir', type=Path, default=Path('output'),
                        help='pictures go to OUTPUT_DIR/demo (default: output)')
    return parser


def prepare(system: InProcessSystem, x: float, y: float, theta: float) -> None:
    """Clean canvas, turtle lifted to the start pose, pen down again."""
    system.call(Trigger, 'reset')
    system.call(SetPen, '/turtle1/set_pen', SetPen.Request(off=1))
    system.call(TeleportAbsolute, '/turtle1/teleport_absolute',
                TeleportAbsolute.Request(x=x, y=y, theta=theta))
    system.spin_sim_seconds(0.1)
    system.call(SetPen, '/turtle1/set_pen', SetPen.Request(r=255, g=255, b=255, width=3))
    if not system.spin_until(lambda: system.node.ready):
        raise RuntimeError('the trajectory node did not get ready after the reset')


def run_example(system: InProcessSystem, trajectory: TrajectoryKind):
    """Draw the trajectory's example from its start pose on a clean canvas; its response."""
    example = trajectory.example
    prepare(system, *example.start)
    return system.call(service_type(trajectory), trajectory.service,
                      make_request(trajectory, example.given))


def _run(system: InProcessSystem, trajectory: TrajectoryKind) -> Run:
    """What the plots need of the run just driven: its poses (one per 16 ms step, lock-step),
    its plan (planned again here, between runs: the node's plan message of a long curve takes
    a while to read, and lock-step time stands still meanwhile) and the node's speed limits."""
    poses = np.array([(index * STEP_S, p.x, p.y, p.theta, p.linear_velocity, p.angular_velocity)
                      for index, p in enumerate(system.poses)]).reshape(-1, 6)
    settings = system.node.settings
    plan = planning.plan(trajectory.name, make_request(trajectory, trajectory.example.given),
                         Pose2D(*trajectory.example.start), settings)
    return Run(trajectory.name, poses, plan.path.points(),
               linear_limit=settings.control.linear_speed,
               angular_limit=settings.control.angular_speed)


def gallery(pictures: list[tuple[str, Path]], target: Path) -> None:
    """All pictures in a labelled grid, one PNG."""
    columns, tile, label = 5, 250, 22
    rows = math.ceil(len(pictures) / columns)
    sheet = Image.new('RGB', (columns * tile, rows * (tile + label)), 'white')
    draw = ImageDraw.Draw(sheet)
    for index, (name, path) in enumerate(pictures):
        x, y = (index % columns) * tile, (index // columns) * (tile + label)
        sheet.paste(Image.open(path).convert('RGB').resize((tile, tile)), (x, y + label))
        draw.text((x + 6, y + 5), name, fill='black')
    sheet.save(target)


def main(args: Sequence[str] | None = None) -> int:
    options = build_parser().parse_args(args)
    folder = (options.output_dir / 'demo').resolve()
    folder.mkdir(parents=True, exist_ok=True)
    rclpy.init()
    wall_start = time.monotonic()
    rows, pictures, plots = [], [], []
    system = None
    # The plots are drawn in another process, on the other core, while lock-step runs on.
    # A fresh interpreter (spawn), not a fork of this one with its middleware's threads.
    plotter = ProcessPoolExecutor(max_workers=1, mp_context=get_context('spawn'))
    try:
        system = InProcessSystem(output_dir=folder)
        sim_start = system.sim_time_s
        for trajectory in TRAJECTORIES:
            rows.append((trajectory.name, run_example(system, trajectory)))
            saved = system.call(SaveImage, '/turtlesim/save_image',
                                SaveImage.Request(filename=f'{trajectory.name}.png'))
            if not saved.success:
                raise RuntimeError(saved.message)
            pictures.append((trajectory.name, Path(saved.path)))
            plots.append(plotter.submit(write_overview, _run(system, trajectory),
                                        folder / f'{trajectory.name}-plot.png'))
        gallery(pictures, folder / 'gallery.png')
        simulated_s = system.sim_time_s - sim_start
        for plot in plots:
            plot.result()
    except (RuntimeError, KeyboardInterrupt) as error:
        print(f'demo stopped: {error or "interrupted"}', file=sys.stderr)
        return 1
    finally:
        plotter.shutdown(cancel_futures=True)
        if system is not None:
            system.close()
        rclpy.try_shutdown()

    print(f'{"trajectory":16} {"ok":>3} {"elapsed s":>10} {"path m":>8} {"max dev m":>10} '
          f'{"end err m":>10}  message')
    for name, response in rows:
        print(f'{name:16} {"yes" if response.success else "NO":>3} {response.elapsed:10.2f} '
              f'{response.path_length:8.2f} {response.max_deviation:10.4f} '
              f'{response.final_error:10.4f}  {response.message}')
    wall_s = time.monotonic() - wall_start
    print(f'pictures: {folder}/ (gallery.png, one PNG per trajectory and its -plot.png)')
    print(f'{simulated_s:.1f} s simulated in {wall_s:.1f} s of wall time: '
          f'{simulated_s / wall_s:.0f}x real time (lock-step)')
    return 0 if all(response.success for _, response in rows) else 1


if __name__ == '__main__':
    sys.exit(main())

"""`python -m turtle_traj.demo` (`make demo`): draw every trajectory, save pictures, print a table.

Runs the simulator and the trajectory node in this process on lock-step simulated time, so it
needs no display and no other program, and prints the same table on every run, however busy
the machine is. Pictures go to output/demo/ (one PNG per trajectory and
gallery.png).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import rclpy
from geometry_msgs.msg import Point
from PIL import Image, ImageDraw
from std_srvs.srv import Trigger
from turtle_traj_interfaces.srv import DrawShape, FollowPath, GoTo, Move, SaveImage
from turtlesim.srv import SetPen, TeleportAbsolute

from turtle_traj.system import InProcessSystem

# name, service type, service, request, where to start (x, y, theta)
DEMO = [
    ('square', DrawShape, 'draw_square', DrawShape.Request(size=3.0), (4.0, 4.0, 0.0)),
    ('triangle', DrawShape, 'draw_triangle', DrawShape.Request(size=4.0), (3.5, 3.5, 0.0)),
    ('hexagon', DrawShape, 'draw_hexagon', DrawShape.Request(size=2.0), (4.5, 2.5, 0.0)),
    ('heptagon', DrawShape, 'draw_polygon', DrawShape.Request(sides=7, size=2.0, clockwise=True),
     (4.5, 8.5, 0.0)),
    ('circle', DrawShape, 'draw_circle', DrawShape.Request(size=2.5, turns=1.0),
     (5.5, 3.0, 0.0)),
    ('spiral', DrawShape, 'draw_spiral', DrawShape.Request(size=0.3, growth=0.6, turns=6.0,
                                                           linear_speed=2.0), (5.5, 5.2, 0.0)),
    ('sine', DrawShape, 'draw_sine', DrawShape.Request(size=1.5, frequency=0.4, length=9.0),
     (1.0, 5.5, 0.0)),
    ('go_to', GoTo, 'go_to', GoTo.Request(x=9.5, y=9.0, use_theta=True, theta=math.pi),
     (1.5, 1.5, 0.0)),
    ('move_and_rotate', Move, 'move', Move.Request(distance=6.0), (2.5, 5.5, 0.0)),
    ('follow_path', FollowPath, 'follow_path', FollowPath.Request(
        points=[Point(x=x, y=y) for x, y in [(8.5, 2.5), (8.5, 8.5), (5.5, 5.5), (2.5, 8.5)]],
        closed=True), (2.5, 2.5, 0.0)),
]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog='python -m turtle_traj.demo', description=__doc__)
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
    rows, pictures = [], []
    system = None
    try:
        system = InProcessSystem(output_dir=folder)
        sim_start = system.sim_time_s
        for name, service_type, service, request, start in DEMO:
            prepare(system, *start)
            response = system.run(service_type, service, request)
            rows.append((service if name == 'move_and_rotate' else name, response))
            if name == 'move_and_rotate' and response.success:
                rows.append(('rotate', system.run(Move, 'rotate', Move.Request(angle=-math.pi))))
            saved = system.call(SaveImage, '/turtlesim/save_image',
                                SaveImage.Request(filename=f'{name}.png'))
            if not saved.success:
                raise RuntimeError(saved.message)
            pictures.append((name, Path(saved.path)))
        gallery(pictures, folder / 'gallery.png')
        simulated_s = system.sim_time_s - sim_start
    except (RuntimeError, KeyboardInterrupt) as error:
        print(f'demo stopped: {error or "interrupted"}', file=sys.stderr)
        return 1
    finally:
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
    print(f'pictures: {folder}/ (gallery.png and one PNG per trajectory)')
    print(f'{simulated_s:.1f} s simulated in {wall_s:.1f} s of wall time: '
          f'{simulated_s / wall_s:.0f}x real time (lock-step)')
    return 0 if all(response.success for _, response in rows) else 1


if __name__ == '__main__':
    sys.exit(main())

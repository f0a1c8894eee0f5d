"""Qt's pen widths: our simulator's colour sensor read across a line, as the real turtlesim's
was read for tests/data/turtlesim-pen-scan.json (measured on turtlesim 1.8.2; our simulator is
driven the way that file describes)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from geometry_msgs.msg import Twist
from std_srvs.srv import Empty
from turtlesim.msg import Color
from turtlesim.srv import SetPen, TeleportAbsolute

from turtle_traj.core.turtlesim_contract import WORLD_SIZE_M
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS

SCAN = Path(__file__).with_name('data') / 'turtlesim-pen-scan.json'
PIXEL_M = WORLD_SIZE_M / 500  # as the file measures it: 11.088889 / 500 m
RED = Color(r=255, g=0, b=0)


def _recorded() -> dict[str, str]:
    return json.loads(SCAN.read_text())['scan']


def _scan(turtle_sim, colours: list[Color], publisher, width: int, heading: float) -> str:
    turtle_sim.call(SetPen, '/turtle1/set_pen', SetPen.Request(off=1))
    turtle_sim.call(TeleportAbsolute, '/turtle1/teleport_absolute',
             TeleportAbsolute.Request(x=3.0, y=3.0, theta=heading))
    turtle_sim.call(Empty, '/clear')
    turtle_sim.call(
        SetPen, '/turtle1/set_pen', SetPen.Request(r=255, g=0, b=0, width=width, off=0)
    )
    turtle_sim.spin_sim_seconds(0.05)
    twist = Twist()
    twist.linear.x = 1.0
    publisher.publish(twist)
    turtle_sim.spin_sim_seconds(1.2)  # it acts for 63 steps, then the turtle stands
    turtle_sim.call(SetPen, '/turtle1/set_pen', SetPen.Request(off=1))
    middle_x, middle_y = 3.0 + 0.504 * math.cos(heading), 3.0 + 0.504 * math.sin(heading)
    read = ''
    for offset in range(-4, 5):  # positive: to the left of the heading
        x = middle_x - offset * PIXEL_M * math.sin(heading)
        y = middle_y + offset * PIXEL_M * math.cos(heading)
        turtle_sim.call(
            TeleportAbsolute,
            '/turtle1/teleport_absolute',
            TeleportAbsolute.Request(x=x, y=y, theta=heading),
        )
        turtle_sim.spin_sim_seconds(0.032)
        read += 'P' if colours[-1] == RED else '.'
    return read


def _scans_of_width(width: int) -> dict[str, str]:
    return {
        name: scan for name, scan in _recorded().items() if name.startswith(f'width {width}, ')
    }


@pytest.mark.parametrize('width', range(6))
def test_every_scan_of_the_real_turtlesim_agrees(turtle_sim, width):
    """One test per pen width, each across the file's headings (0, 0.5 and pi/2)."""
    recorded = _scans_of_width(width)
    assert len(recorded) == 3
    colours: list[Color] = []
    turtle_sim.client.create_subscription(
        Color, 'turtle1/color_sensor', colours.append, TURTLE_TOPIC_QOS
    )
    publisher = turtle_sim.client.create_publisher(Twist, 'turtle1/cmd_vel', TURTLE_TOPIC_QOS)
    assert turtle_sim.spin_until(lambda: colours and publisher.get_subscription_count() > 0)
    ours = {}
    for name in recorded:
        heading = float(name.split(', ')[1].split()[1])
        ours[name] = _scan(turtle_sim, colours, publisher, width, heading)
    assert ours == recorded

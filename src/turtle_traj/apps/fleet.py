"""`python -m turtle_traj.fleet`: the fleet coordinator alone, for turtles whose trajectory
nodes run elsewhere (other programs, another host, the real turtlesim's spawned turtles).
`up --turtles N` runs one beside its nodes already."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from rclpy.utilities import remove_ros_args

from turtle_traj.fleet.coordinator import FleetCoordinator
from turtle_traj.rosutils.runtime import run_nodes


def main(args: Sequence[str] | None = None) -> int:
    argv = list(sys.argv if args is None else ['turtle_traj.fleet', *args])
    argparse.ArgumentParser(
        prog='python -m turtle_traj.fleet',
        description='Run the fleet coordinator (/fleet): its action ~/draw '
                    '(turtle_traj_interfaces/action/FleetDraw) draws one request with several '
                    'turtles, each driven by its trajectory node /NAME/turtle_traj. ROS '
                    'arguments (--ros-args -p clearance:=0.8 -r __node:=fleet2) are passed '
                    'through.').parse_args(remove_ros_args(argv)[1:])
    return run_nodes(lambda _stop: [FleetCoordinator()], args=argv)

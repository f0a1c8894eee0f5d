"""`--web`: the live view, composed: one page server, the simulator's view on it (frames and
keys), and the trajectory panel (a client of the trajectory node beside the simulator, which
says so on the page while there is none). Loaded only when asked for."""

from __future__ import annotations

from typing import TYPE_CHECKING

from rclpy.node import Node

from turtle_traj.client.panel import TrajectoryPanel
from turtle_traj.sim.live_view import SimLiveView, turtle_icon_png
from turtle_traj.sim.node import SimNode
from turtle_traj.sim.options import SimOptions, SimUnavailable
from turtle_traj.web.server import WebServer

if TYPE_CHECKING:
    from turtle_traj.apps.base_view import BaseScene


def create_web(options: SimOptions, sim: SimNode | BaseScene) -> list[Node]:
    """Serve `sim` live on the host and port `options` give, and print the address; the view's
    nodes (the simulator's view first: destroying it stops the server).

    :raises SimUnavailable: the address cannot be listened on (taken, not this machine's).
    """
    server = WebServer(options.web_host, options.web_port, icon_png=turtle_icon_png)
    nodes = [SimLiveView(sim, server), TrajectoryPanel(server)]
    try:
        url = server.start()
    except OSError as error:
        for node in nodes:
            node.destroy_node()
        raise SimUnavailable(f'--web: cannot listen on {server.url}: '
                             f'{error.strerror or error}') from None
    print(f'live view: {url}', flush=True)
    return nodes

"""`--web`: the live view beside the simulator node (loaded only when asked for)."""

from __future__ import annotations

from turtle_traj.sim.node import SimNode
from turtle_traj.sim.options import SimOptions, SimUnavailable
from turtle_traj.web.bridge import WebBridge
from turtle_traj.web.server import WebServer


def create_web(options: SimOptions, sim: SimNode) -> WebBridge:
    """Serve `sim` live on the host and port `options` give, and print the address.

    :raises SimUnavailable: the address cannot be listened on (taken, not this machine's).
    """
    bridge: WebBridge | None = None
    server = WebServer(options.web_host, options.web_port,
                       on_request=lambda page, request: bridge.request(page, request))
    try:
        url = server.start()
    except OSError as error:
        raise SimUnavailable(f'--web: cannot listen on {server.url}: '
                             f'{error.strerror or error}') from None
    bridge = WebBridge(sim, server)
    print(f'live view: {url}', flush=True)
    return bridge

"""Who may use the live view: the hosts a request may name, and the origins a WebSocket may
come from. Plain Python over aiohttp's request."""

from __future__ import annotations

import ipaddress

from aiohttp import web

LOCAL_HOSTS = {'localhost', '127.0.0.1', '::1'}


def _is_ip(host: str) -> bool:
    try:
        ipaddress.ip_address(host.strip('[]'))
    except ValueError:
        return False
    return True


def host_refusal(request: web.Request, own_host: str) -> str | None:
    """Why a request may not be served: it names a host this server is not reached by (a page
    from another site that points its own name at this machine: DNS rebinding)."""
    host = request.url.host or ''
    if host not in LOCAL_HOSTS and host != own_host and not _is_ip(host):
        return f'host {host!r} refused'
    return None


def origin_refusal(request: web.Request) -> str | None:
    """Why a WebSocket may not open: a page of another origin (cross-site WebSocket
    hijacking). A client that is not a browser sends no Origin."""
    origin = request.headers.get('Origin')
    if origin is not None and origin != f'{request.scheme}://{request.host}':
        return f'origin {origin!r} refused: only this server\'s own page may connect'
    return None

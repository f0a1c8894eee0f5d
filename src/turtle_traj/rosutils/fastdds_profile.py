"""Our programs' Fast DDS profile (fastdds.xml), and the same profile kept to this machine.

`ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST` (what our tests set, and what users set to keep
ROS off their network) makes rmw_fastrtps replace the profile's transports with its own: shared
memory and a second UDP transport. Shared memory is what fastdds.xml leaves out on purpose (a
publish() waits on the health check of a port whose reader is busy). So where LOCALHOST is asked
for, our programs take a copy of fastdds.xml that keeps discovery to this machine by itself
(UDP on the loopback interface only, announcements to 127.0.0.1, no multicast) and tell
rmw_fastrtps to leave the transports alone (`SYSTEM_DEFAULT`): one transport everywhere.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import os
import tempfile
import xml.etree.ElementTree as ElementTree
from collections.abc import MutableMapping
from pathlib import Path

PROFILE = Path(__file__).with_name('fastdds.xml')
PROFILE_VARIABLES = ('FASTRTPS_DEFAULT_PROFILES_FILE', 'FASTDDS_DEFAULT_PROFILES_FILE')
RANGE_VARIABLE = 'ROS_AUTOMATIC_DISCOVERY_RANGE'
LOOPBACK = '127.0.0.1'
# Participants of one domain on this machine that find each other: rmw_fastrtps's own figure
# for LOCALHOST (each process is one participant; a test starts a handful).
MAX_PARTICIPANTS = 32
_NS = 'http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles'


def use_our_fastdds_profile(environ: MutableMapping[str, str] = os.environ) -> bool:
    """Point Fast DDS at fastdds.xml (quick re-announcement, quick repair of lost samples, UDP
    only) unless the user chose a profile file or another middleware; under LOCALHOST, at its
    copy kept to this machine. Call before rclpy.init; child processes inherit the choice.
    Returns whether it did."""
    middleware = environ.get('RMW_IMPLEMENTATION', 'rmw_fastrtps_cpp')
    if middleware != 'rmw_fastrtps_cpp' or any(environ.get(v) for v in PROFILE_VARIABLES):
        return False
    profile = PROFILE
    if environ.get(RANGE_VARIABLE) == 'LOCALHOST':
        profile = localhost_profile()
        environ[RANGE_VARIABLE] = 'SYSTEM_DEFAULT'  # rmw_fastrtps keeps the profile's transport
    environ['FASTRTPS_DEFAULT_PROFILES_FILE'] = str(profile)
    return True


def keep_to_this_machine(environ: MutableMapping[str, str] = os.environ) -> None:
    """Keep discovery to this machine for every later context and child process: our
    profile's localhost copy where our profile is taken, LOCALHOST where it is not. A process
    started by one that did this (a pytest worker) inherits the copy and keeps it."""
    if environ.get('FASTRTPS_DEFAULT_PROFILES_FILE') != str(localhost_profile()):
        environ[RANGE_VARIABLE] = 'LOCALHOST'
        use_our_fastdds_profile(environ)


def localhost_profile() -> Path:
    """fastdds.xml kept to this machine, written to the temporary directory once (named by its
    content: processes of one version share it, a new version never reads an old one). A file
    of that name saying anything else (another user's, in a shared /tmp) is not taken: this
    process then writes a copy of its own."""
    text = localhost_profile_text()
    digest = hashlib.sha256(text.encode()).hexdigest()[:12]
    path = Path(tempfile.gettempdir()) / f'turtle_traj_fastdds_localhost_{digest}.xml'
    with contextlib.suppress(OSError):
        if path.read_text() == text:
            return path
    with tempfile.NamedTemporaryFile('w', dir=path.parent, prefix=path.stem, suffix='.xml',
                                     delete=False) as draft:
        draft.write(text)
    try:
        os.replace(draft.name, path)  # atomic: a process starting meanwhile reads all or none
    except OSError:  # not ours to replace
        return Path(draft.name)
    return path


@functools.cache
def localhost_profile_text() -> str:
    """fastdds.xml with its UDP transport on the loopback interface, discovery announced to
    127.0.0.1 (the first MAX_PARTICIPANTS participants' ports) and no multicast locator."""
    ElementTree.register_namespace('', _NS)
    root = ElementTree.parse(PROFILE).getroot()
    for transport in root.iterfind('p:transport_descriptors/p:transport_descriptor',
                                   {'p': _NS}):
        _element(transport, 'maxInitialPeersRange').text = str(MAX_PARTICIPANTS)
        allowed = _element(transport, 'interfaceWhiteList')
        _element(allowed, 'address').text = LOOPBACK
    builtin = root.find('p:participant/p:rtps/p:builtin', {'p': _NS})
    peers = _element(builtin, 'initialPeersList')
    _element(_element(_element(peers, 'locator'), 'udpv4'), 'address').text = LOOPBACK
    # A unicast locator with neither address nor port: the participant's own well-known port
    # on each allowed interface, and (as it is given) no default multicast locator.
    _element(_element(builtin, 'metatrafficUnicastLocatorList'), 'locator').append(
        ElementTree.Element(f'{{{_NS}}}udpv4'))
    ElementTree.indent(root)
    return ElementTree.tostring(root, encoding='unicode', xml_declaration=True)


def _element(parent: ElementTree.Element, name: str) -> ElementTree.Element:
    return ElementTree.SubElement(parent, f'{{{_NS}}}{name}')


def across_hosts(environ: MutableMapping[str, str]) -> dict[str, str]:
    """A copy of `environ` for programs that discover each other across hosts: the subnet's
    range, and fastdds.xml itself where `environ` names its localhost copy."""
    copy = {**environ, RANGE_VARIABLE: 'SUBNET'}
    ours = str(localhost_profile())
    for variable in PROFILE_VARIABLES:
        if copy.get(variable) == ours:
            del copy[variable]
    return copy

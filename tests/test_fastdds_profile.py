"""Our programs' Fast DDS profile: taken only where the user chose nothing, and what it says;
under LOCALHOST, its copy kept to this machine, which every participant of the tests takes."""

import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest

from turtle_traj.rosutils.fastdds_profile import (
    PROFILE,
    across_hosts,
    keep_to_this_machine,
    localhost_profile,
    localhost_profile_text,
    use_our_fastdds_profile,
)

NS = {'p': 'http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles'}


def _transports(profile: ElementTree.Element) -> list[ElementTree.Element]:
    """The descriptors of the transports the default participant profile uses."""
    participant = profile.find('p:participant', NS)
    assert participant.get('is_default_profile') == 'true'
    assert participant.find('p:rtps/p:useBuiltinTransports', NS).text == 'false'
    chosen = [t.text for t in participant.findall('p:rtps/p:userTransports/p:transport_id', NS)]
    descriptors = {d.find('p:transport_id', NS).text: d
                   for d in profile.findall('p:transport_descriptors/p:transport_descriptor', NS)}
    return [descriptors[name] for name in chosen]


def test_the_profile_is_taken_where_the_user_chose_nothing():
    environ = {'RMW_IMPLEMENTATION': 'rmw_fastrtps_cpp'}
    assert use_our_fastdds_profile(environ)
    profile = ElementTree.parse(environ['FASTRTPS_DEFAULT_PROFILES_FILE']).getroot()
    participant = profile.find('p:participant', NS)
    period = participant.find('p:rtps/p:builtin/p:discovery_config/p:leaseAnnouncement', NS)
    seconds = int(period.find('p:sec', NS).text) + int(period.find('p:nanosec', NS).text) / 1e9
    assert seconds == 0.5  # below Fast DDS's 3 s default, far below the 20 s lease
    # UDP only: no shared-memory port whose health check stalls a publish() (see the profile)
    assert [t.find('p:type', NS).text for t in _transports(profile)] == ['UDPv4']


def test_localhost_takes_the_profiles_copy_kept_to_this_machine():
    environ = {'ROS_AUTOMATIC_DISCOVERY_RANGE': 'LOCALHOST'}
    assert use_our_fastdds_profile(environ)
    # rmw_fastrtps would replace the profile's transport with shared memory and UDP under
    # LOCALHOST; under SYSTEM_DEFAULT it keeps the profile's
    assert environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] == 'SYSTEM_DEFAULT'
    assert Path(environ['FASTRTPS_DEFAULT_PROFILES_FILE']) == localhost_profile()
    copy = ElementTree.parse(localhost_profile()).getroot()
    [udp] = _transports(copy)
    assert udp.find('p:type', NS).text == 'UDPv4'
    assert [a.text for a in udp.findall('p:interfaceWhiteList/p:address', NS)] == ['127.0.0.1']
    builtin = copy.find('p:participant/p:rtps/p:builtin', NS)
    peers = builtin.findall('p:initialPeersList/p:locator/p:udpv4/p:address', NS)
    assert [peer.text for peer in peers] == ['127.0.0.1']
    assert builtin.find('p:metatrafficUnicastLocatorList/p:locator', NS) is not None
    # everything else as fastdds.xml says
    original = ElementTree.parse(PROFILE).getroot()
    for path in ('p:data_writer', 'p:data_reader', 'p:participant/p:rtps/p:builtin/'
                 'p:discovery_config'):
        assert (ElementTree.tostring(copy.find(path, NS), 'unicode').split() ==
                ElementTree.tostring(original.find(path, NS), 'unicode').split())


def test_across_hosts_the_subnet_and_the_profile_itself():
    environ = {'ROS_AUTOMATIC_DISCOVERY_RANGE': 'LOCALHOST'}
    use_our_fastdds_profile(environ)
    assert across_hosts(environ) == {'ROS_AUTOMATIC_DISCOVERY_RANGE': 'SUBNET'}
    theirs = {'FASTRTPS_DEFAULT_PROFILES_FILE': '/theirs.xml'}
    assert across_hosts(theirs) == {**theirs, 'ROS_AUTOMATIC_DISCOVERY_RANGE': 'SUBNET'}


_SOCKETS = """
import os, rclpy
rclpy.init()
node = rclpy.create_node('probe')
links = []
for fd in os.listdir('/proc/self/fd'):
    try:
        links.append(os.readlink(f'/proc/self/fd/{fd}'))
    except OSError:  # the listing's own descriptor, closed by now
        pass
inodes = {link[len('socket:['):-1] for link in links if link.startswith('socket:[')}
for table in ('/proc/net/udp', '/proc/net/udp6'):
    for line in open(table).readlines()[1:]:
        fields = line.split()
        if fields[9] in inodes:
            print('socket', fields[1])
print('shm', sum('/dev/shm/fastrtps' in line for line in open('/proc/self/maps')))
"""


def test_a_participant_of_the_tests_listens_on_loopback_alone(ros_domain_id):
    """What the tests' environment (claim_domain_id) gives every participant: UDP sockets
    on 127.0.0.1 only, and no shared-memory transport."""
    probe = subprocess.run([sys.executable, '-c', _SOCKETS], capture_output=True, text=True,
                           timeout=60)
    assert probe.returncode == 0, probe.stderr
    said = [line.split() for line in probe.stdout.splitlines()]
    sockets = [address for word, address in said if word == 'socket']
    assert sockets and all(address.startswith('0100007F:') for address in sockets), probe.stdout
    assert said[-1] == ['shm', '0']


@pytest.mark.parametrize('chosen', [
    {'FASTRTPS_DEFAULT_PROFILES_FILE': '/theirs.xml'},
    {'FASTDDS_DEFAULT_PROFILES_FILE': '/theirs.xml'},
    {'RMW_IMPLEMENTATION': 'rmw_cyclonedds_cpp'},
    {'FASTRTPS_DEFAULT_PROFILES_FILE': '/theirs.xml',
     'ROS_AUTOMATIC_DISCOVERY_RANGE': 'LOCALHOST'},
])
def test_a_users_own_choice_is_left_alone(chosen):
    environ = dict(chosen)
    assert not use_our_fastdds_profile(environ)
    assert environ == chosen


def test_a_process_started_by_one_kept_to_this_machine_keeps_its_copy():
    """A pytest worker inherits its controller's environment, then claims a domain itself."""
    parent = {'ROS_AUTOMATIC_DISCOVERY_RANGE': 'SUBNET'}
    keep_to_this_machine(parent)
    child = dict(parent)
    keep_to_this_machine(child)
    assert child == parent == {'ROS_AUTOMATIC_DISCOVERY_RANGE': 'SYSTEM_DEFAULT',
                               'FASTRTPS_DEFAULT_PROFILES_FILE': str(localhost_profile())}
    theirs = {'FASTDDS_DEFAULT_PROFILES_FILE': '/theirs.xml'}
    keep_to_this_machine(theirs)  # their profile stays, kept to this machine by rmw_fastrtps
    assert theirs == {'FASTDDS_DEFAULT_PROFILES_FILE': '/theirs.xml',
                      'ROS_AUTOMATIC_DISCOVERY_RANGE': 'LOCALHOST'}


def test_a_file_in_the_copys_place_that_says_something_else_is_not_taken(tmp_path,
                                                                          monkeypatch):
    monkeypatch.setattr(tempfile, 'tempdir', str(tmp_path))
    ours = localhost_profile()
    assert ours.parent == tmp_path and ours.read_text() == localhost_profile_text()
    ours.write_text('<profiles/>')  # someone else's, or a torn write
    again = localhost_profile()
    assert again.read_text() == localhost_profile_text()
    ours.unlink()
    ours.mkdir()  # what cannot be read nor replaced: a copy of this process's own
    own = localhost_profile()
    assert own != ours and own.read_text() == localhost_profile_text()

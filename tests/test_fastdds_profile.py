"""Our programs' Fast DDS profile: taken only where the user chose nothing, and what it says."""

import xml.etree.ElementTree as ElementTree

import pytest

from turtle_traj.rosutils.runtime import use_our_fastdds_profile

NS = {'p': 'http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles'}


def test_the_profile_is_taken_where_the_user_chose_nothing():
    environ = {'RMW_IMPLEMENTATION': 'rmw_fastrtps_cpp'}
    assert use_our_fastdds_profile(environ)
    profile = ElementTree.parse(environ['FASTRTPS_DEFAULT_PROFILES_FILE']).getroot()
    participant = profile.find('p:participant', NS)
    assert participant.get('is_default_profile') == 'true'
    period = participant.find('p:rtps/p:builtin/p:discovery_config/p:leaseAnnouncement', NS)
    seconds = int(period.find('p:sec', NS).text) + int(period.find('p:nanosec', NS).text) / 1e9
    assert seconds == 0.5  # below Fast DDS's 3 s default, far below the 20 s lease
    # UDP only: no shared-memory port whose health check stalls a publish() (see the profile)
    assert participant.find('p:rtps/p:useBuiltinTransports', NS).text == 'false'
    chosen = [t.text for t in participant.findall('p:rtps/p:userTransports/p:transport_id', NS)]
    kinds = {d.find('p:transport_id', NS).text: d.find('p:type', NS).text
             for d in profile.findall('p:transport_descriptors/p:transport_descriptor', NS)}
    assert [kinds[name] for name in chosen] == ['UDPv4']


@pytest.mark.parametrize('chosen', [
    {'FASTRTPS_DEFAULT_PROFILES_FILE': '/theirs.xml'},
    {'FASTDDS_DEFAULT_PROFILES_FILE': '/theirs.xml'},
    {'RMW_IMPLEMENTATION': 'rmw_cyclonedds_cpp'},
])
def test_a_users_own_choice_is_left_alone(chosen):
    environ = dict(chosen)
    assert not use_our_fastdds_profile(environ)
    assert environ == chosen

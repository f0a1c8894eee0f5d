"""The live view's messages and its server's fan-out, without a browser or ROS."""

from __future__ import annotations

import asyncio
import base64
import json

import numpy as np
import pytest

from turtle_traj.client import panel_messages
from turtle_traj.core.registry import BY_NAME
from turtle_traj.core.teleop_keys import ARROW_BYTES, ROTATIONS, velocity
from turtle_traj.sim import live_messages
from turtle_traj.sim.canvas import Canvas
from turtle_traj.sim.state import Pen, Segment
from turtle_traj.web import frames, messages
from turtle_traj.web.frames import Frame
from turtle_traj.web.messages import ProtocolError

# The requests of a page with both parts: the simulator's view and the trajectory panel.
CHECKERS = {**live_messages.CHECKERS, **panel_messages.CHECKERS}


def _parse(raw: str) -> dict:
    return messages.parse(raw, CHECKERS)


@pytest.mark.parametrize(('raw', 'reason'), [
    ('not json', 'not JSON'),
    ('[1, 2]', 'JSON object'),
    ('{"type": "launch_missiles"}', "unknown message type 'launch_missiles'"),
    ('{"type": "key", "turtle": "turtle1", "key": "x"}', "unknown key 'x'"),
    ('{"type": "key", "turtle": "../etc", "key": "up"}', 'turtle must be a name'),
    ('{"type": "goto", "x": NaN, "y": 1}', 'x must be a finite number'),
    ('{"type": "goto", "x": true, "y": 1}', 'x must be a finite number'),
    ('{"type": "start", "trajectory": "teleport"}', "unknown trajectory 'teleport'"),
    ('{"type": "start", "trajectory": "square", "fields": {"sides": 4}}', 'square has no '
     "field 'sides'"),
    ('{"type": "start", "trajectory": "polygon", "fields": {"sides": 4.5}}', 'whole number'),
    ('{"type": "start", "trajectory": "follow_path", "fields": {"points": [[1, 2, 3]]}}',
     'a point must be [x, y]'),
    ('{"type": "start", "trajectory": "text", "fields": {"text": 7}}', 'text must be a text'),
    ('{"type": "set_param", "name": "linear_speed", "value": 2}', 'value must be a text'),
    ('{"type": "key", "key": "up", "turtle": "' + 'x' * 20_000 + '"}', 'characters refused'),
    ('[' * 100_000 + ']' * 100_000, 'refused'),
])
def test_every_bad_request_is_refused_with_the_reason(raw, reason):
    with pytest.raises(ProtocolError, match=None) as refused:
        _parse(raw)
    assert reason in str(refused.value)


def test_good_requests_come_out_typed():
    assert _parse('{"type": "key", "turtle": "turtle2", "key": "left"}') == {
        'type': 'key', 'turtle': 'turtle2', 'key': 'left'}
    start = _parse(json.dumps({
        'type': 'start', 'trajectory': 'follow_path',
        'fields': {'points': [[1, 2], [3.5, 4]], 'closed': True, 'linear_speed': 1}}))
    assert start['fields'] == {'points': [(1.0, 2.0), (3.5, 4.0)], 'closed': True,
                               'linear_speed': 1.0}
    assert _parse('{"type": "start", "trajectory": "polygon", "fields": '
                          '{"sides": 6.0}}')['fields'] == {'sides': 6}


def test_the_teleop_mapping_is_turtlesims():
    """As turtlesim's turtle_teleop_key (shared turtlesim reference, section 6)."""
    assert [velocity(ARROW_BYTES[byte]) for byte in 'ABDC'] == [
        (2.0, 0.0), (-2.0, 0.0), (0.0, 2.0), (0.0, -2.0)]
    assert ROTATIONS == {'g': 0.0, 't': 0.7854, 'r': 1.5708, 'e': 2.3562, 'd': 3.1416,
                         'c': -2.3562, 'v': -1.5708, 'b': -0.7854}


def test_the_hello_lists_every_kind_with_its_fields_defaults_and_ranges():
    hello = panel_messages.hello()
    kinds = {kind['name']: kind for kind in hello['kinds']}
    assert set(kinds) == set(BY_NAME)
    polygon = {field['name']: field for field in kinds['polygon']['fields']}
    sides = BY_NAME['polygon'].fields[0]
    assert polygon['sides'] == {**polygon['sides'], 'default': sides.default,
                                'low': sides.low, 'high': sides.high, 'type': 'int'}
    assert polygon['size']['parameter'] == 'default_side_length'


def test_a_frame_carries_the_changed_pixels_exactly():
    """A page that starts from a snapshot and applies every frame's patches holds the
    simulator's trail layer, pixel for pixel."""
    canvas = Canvas()
    canvas.draw(Segment((1.0, 1.0), (3.0, 2.0), Pen(255, 0, 0, 5)))
    canvas.take_changes()  # as the bridge does each step: from here on, changes are kept
    snapshot = Frame(1, 0.0, 0.0, (0, 0, 0), [], snapshot=canvas.trails.copy())
    page = _decode(json.loads(frames.snapshot_text(snapshot)))
    for step, segment in enumerate([Segment((3.0, 2.0), (3.2, 2.4), Pen(0, 255, 0, 3)),
                                    Segment((5.0, 5.0), (5.0, 5.0), Pen(9, 9, 9, 1)),
                                    Segment((-1.0, 5.0), (0.1, 5.0), Pen(1, 2, 3, 40))]):
        canvas.draw(segment)
        cleared, patches = canvas.take_changes()
        frame = json.loads(frames.frame_text(Frame(step + 2, 0.0, 0.0, (0, 0, 0), [],
                                                     cleared, patches)))
        for row, column, height, width, data in frame['patches']:
            pixels = np.frombuffer(base64.b64decode(data), np.uint8).reshape(height, width, 4)
            page[row:row + height, column:column + width] = pixels
    assert np.array_equal(page, canvas.trails)
    canvas.clear()
    assert canvas.take_changes() == (True, [])


def _decode(snapshot: dict) -> np.ndarray:
    return np.frombuffer(base64.b64decode(snapshot['pixels']), np.uint8).reshape(
        snapshot['height'], snapshot['width'], 4).copy()


class _Socket:
    closed = False


def test_a_page_that_falls_behind_loses_frames_then_gets_the_whole_canvas():
    from turtle_traj.web.pages import FRAME_QUEUE, Page
    from turtle_traj.web.server import WebServer

    async def scenario() -> tuple[list[str], int, bool]:
        server = WebServer('127.0.0.1', 0, icon_png=bytes)
        page = Page(1, _Socket())
        server._pages[1] = page
        frames = [Frame(seq, 0.0, 0.0, (1, 2, 3), [('turtle1', 1.0, 2.0, 0.0)])
                  for seq in range(1, FRAME_QUEUE + 3)]
        frames[0].snapshot = np.zeros((2, 2, 4), np.uint8)
        server._backlog = frames  # nobody takes them off the queue: the page is stalled
        server._fan_out()
        dropped, wanted = server.frames_dropped, server.snapshot_wanted
        sent = [json.loads(page.frames.get_nowait())['type'] for _ in range(page.frames.qsize())]
        server._backlog = [Frame(99, 0.0, 0.0, (1, 2, 3), [], snapshot=frames[0].snapshot)]
        server._fan_out()  # the next snapshot brings it back
        return sent, dropped, wanted and json.loads(page.frames.get_nowait())['seq'] == 99

    sent, dropped, resynced = asyncio.run(scenario())
    assert sent == ['snapshot'] + ['frame'] * (FRAME_QUEUE - 1)
    assert dropped == 2 and resynced

"""The live view in a real browser (headless chromium), against the real programs.

`python -m turtle_traj --with-sim --web` at real time, a page in chromium, and a ROS observer
in this process that sees what the page's keys and buttons did on the wire.
"""

from __future__ import annotations

import asyncio
import http.client
import json
import math
import tempfile
import time
from pathlib import Path

import aiohttp
import numpy as np
import pytest
from PIL import Image

from turtle_traj.client.traj_client import TrajClient
from turtle_traj.core.turtlesim_contract import PIXELS_PER_METER, WORLD_SIZE_M
from turtle_traj.testing.browser import chromium, free_port, page_canvas, wait_for
from turtle_traj.testing.processes import program

pytestmark = pytest.mark.system  # a browser and programs: `make check` leaves it out

SPRITE_RADIUS_PX = 33  # a 45 px turtle, turned any way


@pytest.fixture(scope='module')
def live(tmp_path_factory):
    """The programs with the live view, and the page's address."""
    port = free_port()
    folder = tmp_path_factory.mktemp('web')
    with program('turtle_traj', '--with-sim', '--web', '--web-port', str(port),
                 cwd=folder) as process:
        with TrajClient(connect_timeout_s=30.0) as client:
            assert client.call('reset').success, process.said()
        yield f'http://127.0.0.1:{port}/', folder


@pytest.fixture(scope='module')
def page(live):
    with chromium() as driver:
        driver.get(live[0])
        wait_for(lambda: driver.execute_script('return window.turtleTraj.stats().received') > 0,
                 what='frames on the page')
        yield driver


@pytest.fixture
def observer(rclpy_context):
    """A node of this test that records turtle1's poses."""
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from turtlesim.msg import Pose

    from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS

    node = Node('web_observer', context=rclpy_context)
    executor = SingleThreadedExecutor(context=rclpy_context)
    executor.add_node(node)
    node.poses = []
    node.create_subscription(Pose, 'turtle1/pose', node.poses.append, TURTLE_TOPIC_QOS)

    def spin_until(condition, timeout_s: float = 20.0) -> bool:
        from turtle_traj.rosutils.runtime import spin_until as spin
        return spin(executor, condition, timeout_s=timeout_s)
    node.spin_until = spin_until
    assert spin_until(lambda: bool(node.poses))
    yield node
    executor.shutdown()
    node.destroy_node()


def _reset() -> None:
    with TrajClient(connect_timeout_s=30.0) as client:
        assert client.call('reset').success


def _text(driver, element: str) -> str:
    return driver.find_element('id', element).text


def _press(driver, *keys: str) -> None:
    from selenium.webdriver.common.action_chains import ActionChains
    ActionChains(driver).send_keys(*keys).perform()


def test_the_page_shows_the_canvas_and_the_turtle(page):
    stats = page.execute_script('return window.turtleTraj.stats()')
    assert [turtle[0] for turtle in stats['turtles']] == ['turtle1']
    name, x, y, _ = stats['turtles'][0]
    # the sprite layer shows the turtle where it stands
    alpha = page.execute_script(
        'return document.getElementById("sprites").getContext("2d")'
        '.getImageData(arguments[0], arguments[1], 1, 1).data[3]',
        round(x * PIXELS_PER_METER), round((WORLD_SIZE_M - y) * PIXELS_PER_METER))
    assert alpha == 255
    assert _text(page, 'connection') == 'live'


def test_after_a_square_the_page_shows_save_images_pixels(live, page):
    from turtle_traj_interfaces.srv import DrawShape
    _reset()
    with TrajClient(connect_timeout_s=30.0) as client:
        assert client.call('draw_square', DrawShape.Request(size=1.0), timeout_s=60.0).success
        saved = client.save_canvas('square.png')
        assert saved.success, saved.message
    time.sleep(0.5)  # the page has the last frames (the turtle stands: nothing changes)
    expected = np.asarray(Image.open(saved.path).convert('RGB'))
    shown = page_canvas(page)
    far = np.ones(shown.shape[:2], bool)  # away from every turtle sprite
    rows, columns = np.mgrid[:shown.shape[0], :shown.shape[1]]
    for _, x, y, _ in page.execute_script('return window.turtleTraj.stats().turtles'):
        px, py = x * PIXELS_PER_METER, (WORLD_SIZE_M - y) * PIXELS_PER_METER
        far &= np.hypot(columns - px, rows - py) > SPRITE_RADIUS_PX
    assert np.array_equal(shown[far], expected[far])
    trail = np.all(shown[far] == (179, 184, 255), axis=1).sum()
    assert trail > 4 * 1.0 * PIXELS_PER_METER  # the square's four sides are there


def test_arrow_keys_drive_as_turtle_teleop_key(page, observer):
    from selenium.webdriver.common.keys import Keys
    _reset()
    page.execute_script('document.getElementById("view").focus()')  # (a click drives there)
    count = len(observer.poses)
    _press(page, Keys.ARROW_UP)
    assert observer.spin_until(lambda: any(p.linear_velocity == 2.0
                                           for p in observer.poses[count:]))
    count = len(observer.poses)
    _press(page, Keys.ARROW_LEFT)
    assert observer.spin_until(lambda: any(p.angular_velocity == 2.0
                                           for p in observer.poses[count:]))
    observer.spin_until(lambda: False, timeout_s=1.2)  # the last command times out
    _press(page, 'r')  # rotate_absolute to 1.5708
    assert observer.spin_until(lambda: abs(observer.poses[-1].theta - 1.5708) < 0.03
                               and observer.poses[-1].angular_velocity == 0.0)


def test_a_click_drives_the_turtle_there(page, observer):
    from selenium.webdriver.common.action_chains import ActionChains
    _reset()
    view = page.find_element('id', 'view')
    # 100 px right and 80 px up of the centre: (x, y) in metres
    target = (5.544 + 100 / PIXELS_PER_METER, 5.544 + 80 / PIXELS_PER_METER)
    ActionChains(page).move_to_element_with_offset(view, 100, -80).click().perform()
    assert observer.spin_until(lambda: math.dist(
        (observer.poses[-1].x, observer.poses[-1].y), target) < 0.05
        and observer.poses[-1].linear_velocity == 0.0, timeout_s=30.0)


def _start(page, kind: str, **values: object) -> None:
    from selenium.webdriver.support.select import Select
    Select(page.find_element('id', 'kind')).select_by_value(kind)
    for name, value in values.items():
        field = page.find_element('css selector', f'#fields input[name={name}]')
        if isinstance(value, bool):
            if field.is_selected() != value:
                field.click()
        else:
            field.clear()
            field.send_keys(str(value))
    page.find_element('id', 'start').click()


def test_a_trajectory_from_the_panel_runs_with_progress_and_its_figures(page):
    _reset()
    wait_for(lambda: page.find_element('id', 'start').is_enabled(), what='Start enabled')
    _start(page, 'move', distance=2.0)
    progress = []

    def ended() -> bool:
        progress.append(float(page.find_element('id', 'progress').get_attribute('value')))
        return 'move: done' in _text(page, 'run')
    wait_for(ended, timeout_s=30.0, what='the move to end')
    assert any(0.0 < value < 1.0 for value in progress), progress
    figures = dict(row.text.split(' ', 1) for row in
                   page.find_elements('css selector', '#result tr'))
    assert float(figures['path_length']) == pytest.approx(2.0)
    assert figures['success'] == 'true' and figures['ending'] == 'succeeded'


def test_cancel_stops_an_endless_circle(page, observer):
    _reset()
    wait_for(lambda: page.find_element('id', 'start').is_enabled(), what='Start enabled')
    _start(page, 'circle', size=1.0, forever=True)
    wait_for(lambda: 'running' in _text(page, 'run'), what='the circle to run')
    assert observer.spin_until(lambda: observer.poses[-1].linear_velocity > 0.5)
    page.find_element('id', 'cancel').click()
    wait_for(lambda: 'stopped by request' in _text(page, 'run'), what='the cancel')
    assert observer.spin_until(lambda: observer.poses[-1].linear_velocity == 0.0)


def test_parameters_are_listed_and_a_refusal_shows_the_nodes_message(page):
    def set_to(value: str) -> str:
        field = page.find_element('css selector', '#params input[name=linear_speed]')
        field.clear()
        field.send_keys(value)
        before = _text(page, 'param-message')
        page.find_element('xpath', '//table[@id="params"]//input[@name="linear_speed"]'
                                   '/../../td[3]/button').click()
        return wait_for(lambda: (_text(page, 'param-message') != before
                                 and _text(page, 'param-message')), what='an answer')

    page.find_element('id', 'reload').click()
    wait_for(lambda: page.find_elements('css selector', '#params input[name=linear_speed]'),
             what='the parameters')
    assert "expects a number, got 'fast'" in set_to('fast')
    assert 'linear_speed' in set_to('1e6')  # the node's own range refusal
    assert set_to('1.5') == 'linear_speed set to 1.5'
    wait_for(lambda: page.find_element('css selector', '#params input[name=linear_speed]')
             .get_attribute('value') == '1.5', what='the new value listed')
    set_to('1.0')


async def _websocket(url: str, **headers: str):
    session = aiohttp.ClientSession()
    try:
        return session, await session.ws_connect(url.replace('http', 'ws') + 'ws',
                                                 headers=headers)
    except Exception:
        await session.close()
        raise


async def _hangs_up(socket, within_s: float = 10.0) -> bool:
    """Whether the server closes the stream within `within_s`. What it sent before it read our
    last message (a frame a second, an answer) may still come first; nothing else may."""
    deadline = time.monotonic() + within_s
    while (left := deadline - time.monotonic()) > 0:
        message = await socket.receive(timeout=left)
        if message.type in (aiohttp.WSMsgType.CLOSE, aiohttp.WSMsgType.CLOSED):
            return True
        if message.type != aiohttp.WSMsgType.TEXT:
            return False
    return False


def test_a_page_of_another_site_cannot_connect(live):
    async def scenario() -> list[int]:
        statuses = []
        host = live[0].split('/')[2]
        for headers in ({'Origin': 'http://evil.example'},
                        {'Origin': f'http://{host}.evil.example'},
                        {'Host': 'evil.example', 'Origin': 'http://evil.example'}):
            try:
                session, socket = await _websocket(live[0], **headers)
            except aiohttp.WSServerHandshakeError as refused:
                statuses.append(refused.status)
            else:
                await socket.close()
                await session.close()
                statuses.append(101)
        session, socket = await _websocket(live[0], Origin=f'http://{host}')  # its own page
        await socket.close()
        await session.close()
        return statuses
    assert asyncio.run(scenario()) == [403, 403, 403]


@pytest.mark.parametrize('path', ['/static/../server.py', '/static/%2e%2e/server.py',
                                  '/static/..%2fserver.py', '/static/../../../../etc/passwd',
                                  '/static/%2e%2e/%2e%2e/web/server.py', '/server.py',
                                  '/static/', '/static/.'])
def test_only_the_bundled_files_are_served(live, path):
    host, port = live[0].split('/')[2].split(':')
    connection = http.client.HTTPConnection(host, int(port), timeout=10)
    connection.request('GET', path)
    response = connection.getresponse()
    body = response.read()
    assert response.status in (403, 404), (path, response.status)
    assert b'import' not in body and b'root:' not in body
    connection.request('GET', '/static/app.js')
    assert connection.getresponse().status == 200


def test_bad_messages_get_an_error_and_the_stream_goes_on(live):
    async def scenario() -> tuple[list[str], int, bool]:
        session, socket = await _websocket(live[0])
        errors = []
        for raw in ('not json', '{"type": "warp"}', '{"type": "key", "turtle": "turtle9", '
                    '"key": "up"}', 'x' * 20_000):
            await socket.send_str(raw)
        await socket.send_bytes(b'\x00\x01')
        frames = 0
        deadline = time.monotonic() + 20.0
        while (len(errors) < 5 or frames < 2) and time.monotonic() < deadline:
            message = json.loads((await socket.receive(timeout=10)).data)
            errors += [message['message']] if message['type'] == 'error' else []
            frames += message['type'] == 'frame'
        await socket.send_str('y' * 200_000)  # beyond what the server reads: it hangs up
        closed = await _hangs_up(socket)
        await session.close()
        session, socket = await _websocket(live[0])  # and serves the next page as before
        assert json.loads((await socket.receive(timeout=10)).data)['type'] == 'hello'
        await session.close()
        return errors, frames, closed

    errors, frames, closed = asyncio.run(scenario())
    # (the turtle's name is checked on the ROS side: that answer may come last)
    assert sorted(error.split(' ')[0] for error in errors) == [
        'binary', 'message', 'no', 'not', 'unknown']
    assert "no turtle 'turtle9'; there are: turtle1" in errors
    assert "unknown message type 'warp'" in errors
    assert any(error.startswith('message of 20000 characters refused') for error in errors)
    assert frames >= 2 and closed  # (a standing turtle: a frame a second)


def _answers(observer, client, requests: list) -> list:
    """Each request's answer, eight in flight at a time: a service's queues keep the last ten
    (all 99 at once lost some)."""
    answers = []
    for first in range(0, len(requests), 8):
        calls = [client.call_async(request) for request in requests[first:first + 8]]
        assert observer.spin_until(lambda calls=calls: all(call.done() for call in calls))
        answers += [call.result() for call in calls]
    return answers


def test_a_hundred_turtles_are_shown(page, observer):
    from turtlesim.srv import Kill, Spawn
    _reset()
    spawn = observer.create_client(Spawn, 'spawn')
    kill = observer.create_client(Kill, 'kill')
    # (a request sent before the service is discovered would be lost)
    assert observer.spin_until(lambda: spawn.service_is_ready() and kill.service_is_ready())
    names = [answer.name for answer in _answers(observer, spawn, [
        Spawn.Request(x=0.5 + (index % 10), y=0.5 + (index // 10), theta=0.1 * index)
        for index in range(99)])]
    assert len(set(names)) == 99
    wait_for(lambda: len(page.execute_script('return window.turtleTraj.stats().turtles'))
             == 100, what='100 turtles on the page')
    before = page.execute_script('return window.turtleTraj.stats().received')
    wait_for(lambda: page.execute_script('return window.turtleTraj.stats().received')
             > before + 2, what='frames still arriving')
    _answers(observer, kill, [Kill.Request(name=name) for name in names])
    wait_for(lambda: len(page.execute_script('return window.turtleTraj.stats().turtles'))
             == 1, what='the 99 gone from the page')


def test_without_a_trajectory_node_the_page_says_why_and_the_keys_still_work(tmp_path,
                                                                             observer_alone):
    from selenium.webdriver.common.keys import Keys
    url, observer = observer_alone
    left_before = _chromium_leftovers()
    with chromium() as driver:
        driver.get(url)
        wait_for(lambda: 'no trajectory node answers' in _text(driver, 'status'),
                 what='the reason on the page')
        driver.execute_script('document.getElementById("view").focus()')
        count = len(observer.poses)
        _press(driver, Keys.ARROW_DOWN)
        assert observer.spin_until(lambda: any(p.linear_velocity == 2.0
                                               for p in observer.poses[count:]))
        assert not driver.find_element('id', 'start').is_enabled()
        driver.find_element('id', 'view').click()  # a go-to: the page says why not
        wait_for(lambda: 'no trajectory node answers' in _text(driver, 'error'),
                 what='the reason for the refused click')
    # and the browser, closed, left nothing in the temporary folder
    assert _chromium_leftovers() <= left_before


def _chromium_leftovers() -> set[str]:
    """What chromium leaves in the temporary folder when it runs there (a process singleton's
    folder per browser)."""
    return {path.name for path in Path(tempfile.gettempdir()).glob('org.chromium.Chromium.*')}


@pytest.fixture
def observer_alone(tmp_path, rclpy_context):
    """Our simulator alone with its live view, in a namespace of its own (apart from the
    system of the other tests); its observer."""
    port = free_port()
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from turtlesim.msg import Pose

    from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
    from turtle_traj.rosutils.runtime import spin_until
    with program('turtle_traj.sim', '--web', '--web-port', str(port), '--ros-args', '-r',
                 '__ns:=/alone', cwd=tmp_path):
        node = Node('alone_observer', context=rclpy_context)
        executor = SingleThreadedExecutor(context=rclpy_context)
        executor.add_node(node)
        node.poses = []
        node.create_subscription(Pose, '/alone/turtle1/pose', node.poses.append,
                                 TURTLE_TOPIC_QOS)
        node.spin_until = lambda condition, timeout_s=20.0: spin_until(
            executor, condition, timeout_s=timeout_s)
        assert node.spin_until(lambda: bool(node.poses))
        try:
            yield f'http://127.0.0.1:{port}/', node
        finally:
            executor.shutdown()
            node.destroy_node()



def test_a_flood_of_requests_is_cut_short_and_told_once(live):
    async def scenario() -> list[str]:
        session, socket = await _websocket(live[0])
        for _ in range(400):  # each answered on the ROS side: no such turtle
            await socket.send_str('{"type": "key", "turtle": "turtle9", "key": "up"}')
        errors = []
        deadline = time.monotonic() + 3.0
        while time.monotonic() < deadline:
            try:
                message = json.loads((await socket.receive(timeout=1.0)).data)
            except asyncio.TimeoutError:
                continue
            errors += [message['message']] if message['type'] == 'error' else []
        await session.close()
        return errors

    errors = asyncio.run(scenario())
    told = [error for error in errors if error.startswith('too many requests')]
    handled = [error for error in errors if error.startswith("no turtle 'turtle9'")]
    assert len(told) == 1
    assert 45 <= len(handled) <= 100  # the allowance (50), and what it refilled meanwhile

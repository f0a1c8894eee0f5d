"""Drawings without ROS: curves, text, SVG, stroke order, pen-up moves and every refusal."""

import itertools
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import svgelements
from hypothesis import given, settings
from hypothesis import strategies as st

from turtle_traj.core.control.controllers.catalogue import ControllerChoice
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.geometry import drawing, svg, text
from turtle_traj.core.geometry.path import Polyline, Pose2D, Turn
from turtle_traj.core.geometry.shapes import ShapeError
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.planning.planner import PlanError
from turtle_traj.core.registry import BY_NAME
from turtle_traj.testing.geometry import distance_to_polyline, drawn_strokes

START = Pose2D(1.0, 5.0, 0.0)


def request(name: str, **given) -> SimpleNamespace:
    return SimpleNamespace(**BY_NAME[name].request_values(given))


def plan(name: str, start: Pose2D = START, **given):
    return planning.plan(name, request(name, **given), start, DEFAULT_SETTINGS)


@pytest.mark.parametrize(('name', 'given', 'reason'), [
    ('text', {'text': 'Grüße ☺'}, "no glyph for 'ß', 'ü', '☺'"),
    ('text', {'text': '   '}, 'the text is empty'),
    ('text', {'text': ''}, 'the text is empty'),
    ('text', {'text': 'Hi', 'height': math.nan}, 'height must be a finite number'),
    ('text', {'text': 'Hi', 'height': -1.0}, 'height must be at least'),
    ('text', {'text': 'Hello ROS', 'height': 3.0},
     'the largest that fits from here is 1.36 m (height)'),
    ('text', {'text': 'Hi', 'height': 1e308}, 'the largest that fits from here is'),
    ('text', {'text': 'Hi', 'pen_color': 'blurple'}, "pen_color 'blurple' is not a colour"),
    ('text', {'text': 'x' * 201}, 'the text has 201 characters; at most 200'),
    ('svg', {}, 'give path_data or a file'),
    ('svg', {'file': 'turtle.svg', 'path_data': 'M 0 0 L 1 1'}, 'not both'),
    ('svg', {'path_data': 'M 0 0 L 1 x'}, "unexpected 'x' at character 11"),
    ('svg', {'path_data': 'L 3 3'}, "must start with a moveto (M or m), not 'L'"),
    ('svg', {'path_data': 'M 0 0 C 1 1 2 2'}, 'the C command at character 7 takes 6 numbers'),
    ('svg', {'path_data': 'M 0 0 Z 4'}, 'the Z command at character 7 takes no numbers'),
    ('svg', {'path_data': 'M 1 1 L 1 1'}, 'has no extent'),
    ('svg', {'path_data': 'M 0 0 L 1e400 1'}, 'the number 1e400 at character 9 is not finite'),
    ('svg', {'path_data': 'M 0 0' + ' L 1 1' * 40_000}, 'at most 200000'),
    ('svg', {'path_data': 'M 0,0 l 1,1 ,, q'}, 'the q command at character 16 takes 4 numbers'),
    ('svg', {'file': '../drawings/../../x.svg'}, 'outside the SVG folder'),
    ('svg', {'file': '/etc/passwd'}, 'must be relative to the SVG folder'),
    ('svg', {'file': 'nope.svg'}, 'there are: turtle.svg, wave.svg'),
    ('svg', {'file': 'wave.svg', 'size': math.inf}, 'size must be a finite number'),
    ('svg', {'file': 'wave.svg', 'size': 20.0}, 'the largest that fits from here is'),
    ('svg', {'path_data': ' '.join(f'M {i} 0 v 1' for i in range(501)), 'size': 3.0},
     'has 501 strokes; at most 500'),
    ('star', {'size': 1.0, 'inner_radius': 1.5}, 'must be smaller than the outer radius'),
    ('star', {'tips': 2}, 'tips must be 3 to 100'),
    ('rose', {'petals': 6}, 'no rose r = sin(k t) has 6 petals'),
    ('lissajous', {'phase': math.nan}, 'phase must be a finite number'),
    ('heart', {'size': 12.0}, 'the largest that fits from here is'),
    ('heart', {'size': math.nan}, 'size must be a finite number'),
    ('rose', {'size': -2.0}, 'size must be at least'),
])
def test_bad_drawings_are_refused_with_the_reason(name, given, reason):
    with pytest.raises(PlanError) as refusal:
        plan(name, **given)
    assert reason in str(refusal.value)


def test_a_malformed_svg_file_is_refused(tmp_path):
    (tmp_path / 'broken.svg').write_text('<svg><path d="M 0 0 L')
    (tmp_path / 'words.svg').write_text('<svg xmlns="http://www.w3.org/2000/svg"><text>hi'
                                        '</text></svg>')
    with pytest.raises(ShapeError, match='broken.svg is not a readable SVG document'):
        svg.parse_file(tmp_path, 'broken.svg')
    with pytest.raises(ShapeError, match='words.svg has no shapes to draw'):
        svg.parse_file(tmp_path, 'words.svg')


@pytest.mark.parametrize('name', ['star', 'heart', 'lemniscate', 'rose', 'lissajous', 'text',
                                  'svg'])
def test_every_drawing_example_starts_at_the_turtle_and_stays_in_the_arena(name):
    example = BY_NAME[name].example
    path = plan(name, Pose2D(*example.start), **example.given).path
    points = path.points()
    assert np.allclose(points[0], example.start[:2])
    assert DEFAULT_SETTINGS.arena.contains(points[1:])


# The heart spans y from -17 to 11.76 for x within 16; a rose of five petals is 2 cos 18 deg
# wide and 1 + cos 36 deg high (radius 1).
@pytest.mark.parametrize(('name', 'width', 'height'), [
    ('heart', 3.0, 3.0 * 28.76 / 32), ('lemniscate', 3.0, 1.06),
    ('rose', 3.0 * math.cos(math.radians(18)), 1.5 * (1 + math.cos(math.radians(36)))),
    ('lissajous', 3.0, 3.0), ('star', 2 * 1.5 * math.sin(math.radians(72)), 1.5 * 1.809)])
def test_curves_have_the_size_asked_for(name, width, height):
    path = plan(name, Pose2D(5.5, 5.5, 0.0), size=1.5 if name == 'star' else 3.0).path
    extent = np.ptp(path.points(), axis=0)
    assert extent == pytest.approx((width, height), abs=0.02)
    assert path.pen_up_length == 0.0


def test_a_curve_turned_with_the_turtle_keeps_its_shape():
    upright = plan('heart', Pose2D(5.5, 3.0, 0.0), size=3.0).path.points() - (5.5, 3.0)
    turned = plan('heart', Pose2D(5.5, 3.0, math.pi / 2), size=3.0).path.points() - (5.5, 3.0)
    assert np.allclose(turned, upright @ np.array([[0.0, 1.0], [-1.0, 0.0]]), atol=1e-9)


def test_text_is_written_along_the_heading_with_capitals_of_the_height():
    strokes = text.text_strokes('HI', 2.0)
    every = np.concatenate(strokes)
    assert every[:, 1].min() == pytest.approx(0.0) and every[:, 1].max() == pytest.approx(2.0)
    vertical = [s for s in strokes if np.allclose(s[:, 0], s[0, 0])]
    assert len(vertical) == 3  # H's two legs and the I
    path = plan('text', Pose2D(4.0, 2.0, math.pi / 2), text='HI', height=2.0).path
    drawn = np.concatenate(drawn_strokes(path))
    # written upwards: the baseline runs up x = 4, capitals reach x = 2
    assert (drawn[:, 0].min(), drawn[:, 0].max()) == pytest.approx((2.0, 4.0), abs=1e-9)
    assert drawn[:, 1].min() > 2.0


def test_wave_svg_is_sampled_within_half_a_millimetre_of_the_true_curve():
    size = 6.0
    parsed = svg.parse_file(Path(DEFAULT_SETTINGS.svg_dir), 'wave.svg')
    x_min, y_min, x_max, y_max = svg.bounding_box(parsed)
    scale = size / max(x_max - x_min, y_max - y_min)
    stroke = svg.path_strokes(parsed, 0.0005 / scale, 0.02 / scale)[0] * scale
    truth = []
    for segment in parsed:
        if not isinstance(segment, svgelements.Move):
            truth.append(np.asarray(segment.npoint(np.linspace(0, 1, 1001))) * (1, -1) * scale)
    error = distance_to_polyline(np.concatenate(truth), stroke)
    assert error.max() < 0.0005


def test_pen_up_moves_join_the_strokes_and_the_strokes_are_drawn_exactly():
    strokes = [np.array([(2.0, 2.0), (3.0, 2.0)]), np.array([(3.0, 3.0), (2.0, 3.5)])]
    path = drawing.drawing_path(Pose2D(1.0, 1.0, 0.0), strokes, corner_angle_rad=0.1)
    curves = [leg for leg in path.legs if isinstance(leg, Polyline)]
    assert [leg.pen for leg in curves] == [False, True, False, True]
    assert path.pen_up_length == pytest.approx(math.sqrt(2) + 1.0)
    for drawn, stroke in zip(drawn_strokes(path), strokes, strict=True):
        assert np.allclose(drawn, stroke)
    # every curve starts along its first segment: a turn in place comes first
    heading = 0.0
    for leg in path.legs:
        if isinstance(leg, Turn):
            heading = leg.start_heading + leg.sweep_rad
        else:
            assert math.remainder(leg.headings[0] - heading, 2 * math.pi) == pytest.approx(0)
            heading = leg.headings[-1]


strokes_lists = st.lists(st.lists(st.tuples(st.floats(0, 10), st.floats(0, 10)), min_size=2,
                                  max_size=3), min_size=1, max_size=7)


@settings(max_examples=50, deadline=None)
@given(strokes_lists)
def test_stroke_order_keeps_every_stroke_and_never_lengthens_the_pen_up_moves(raw):
    strokes = [np.array(stroke) for stroke in raw]
    ordered = drawing.order_strokes(strokes, (0.0, 0.0))
    assert sorted(map(_canonical, ordered)) == sorted(map(_canonical, strokes))
    assert drawing.pen_up_length(ordered, (0, 0)) <= drawing.pen_up_length(strokes, (0, 0)) + 1e-9


def _canonical(stroke: np.ndarray) -> tuple:
    forward, backward = tuple(map(tuple, stroke)), tuple(map(tuple, stroke[::-1]))
    return min(forward, backward)


def test_stroke_order_is_near_the_best_on_small_drawings():
    rng = np.random.default_rng(7)
    for _ in range(5):
        strokes = [rng.random((2, 2)) * 8 for _ in range(5)]
        best = min(drawing.pen_up_length(
            [s[::-1] if flip else s for s, flip in zip(order, flips, strict=True)], (0, 0))
            for order in itertools.permutations(strokes)
            for flips in itertools.product((False, True), repeat=5))
        assert drawing.pen_up_length(drawing.order_strokes(strokes, (0, 0)), (0, 0)) \
            <= 1.15 * best


def test_hello_ros_needs_less_pen_up_travel_once_ordered():
    result = plan('text', text='Hello ROS', height=1.0)
    assert result.path.pen_up_length < 0.7 * result.pen_up_unordered


def test_the_follower_waits_for_the_pen_before_each_curve():
    path = drawing.drawing_path(Pose2D(1.0, 1.0, 0.0), [np.array([(2.0, 1.0), (3.0, 1.0)])],
                                corner_angle_rad=0.1)
    # the exact follower
    follower = ControllerChoice().driver(Plan('drawing', path), manage_pen=True)
    config = DEFAULT_SETTINGS.control
    first = follower.update(Pose2D(1.0, 1.0, 0.0), config)
    assert (first.linear, first.angular) == (0.0, 0.0) and follower.pen_wanted is False
    follower.pen_down = False
    assert follower.update(Pose2D(1.0, 1.0, 0.0), config).linear > 0.0  # pen up: drives
    assert follower.pen_wanted is None
    at_stroke = Pose2D(2.0, 1.0, 0.0)
    for _ in range(5):  # the pen-up move ends here: the stroke waits for the pen to go down
        command = follower.update(at_stroke, config)
    assert (command.linear, command.angular) == (0.0, 0.0) and follower.pen_wanted is True
    follower.pen_down = True
    assert follower.update(at_stroke, config).linear > 0.0
    plain = ControllerChoice().driver(Plan('drawing', path), manage_pen=False)  # drives at once
    assert plain.update(Pose2D(1.0, 1.0, 0.0), config).linear > 0.0


def test_the_menu_asks_for_text_and_sends_enter_as_nothing():
    from turtle_traj.cli.menu import CHOICES, NodeSnapshot, ask_field

    write = next(t for t in CHOICES.values() if t.name == 'text')
    field = next(f for f in write.fields if f.name == 'text')
    live = NodeSnapshot({}, DEFAULT_SETTINGS, None)
    assert ask_field(write, field, {}, live, lambda _: ' Hello ROS ', print) == 'Hello ROS'
    assert ask_field(write, field, {}, live, lambda _: '', print) is None
    assert write.request_values({'text': None})['text'] == ''  # refused by the node: empty

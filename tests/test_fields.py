"""The one parser of each field type: text (command line, menu, a file of points) and JSON values
(the live view's panel) give the same values, and the same refusals."""

import math

import pytest

from turtle_traj.core.fields import FieldError, parse_points
from turtle_traj.core.planning.limits import MAX_POINTS, MAX_TEXT_CHARS
from turtle_traj.core.registry import BY_NAME

SIDES = BY_NAME['polygon'].fields[0]
SIZE = next(item for item in BY_NAME['circle'].fields if item.name == 'size')
CLOCKWISE = next(item for item in BY_NAME['circle'].fields if item.name == 'clockwise')
POINTS = next(item for item in BY_NAME['follow_path'].fields if item.name == 'points')
TEXT = next(item for item in BY_NAME['text'].fields if item.name == 'text')


@pytest.mark.parametrize(('item', 'text', 'json_value', 'expected'), [
    (SIDES, '6', 6, 6), (SIDES, '6.0', 6.0, 6),
    (SIZE, '1.5', 1.5, 1.5), (SIZE, '2', 2, 2.0),
    (CLOCKWISE, 'y', True, True), (CLOCKWISE, 'no', False, False),
    (POINTS, '1,2 3.5,4', [[1, 2], [3.5, 4]], [(1.0, 2.0), (3.5, 4.0)]),
    (TEXT, 'Hi', 'Hi', 'Hi'),
])
def test_text_and_json_give_the_same_value(item, text, json_value, expected):
    assert item.parse(text) == expected
    assert item.parse(json_value) == expected
    assert type(item.parse(text)) is type(expected)


@pytest.mark.parametrize(('item', 'given', 'reason'), [
    (SIDES, '4.5', 'not a whole number'), (SIDES, 4.5, 'not a whole number'),
    (SIZE, 'big', "'big' is not a number"), (SIZE, 'nan', 'not a finite number'),
    (SIZE, math.inf, 'not a finite number'), (SIZE, True, 'not a finite number'),
    (CLOCKWISE, 'maybe', 'please answer y or n'),
    (POINTS, '1,2,3', 'a point must be'), (POINTS, [[1, 2, 3]], 'a point must be'),
    (POINTS, [[0, 0]] * (MAX_POINTS + 1), f'at most {MAX_POINTS}'),
    (TEXT, 7, 'must be a text'), (TEXT, 'x' * (MAX_TEXT_CHARS + 1), 'must be a text'),
])
def test_a_value_not_of_the_type_is_refused_with_the_reason(item, given, reason):
    with pytest.raises(FieldError) as refused:
        item.parse(given)
    assert reason in str(refused.value)


def test_a_file_of_points_reads_commas_spaces_and_comments():
    text = '# a path\n1,2\n3 4\n\n5.5, 6  # the last\n'
    assert parse_points(text) == [(1.0, 2.0), (3.0, 4.0), (5.5, 6.0)]

"""Tests for nubot_common.field: MSL field dimensions, validation, goal and line geometry."""

import dataclasses

import pytest

from nubot_common.field import FieldGeometry

FIELDS = [FieldGeometry(), FieldGeometry.msl_current()]
FIELD_IDS = ["chapter_18x12", "msl_current_22x14"]


def test_defaults_are_the_chapter_field():
    field = FieldGeometry()
    assert (field.length, field.width) == (18.0, 12.0)
    assert (field.goal_width, field.goal_height) == (2.4, 1.0)
    assert (field.half_length, field.half_width) == (9.0, 6.0)


def test_msl_current_is_22_by_14_with_the_same_goal():
    field = FieldGeometry.msl_current()
    assert (field.length, field.width) == (22.0, 14.0)
    assert (field.half_length, field.half_width) == (11.0, 7.0)
    assert (field.goal_width, field.goal_height) == (2.4, 1.0)
    assert field.penalty_mark_distance == 3.6


def test_field_is_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError, match="cannot assign to field 'length'"):
        FieldGeometry().length = 20.0  # type: ignore[misc]


@pytest.mark.parametrize("name", ["length", "width", "goal_width", "goal_height", "goal_depth", "border"])
@pytest.mark.parametrize("value", [0.0, -1.0])
def test_non_positive_sizes_are_rejected_naming_the_field(name, value):
    with pytest.raises(ValueError, match=rf"^{name} must be positive, got {value}$"):
        FieldGeometry(**{name: value})


def test_goal_wider_than_the_field_is_rejected():
    with pytest.raises(ValueError, match="goal_width must be smaller than the field width"):
        FieldGeometry(goal_width=12.0)


@pytest.mark.parametrize(
    "changes",
    [{"penalty_area_width": 12.0}, {"penalty_area_length": 9.0}, {"length": 4.0, "penalty_area_length": 2.25}],
)
def test_penalty_area_must_fit_in_one_half(changes):
    with pytest.raises(ValueError, match="the penalty area must fit inside one half of the field"):
        FieldGeometry(**changes)


@pytest.mark.parametrize("field", FIELDS, ids=FIELD_IDS)
@pytest.mark.parametrize("side", [1, -1])
def test_goal_posts_leave_goal_width_between_them_behind_the_end_line(field, side):
    (x0, y0), (x1, y1) = field.goal_posts(side)
    assert x0 == x1
    assert x0 * side > 0
    assert abs(x0) - field.post_radius == pytest.approx(field.half_length)
    assert y0 == pytest.approx(-y1)
    assert y0 < 0 < y1
    assert (y1 - y0) - 2 * field.post_radius == pytest.approx(field.goal_width)


def test_goal_posts_of_the_two_sides_are_mirror_images():
    field = FieldGeometry()
    (ax0, ay0), (ax1, ay1) = field.goal_posts(1)
    (bx0, by0), (bx1, by1) = field.goal_posts(-1)
    assert (bx0, by0, bx1, by1) == (-ax0, ay0, -ax1, ay1)


def test_is_inside_on_the_lines_and_beyond():
    field = FieldGeometry()
    assert field.is_inside(0.0, 0.0)
    assert field.is_inside(9.0, 6.0)
    assert field.is_inside(-9.0, -6.0)
    assert not field.is_inside(9.01, 0.0)
    assert not field.is_inside(0.0, -6.01)
    assert field.is_inside(9.5, 6.5, margin=0.5)
    assert not field.is_inside(9.5, 6.51, margin=0.5)
    assert not field.is_inside(0.0, 5.9, margin=-0.2)


def test_is_inside_uses_the_wider_current_field():
    assert not FieldGeometry().is_inside(10.0, 6.5)
    assert FieldGeometry.msl_current().is_inside(10.0, 6.5)


def test_is_in_goal_mouth_requires_the_whole_ball_between_posts_and_under_bar():
    field = FieldGeometry()
    radius = 0.11
    assert field.is_in_goal_mouth(0.0, radius, radius)
    assert field.is_in_goal_mouth(-1.2 + radius, radius, radius)
    assert field.is_in_goal_mouth(1.2 - radius, 1.0 - radius, radius)
    assert not field.is_in_goal_mouth(1.2 - radius + 0.001, radius, radius)
    assert not field.is_in_goal_mouth(-1.2, radius, radius)
    assert not field.is_in_goal_mouth(0.0, 1.0 - radius + 0.001, radius)
    assert not field.is_in_goal_mouth(0.0, 1.0, radius)


def _on_or_inside(field: FieldGeometry, point: tuple[float, float]) -> bool:
    x, y = point
    return abs(x) <= field.half_length + 1e-9 and abs(y) <= field.half_width + 1e-9


@pytest.mark.parametrize("field", FIELDS, ids=FIELD_IDS)
def test_line_segments_all_lie_on_or_inside_the_field_lines(field):
    segments = field.line_segments()
    assert len(segments) == 5 + 2 * 2 * 3
    for start, end in segments:
        assert _on_or_inside(field, start), (start, end)
        assert _on_or_inside(field, end), (start, end)
        assert start != end
        assert start[0] == end[0] or start[1] == end[1], "lines are axis-aligned"


@pytest.mark.parametrize("field", FIELDS, ids=FIELD_IDS)
def test_line_segments_include_the_boundary_and_halfway_line(field):
    hl, hw = field.half_length, field.half_width
    segments = {frozenset(s) for s in field.line_segments()}
    assert frozenset({(-hl, -hw), (hl, -hw)}) in segments
    assert frozenset({(-hl, hw), (hl, hw)}) in segments
    assert frozenset({(-hl, -hw), (-hl, hw)}) in segments
    assert frozenset({(hl, -hw), (hl, hw)}) in segments
    assert frozenset({(0.0, -hw), (0.0, hw)}) in segments


@pytest.mark.parametrize("field", FIELDS, ids=FIELD_IDS)
@pytest.mark.parametrize("side", [1, -1])
def test_penalty_and_goal_area_front_lines(field, side):
    segments = {frozenset(s) for s in field.line_segments()}
    for depth, width in (
        (field.penalty_area_length, field.penalty_area_width),
        (field.goal_area_length, field.goal_area_width),
    ):
        x = side * (field.half_length - depth)
        assert frozenset({(x, -width / 2), (x, width / 2)}) in segments


def test_a_field_that_constructs_has_all_lines_inside():
    try:
        field = FieldGeometry(goal_area_width=13.0)
    except ValueError:
        return
    assert all(_on_or_inside(field, p) for segment in field.line_segments() for p in segment)


@pytest.mark.parametrize(("x", "y", "z", "side"), [
    (9.3, 0.0, 0.11, 1),
    (-9.3, 0.5, 0.5, -1),
    (-9.12, 1.15, 0.11, -1),  # came in grazing a post: between the side nets, wholly behind the line
    (9.5, -1.2, 0.85, 1),  # in a back corner, under the bar
    (9.05, 0.0, 0.11, 0),  # on the line, not wholly behind it
    (9.3, 1.5, 0.11, 0),  # beside the goal, outside its side net
    (9.3, 0.0, 1.15, 0),  # on the top net
    (9.75, 0.0, 0.11, 0),  # behind the back net
    (50.0, 0.0, 0.11, 0),
])
def test_goal_holding_is_the_ball_wholly_behind_a_goal_line_inside_the_nets(x, y, z, side):
    assert FieldGeometry().goal_holding(x, y, z, 0.11) == side

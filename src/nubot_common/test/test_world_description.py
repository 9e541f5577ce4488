"""The world description: the shipped fields, every marking, loading and refusing bad ones."""

import math

import pytest

from nubot_common import NubotCommonError
from nubot_common import conversions as conv
from nubot_common.field import FieldGeometry
from nubot_common.world_description import WORLD_NAMESPACE, WorldDescription, load_world, world_from_params


def test_the_shipped_fields_are_the_chapters_and_the_current_rules():
    chapter, current = load_world("18x12"), load_world("22x14")
    assert chapter == WorldDescription(), "the default is the chapter's field"
    assert chapter.field == FieldGeometry()
    assert current.field == FieldGeometry.msl_current()
    f = current.field
    assert (f.length, f.width, f.penalty_area_width, f.penalty_area_length) == (22.0, 14.0, 6.9, 2.25)
    assert (f.goal_area_width, f.goal_area_length) == (3.9, 0.75)
    assert (f.penalty_mark_distance, f.corner_arc_radius) == (3.6, 0.75)
    assert (current.ball.radius, current.robot.radius, current.ball_name) == (0.11, 0.26, "football")
    assert (current.name, chapter.name) == ("22 x 14 m", "18 x 12 m")


def test_every_marking_lies_on_the_field():
    f = load_world("22x14").field
    arcs = f.arcs()
    assert len(arcs) == 5 and arcs[0].radius == f.center_circle_radius
    for arc in arcs[1:]:  # corner arcs: quarter circles that open into the field
        mid = (arc.start + arc.end) / 2
        x, y = arc.x + arc.radius * math.cos(mid), arc.y + arc.radius * math.sin(mid)
        assert f.is_inside(x, y) and abs(arc.end - arc.start) == pytest.approx(math.pi / 2)
    assert f.spots() == [(0.0, 0.0), (-7.4, 0.0), (7.4, 0.0)], "centre spot and penalty marks 3.6 m in"
    for (x0, y0), (x1, y1) in f.line_segments():
        assert f.is_inside(x0, y0) and f.is_inside(x1, y1)


def test_a_world_file_with_a_bad_value_is_refused_naming_it(tmp_path):
    path = tmp_path / "world.yaml"
    path.write_text("field: {length: 18.0, width: 12.0, penalty_mark_distance: 9.5}\n")
    with pytest.raises(NubotCommonError, match="the penalty mark must lie in its own half"):
        load_world(path)
    path.write_text("field: {lenght: 20.0}\n")
    with pytest.raises(NubotCommonError, match=r"unknown parameter\(s\) lenght"):
        load_world(path)
    with pytest.raises(NubotCommonError, match="no world description '30x20': give one of 18x12, 22x14"):
        load_world("30x20")


def test_a_node_without_a_world_is_told_how_to_load_one():
    with pytest.raises(NubotCommonError, match=f"no world description under {WORLD_NAMESPACE}: .*rosparam load"):
        world_from_params(None)
    assert world_from_params({"field": {"length": 22.0, "width": 14.0}}).field.length == 22.0


@pytest.mark.parametrize("name", ["18x12", "22x14"])
def test_the_world_description_message_carries_every_value(name):
    world = load_world(name)
    msg = conv.world_description_msg(world, 3.0)
    assert conv.world_description(msg) == world and msg.header.stamp.to_sec() == 3.0
    msg.field.length = -1.0
    with pytest.raises(NubotCommonError, match="bad world description: length must be positive"):
        conv.world_description(msg)

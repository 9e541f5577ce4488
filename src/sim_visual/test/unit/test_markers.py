"""Unit tests of sim_visual.markers (the frames and markers RViz shows) and of the node's conversions."""

import math
from io import BytesIO

import numpy as np
import pytest

from nubot_common.field import FieldGeometry
from nubot_common.geometry import quaternion_to_yaw, wrap_angle, yaw_to_quaternion
from nubot_common.naming import TEAM_COLOURS, rgb
from nubot_common.team_frame import TeamFrame
from nubot_common.world_description import WorldDescription, load_world
from sim_visual.markers import (
    BALL_FRAME,
    WORLD_FRAME,
    FrameTransform,
    MarkerKind,
    MatchMarkersParams,
    ModelPose,
    SimTimeThrottle,
    TeamSides,
    configured_attacks,
    field_markers,
    frame_transforms,
    scene_markers,
)

WORLD = WorldDescription()


def robot(name, x, y, yaw):
    return ModelPose(name, (x, y, 0.0), yaw_to_quaternion(yaw))


POSES = [robot("nubot1", -8.0, 0.0, 0.0), robot("nubot2", -1.0, 1.5, 0.7), robot("rival1", 8.0, 0.0, math.pi),
         robot("rival2", 2.0, -3.0, -2.0), ModelPose(WORLD.ball_name, (1.0, 2.0, 0.3), (0.3, 0.1, 0.2, 0.9))]


def apply(tf: FrameTransform, x: float, y: float) -> tuple[float, float]:
    """A point of the child frame in the parent frame (planar transforms)."""
    yaw = quaternion_to_yaw(*tf.rotation)
    c, s = math.cos(yaw), math.sin(yaw)
    return tf.translation[0] + c * x - s * y, tf.translation[1] + s * x + c * y


def by_child(transforms):
    return {tf.child: tf for tf in transforms}


# --- frames ------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("attack", [1, -1])
def test_a_team_frame_agrees_with_team_frame(attack):
    sides = TeamSides()
    sides.on_referee(["nubot", "rival"], [attack, -attack])
    frames = by_child(frame_transforms(POSES, sides, WORLD.ball_name))
    rng = np.random.default_rng(3)
    for team, team_attack in (("nubot", attack), ("rival", -attack)):
        tf, frame = frames[team], TeamFrame(team_attack)
        assert tf.parent == WORLD_FRAME
        assert math.isclose(sum(q * q for q in tf.rotation), 1.0)
        for x, y, heading in rng.uniform((-9, -6, -math.pi), (9, 6, math.pi), (20, 3)):
            assert apply(tf, x, y) == pytest.approx(frame.point_to_world(x, y), abs=1e-12)
            world_heading = wrap_angle(quaternion_to_yaw(*tf.rotation) + heading)
            assert math.cos(world_heading - frame.heading_to_world(heading)) == pytest.approx(1.0)


def test_every_robot_has_its_base_link_and_the_ball_its_frame():
    frames = by_child(frame_transforms(POSES, TeamSides(), WORLD.ball_name))
    assert set(frames) == {"nubot", "rival", "nubot1/base_link", "nubot2/base_link", "rival1/base_link",
                           "rival2/base_link", BALL_FRAME}
    for pose in POSES[:4]:
        tf = frames[f"{pose.name}/base_link"]
        assert (tf.parent, tf.translation, tf.rotation) == (WORLD_FRAME, pose.position, pose.orientation)
    ball = frames[BALL_FRAME]
    assert ball.translation == (1.0, 2.0, 0.3), "the ball at its height"
    assert ball.rotation == (0.0, 0.0, 0.0, 1.0), "its spin is left out"


def test_a_robot_seen_from_the_other_team_is_where_team_frame_puts_it():
    """nubot -> rival2/base_link, composed from the two transforms as tf2 does, is rival2 in nubot's frame."""
    sides = TeamSides()
    sides.on_referee(["rival", "nubot"], [1, -1])
    frames = by_child(frame_transforms(POSES, sides, WORLD.ball_name))
    team, body = frames["nubot"], frames["rival2/base_link"]
    yaw = quaternion_to_yaw(*team.rotation)
    dx, dy = body.translation[0] - team.translation[0], body.translation[1] - team.translation[1]
    seen = (math.cos(yaw) * dx + math.sin(yaw) * dy, -math.sin(yaw) * dx + math.cos(yaw) * dy)
    assert seen == pytest.approx(TeamFrame(-1).point_to_team(2.0, -3.0))
    assert seen == pytest.approx((-2.0, 3.0))


def test_the_referee_decides_and_half_time_turns_the_frames():
    sides = TeamSides({"nubot": -1})
    assert sides.attack("nubot", ["nubot", "rival"]) == -1, "the simulator's configured attack before the referee"
    assert sides.attack("rival", ["nubot", "rival"]) == 1, "the goal the known team does not attack"
    sides.on_referee(["nubot", "rival"], [1, -1])
    assert (sides.attack("nubot", []), sides.attack("rival", [])) == (1, -1)
    sides.on_referee(["nubot", "rival"], [-1, 1])  # half time
    frames = by_child(frame_transforms(POSES, sides, WORLD.ball_name))
    assert apply(frames["nubot"], 1.0, 0.0) == pytest.approx((-1.0, 0.0))
    assert apply(frames["rival"], 1.0, 0.0) == pytest.approx((1.0, 0.0))


def test_without_referee_nor_configuration_the_first_team_alphabetically_attacks_plus_x():
    sides = TeamSides()
    seen = ["rival", "nubot"]  # the order the spawners happened to add them
    assert (sides.attack("nubot", seen), sides.attack("rival", seen)) == (1, -1)
    assert sides.attack("alpha", ["alpha"]) == 1, "a team playing alone: its frame is the world frame"


def test_a_team_the_referee_names_gets_a_frame_before_its_robots_arrive():
    sides = TeamSides()
    sides.on_referee(["nubot", "rival"], [1, -1])
    children = [tf.child for tf in frame_transforms(POSES[:2], sides, WORLD.ball_name)]
    assert children[:2] == ["nubot", "rival"]


def test_configured_attacks_read_the_simulator_robots():
    robots = [{"name": "nubot1", "x": -2.0, "attack": 1}, {"name": "rival2", "attack": -1}, {"name": "ball"},
              "nonsense", {"name": "nubot3", "attack": 7}]
    assert configured_attacks(robots) == {"nubot": 1, "rival": -1}
    assert configured_attacks(None) == {}


def test_a_bad_attack_is_refused():
    with pytest.raises(Exception, match="attack must be 1"):
        TeamSides({"nubot": 0})


# --- the field ---------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("field", ["18x12", "22x14"])
def test_the_field_markers_cover_every_line_arc_spot_and_both_goals(field):
    world = load_world(field)
    f: FieldGeometry = world.field
    markers = field_markers(world)
    assert all(m.frame == WORLD_FRAME for m in markers)
    assert len({(m.ns, m.id) for m in markers}) == len(markers), "each marker its own (ns, id)"
    (lines,) = [m for m in markers if m.ns == "lines"]
    assert lines.kind is MarkerKind.LINE_LIST and lines.scale[0] == f.line_width
    drawn = {tuple(round(v, 9) for v in (*a[:2], *b[:2])) for a, b in zip(lines.points[::2], lines.points[1::2])}
    for a, b in f.line_segments():
        assert tuple(round(v, 9) for v in (*a, *b)) in drawn, f"the line {a} -> {b} is drawn"
    assert len(drawn) == len(f.line_segments())
    arcs = [m for m in markers if m.ns == "arcs"]
    assert len(arcs) == len(f.arcs()) == 5
    for arc, marker in zip(f.arcs(), arcs):
        assert marker.kind is MarkerKind.LINE_STRIP and len(marker.points) >= 10
        for x, y, _ in marker.points:
            assert math.hypot(x - arc.x, y - arc.y) == pytest.approx(arc.radius)
        ends = [(arc.x + arc.radius * math.cos(a), arc.y + arc.radius * math.sin(a)) for a in (arc.start, arc.end)]
        assert [p[:2] for p in (marker.points[0], marker.points[-1])] == pytest.approx(ends)
    assert [m.position[:2] for m in markers if m.ns == "spots"] == pytest.approx(f.spots())
    posts = [m.position[:2] for m in markers if m.ns == "goals" and m.kind is MarkerKind.CYLINDER]
    assert posts == pytest.approx([*f.goal_posts(1), *f.goal_posts(-1)])
    nets = [m for m in markers if m.ns == "goals" and m.kind is MarkerKind.LINE_LIST]
    assert sorted(max(abs(p[0]) for p in n.points) for n in nets) == pytest.approx([f.half_length + f.goal_depth] * 2)
    (carpet,) = [m for m in markers if m.ns == "carpet"]
    assert carpet.scale[:2] == pytest.approx((f.length + 2 * f.border, f.width + 2 * f.border))


# --- the scene ---------------------------------------------------------------------------------------------------
def test_the_scene_draws_robots_ball_and_paths_on_their_frames():
    sides = TeamSides()
    sides.on_referee(["nubot", "rival"], [1, -1])
    paths = {"nubot2": ("nubot", [(-1.0, 1.5), (0.0, 1.0), (2.0, 0.0)]), "rival1": ("rival", [(-8.0, 0.0)])}
    markers = scene_markers(POSES, WORLD, sides, paths)
    assert markers[0].kind is MarkerKind.DELETEALL, "a robot that left takes its markers along"
    assert len({(m.ns, m.id) for m in markers}) == len(markers)
    bodies = {m.frame: m for m in markers if m.ns == "robots"}
    assert set(bodies) == {f"{p.name}/base_link" for p in POSES[:4]}
    body = bodies["nubot1/base_link"]
    assert body.kind is MarkerKind.CYLINDER and body.frame_locked
    assert body.scale == pytest.approx((2 * WORLD.robot.radius, 2 * WORLD.robot.radius, WORLD.robot.height))
    cyan, magenta = (pytest.approx(rgb(c)) for c in TEAM_COLOURS[:2])  # the live page's colours too
    assert body.colour[:3] == cyan and bodies["rival2/base_link"].colour[:3] == magenta
    numbers = {m.frame: m.text for m in markers if m.kind is MarkerKind.TEXT_VIEW_FACING}
    assert numbers == {"nubot1/base_link": "1", "nubot2/base_link": "2", "rival1/base_link": "1",
                       "rival2/base_link": "2"}
    arrows = [m for m in markers if m.kind is MarkerKind.ARROW]
    assert len(arrows) == 4 and all(m.points[1][0] > WORLD.robot.radius and m.points[1][1] == 0 for m in arrows)
    (ball,) = [m for m in markers if m.ns == "ball"]
    assert ball.frame == BALL_FRAME and ball.kind is MarkerKind.SPHERE and ball.scale[0] == 2 * WORLD.ball.radius
    (path,) = [m for m in markers if m.ns == "paths"]  # rival1's single point is no path
    assert (path.kind, path.frame) == (MarkerKind.LINE_STRIP, "nubot")
    assert [p[:2] for p in path.points] == [(-1.0, 1.5), (0.0, 1.0), (2.0, 0.0)]


def test_an_empty_world_is_an_empty_scene():
    assert [m.kind for m in scene_markers([], WORLD, TeamSides(), {})] == [MarkerKind.DELETEALL]


# --- the throttle and the parameters -------------------------------------------------------------------------
def test_the_throttle_thins_100_hz_to_30_hz_and_restarts_when_time_runs_back():
    throttle = SimTimeThrottle(1.0 / 30.0)
    passed = [k for k in range(300) if throttle.due(k * 0.01)]
    assert len(passed) == 90 and {b - a for a, b in zip(passed, passed[1:])} == {3, 4}
    assert throttle.due(0.5), "a world reset or a bag played again"
    assert not throttle.due(0.51)
    assert throttle.due(10.0), "after a pause"


def test_bad_rates_are_refused():
    with pytest.raises(ValueError, match="tf_rate must be positive"):
        MatchMarkersParams(tf_rate=0.0)
    with pytest.raises(ValueError, match="period must be positive"):
        SimTimeThrottle(0.0)


# --- the node's conversions ----------------------------------------------------------------------------------
def test_the_conversions_make_tf_and_marker_messages():
    import genpy
    from geometry_msgs.msg import Pose, Twist
    from visualization_msgs.msg import Marker as MarkerMsg

    from nubot_common.msg import ModelStates
    from sim_visual import marker_conversions as conv

    states = ModelStates(name=[p.name for p in POSES])
    for p in POSES:
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = p.position
        pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = p.orientation
        states.pose.append(pose)
        states.twist.append(Twist())
    states.header.stamp = genpy.Time(12, 340_000_000)
    buffer = BytesIO()
    states.serialize(buffer)
    raw = buffer.getvalue()
    assert conv.header_stamp(raw) == genpy.Time(12, 340_000_000)
    assert conv.model_poses(conv.model_states(raw)) == POSES

    tf = conv.tf_message(frame_transforms(POSES, TeamSides(), WORLD.ball_name), conv.header_stamp(raw))
    by_name = {t.child_frame_id: t for t in tf.transforms}
    assert by_name["rival"].header.frame_id == WORLD_FRAME
    assert by_name["rival"].transform.rotation.z == pytest.approx(1.0)
    assert by_name["nubot2/base_link"].transform.translation.y == 1.5
    assert {t.header.stamp for t in tf.transforms} == {genpy.Time(12, 340_000_000)}

    array = conv.marker_array(scene_markers(POSES, WORLD, TeamSides(), {"nubot1": ("nubot", [(0, 0), (1, 1)])}))
    assert array.markers[0].action == MarkerMsg.DELETEALL
    kinds = {m.type for m in array.markers[1:]}
    assert kinds == {MarkerMsg.CYLINDER, MarkerMsg.TEXT_VIEW_FACING, MarkerMsg.ARROW, MarkerMsg.LINE_STRIP,
                     MarkerMsg.SPHERE}
    strip = next(m for m in array.markers if m.type == MarkerMsg.LINE_STRIP)
    assert (strip.header.frame_id, strip.frame_locked, strip.points[1].x) == ("nubot", True, 1.0)
    buffer = BytesIO()
    array.serialize(buffer)  # every field has its message type

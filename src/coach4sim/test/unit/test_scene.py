"""The viewer's scene: messages in (as rospy or rosbags deliver them), the match in the world frame out."""

import json
import math
from types import SimpleNamespace as NS

import pytest

from coach4sim.scene import EVENTS_KEPT, Scene, field_layout, stamp_seconds
from nubot_common.field import FieldGeometry
from nubot_common.match_mode import MatchMode
from nubot_common.team_play import Role
from nubot_common.world_description import WorldDescription

WORLD = WorldDescription()


def stamp(t):
    return NS(secs=int(t), nsecs=int(round((t - int(t)) * 1e9)))


def pose(x, y, yaw, z=0.0):
    return NS(position=NS(x=x, y=y, z=z),
              orientation=NS(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2)))


def twist(vx=0.0, vy=0.0, vz=0.0):
    return NS(linear=NS(x=vx, y=vy, z=vz), angular=NS(x=0.0, y=0.0, z=0.0))


def states(t, models):
    return NS(header=NS(stamp=stamp(t)), name=[m[0] for m in models], pose=[pose(*m[1:]) for m in models],
              twist=[twist() for _ in models])


def referee(t, attack=(1, -1), score=(0, 0), event="", running=True, half=1, modes=(15, 15)):
    return NS(header=NS(stamp=stamp(t)), teams=["nubot", "rival"], score=list(score), attack=list(attack),
              match_mode=bytes(modes), half=half, game_time=t, running=running, last_event=event)


def robot_info(agent, role, target, pos=(0.0, 0.0), heading=0.0, valid=True):
    return NS(AgentID=agent, current_role=int(role), target=NS(x=target[0], y=target[1]),
              pos=NS(x=pos[0], y=pos[1]), heading=NS(theta=heading), isvalid=valid)


def test_robots_and_ball_come_in_the_world_frame_with_heading_and_the_ball_s_height():
    scene = Scene(WORLD)
    scene.on_model_states(states(3.0, [("nubot1", -8.0, 0.5, 0.3), ("rival2", 2.0, -1.0, -2.0),
                                       ("football", 1.0, 2.0, 0.0, 0.8)]))
    frame = scene.frame()
    robots = {r["name"]: r for r in frame["robots"]}
    assert robots["nubot1"]["x"] == -8.0 and robots["nubot1"]["theta"] == pytest.approx(0.3, abs=1e-3)
    assert robots["rival2"]["team"] == "rival" and robots["rival2"]["id"] == 2
    assert frame["ball"]["z"] == pytest.approx(0.8) and frame["t"] == 3.0
    assert [t["name"] for t in frame["teams"]] == ["nubot", "rival"]
    json.dumps(frame, allow_nan=False)  # the page gets strict JSON


def test_roles_targets_and_paths_of_the_team_attacking_minus_x_are_turned_into_the_world_frame():
    scene = Scene(WORLD)
    scene.on_referee(referee(1.0, attack=(1, -1)))
    scene.on_model_states(states(1.0, [("nubot2", -1.0, 0.0, 0.0), ("rival2", 1.0, 0.0, math.pi)]))
    scene.on_teammates("rival", NS(messages=[NS(robot=robot_info(2, Role.ACTIVE, (3.0, 1.0)))]))
    scene.on_teammates("nubot", NS(messages=[NS(robot=robot_info(2, Role.PASSIVE, (3.0, 1.0)))]))
    scene.on_path("rival2", NS(points=[NS(x=0.0, y=0.0), NS(x=3.0, y=1.0)]))
    robots = {r["name"]: r for r in scene.frame()["robots"]}
    assert robots["rival2"]["role"] == "ACTIVE" and robots["rival2"]["target"] == [-3.0, -1.0]
    assert robots["rival2"]["path"] == [[0.0, 0.0], [-3.0, -1.0]]
    assert robots["nubot2"]["role"] == "PASSIVE" and robots["nubot2"]["target"] == [3.0, 1.0]
    scene.on_referee(referee(20.0, attack=(-1, 1), half=2))  # the teams change ends
    robots = {r["name"]: r for r in scene.frame()["robots"]}
    assert robots["rival2"]["target"] == [3.0, 1.0] and robots["nubot2"]["target"] == [-3.0, -1.0]


def test_a_lockstep_bag_s_strategy_gives_the_role_when_no_team_message_does():
    scene = Scene(WORLD)
    scene.on_model_states(states(1.0, [("nubot1", -8.0, 0.0, 0.0)]))
    assert scene.frame()["robots"][0]["role"] is None
    scene.on_strategy("nubot1", NS(role=int(Role.GOALIE)))
    assert scene.frame()["robots"][0]["role"] == "GOALIE"


def test_the_referee_s_score_modes_and_last_decisions_are_kept_and_repeats_are_not():
    scene = Scene(WORLD)
    for k in range(EVENTS_KEPT + 3):
        scene.on_referee(referee(k, event=f"decision {k}", modes=(MatchMode.OUR_KICKOFF, MatchMode.OPP_KICKOFF)))
        scene.on_referee(referee(k + 0.5, event=f"decision {k}", score=(1, 0)))
    ref = scene.frame()["referee"]
    assert [e["text"] for e in ref["events"]] == [f"decision {k}" for k in range(3, EVENTS_KEPT + 3)]
    assert ref["score"] == [1, 0] and ref["teams"] == ["nubot", "rival"] and ref["seen"]


def test_an_unknown_match_mode_is_shown_as_its_number():
    scene = Scene(WORLD)
    scene.on_referee(referee(1.0, modes=(15, 99)))
    assert scene.frame()["referee"]["modes"] == ["STARTROBOT", "99"]


def test_nan_from_the_simulator_becomes_null_not_invalid_json():
    scene = Scene(WORLD)
    scene.on_model_states(states(1.0, [("nubot1", float("nan"), 0.0, 0.0), ("football", 0.0, float("inf"), 0.0)]))
    text = json.dumps(scene.frame(), allow_nan=False)
    assert '"x":null' in text.replace(" ", "") and '"y":null' in text.replace(" ", "")


def test_a_watched_robot_s_beliefs_are_drawn_in_the_world_frame():
    scene = Scene(WORLD)
    scene.on_referee(referee(1.0, attack=(1, -1)))
    scene.on_model_states(states(1.0, [("rival1", 8.0, 0.0, math.pi), ("rival2", 1.0, 0.0, math.pi)]))
    ball = [NS(pos_known=False, pos=NS(x=0, y=0), ballinfostate=0),
            NS(pos_known=True, pos=NS(x=2.0, y=0.5), ballinfostate=1)]
    belief = NS(header=NS(stamp=stamp(1.0)),
                robotinfo=[robot_info(1, Role.GOALIE, (0, 0), pos=(-8.0, 0.0)),
                           robot_info(2, Role.ACTIVE, (0, 0), pos=(-1.0, 0.0), heading=0.0),
                           robot_info(3, Role.NOROLE, (0, 0), valid=False)],
                ballinfo=ball, oppinfo=NS(pos=[NS(x=4.0, y=1.0)]), obstacleinfo=NS(pos=[NS(x=4.0, y=1.0)]))
    scene.on_world_model("rival2", belief)
    assert scene.frame()["belief"] is None  # nobody watched
    seen = scene.frame("rival2")["belief"]
    assert [(m["id"], m["x"]) for m in seen["teammates"]] == [(1, 8.0), (2, 1.0)]
    assert seen["teammates"][1]["theta"] == pytest.approx(math.pi, abs=1e-3)
    assert (seen["ball"]["x"], seen["ball"]["y"], seen["ball"]["own"]) == (-2.0, -0.5, True)
    assert seen["opponents"] == [[-4.0, -1.0]]
    assert scene.frame("nobody7")["belief"] is None


def test_the_field_layout_has_every_marking_of_the_world_s_field():
    for geometry in (FieldGeometry(), FieldGeometry.msl_current()):
        layout = field_layout(WorldDescription(field=geometry))
        assert len(layout["segments"]) == len(geometry.line_segments()) == 17
        assert len(layout["arcs"]) == 5 and len(layout["spots"]) == 3
        assert {g["side"] for g in layout["goals"]} == {1, -1}
        assert layout["length"] == geometry.length and layout["goals"][0]["depth"] == geometry.goal_depth
        json.dumps(layout, allow_nan=False)


def test_stamps_of_rospy_and_of_rosbags_read_alike():
    assert stamp_seconds(NS(secs=3, nsecs=500_000_000)) == stamp_seconds(NS(sec=3, nanosec=500_000_000)) == 3.5

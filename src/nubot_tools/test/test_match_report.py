"""Round trip of the match report: write a scripted match bag with the repo's messages, report, compare.

The scripted match (sim time, 0-20 s, nubot attacks +x, rival -x):

- play runs 1-12 s (kick-off nubot) and 14-19 s (kick-off rival); the referee stops it at each goal;
- touches: 2 nubot2, 4 nubot3, 6 nubot2, 8 rival1, 10 nubot1, 13 nubot4 (stopped), 15 rival2, 17 nubot3;
- kicks: 3 nubot2 -> nubot3 (completed), 5 nubot3 -> nubot2 (completed), 7 nubot2 -> rival1 (intercepted),
  9 rival1 ground shot at the -x goal, 10.5 nubot1 to nubot4 (lost: it kicks again), 11 nubot1 lob from 6 m (shot),
  13 nubot4 (outside play), 16 rival2 at nobody (a clearance; nubot3 takes it), 18 nubot3 back to nubot1 (lost: own
  goal at 19);
- goals: 12 at +x (nubot, by nubot1), 19 at -x (rival, own goal by nubot3);
- runs: nubot2 3 m, nubot3 7 m, rival1 3 m with a 5 m teleport, rival2 only a 4 m teleport, others still;
- the world: the simulator's latched world description (18 x 12 m) first.

The timing match (0-10 s, play runs 1-9 s, model states at 100 Hz) tests the sample times: rival1 drives into
nubot1 twice, rival2 leaves the ball at 4 s and nubot3 reaches it at 7 s, nubot2 runs a circle, and nubot1 kicks
from x = 9.5 m straight at +x at 3 s (behind the goal line of an 18 m field, 1.5 m before that of a 22 m field).
"""

import dataclasses
import errno
import json
import math
import os
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag1 import Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from nubot_common.field import FieldGeometry
from nubot_common.world_description import WorldDescription
from nubot_match import match_analysis as ma
from nubot_match.bag_reader import MatchBagError, read_match
from nubot_tools.report import match_plots, match_report

MSG_DIR = Path(__file__).resolve().parents[2] / "nubot_common" / "msg"
WALL_START = 1_700_000_000.0  # bag (receive) times are wall time: the report must use sim time
RECEIVE_LAG = 0.001  # [s]
DT = 0.02  # model-state period [s]
END = 20.0


OLD_MODEL_STATES = """string[] name
geometry_msgs/Pose[] pose
geometry_msgs/Twist[] twist
"""  # before the header: bags of the simulator that stamped its model states with nothing


def nubot_typestore(old_model_states=False):
    store = get_typestore(Stores.ROS1_NOETIC)
    types = {}
    for path in sorted(MSG_DIR.glob("*.msg")):
        text = OLD_MODEL_STATES if old_model_states and path.stem == "ModelStates" else path.read_text()
        types.update(get_types_from_msg(text, f"nubot_common/msg/{path.stem}"))
    store.register(types)
    return store


STORE = nubot_typestore()
OLD_STORE = nubot_typestore(old_model_states=True)
T = STORE.types


def time_msg(t):
    sec = math.floor(t)
    return T["builtin_interfaces/msg/Time"](sec=sec, nanosec=round((t - sec) * 1e9))


def header(t):
    return T["std_msgs/msg/Header"](seq=0, stamp=time_msg(t), frame_id="world")


def point3(x, y, z=0.0):
    return T["nubot_common/msg/Point3d"](x=x, y=y, z=z)


def positions(t):
    """Planar position [m] of every model at sim time t."""
    return {
        "nubot1": (-8.0, 0.0),
        "nubot2": (-2.0 + 0.3 * min(t, 10.0), 1.0),
        "nubot3": (1.0, 0.5 * t) if t < 8.0 else (1.0 + 0.5 * (min(t, 14.0) - 8.0), 4.0),
        "nubot4": (-4.0, -3.0),
        "rival1": (3.0 + 0.5 * min(t, 4.0), -1.0) if t < 12.0 else (0.2 * min(max(t - 15.0, 0.0), 5.0), -1.0),
        "rival2": (6.0, 2.0) if t < 14.0 else (6.0, -2.0),
        "football": (4.0 * math.sin(0.3 * t), 3.0 * math.cos(0.2 * t)),
    }


def model_states(t, where=positions, stamped=True):
    """The states of every model at sim time t: ``where(t)`` gives the positions; without a header if not stamped."""
    names, poses, twists = [], [], []
    for name, (x, y) in where(t).items():
        names.append(name)
        poses.append(T["geometry_msgs/msg/Pose"](
            position=T["geometry_msgs/msg/Point"](x=x, y=y, z=0.0),
            orientation=T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)))
        zero = T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)
        twists.append(T["geometry_msgs/msg/Twist"](linear=zero, angular=zero))
    if stamped:
        return T["nubot_common/msg/ModelStates"](header=header(t), name=names, pose=poses, twist=twists)
    return OLD_STORE.types["nubot_common/msg/ModelStates"](name=names, pose=poses, twist=twists)


def world_description(world):
    def part(name, value):
        return T[f"nubot_common/msg/{name}"](**dataclasses.asdict(value))  # the message's fields are the dataclass's

    return T["nubot_common/msg/WorldDescription"](
        header=header(0.0), field=part("FieldGeometry", world.field), ball=part("BallBody", world.ball),
        robot=part("RobotBody", world.robot), ball_name=world.ball_name)


def strategy_info(t, robot):
    point = T["nubot_common/msg/Point2d"]
    pass_cmd = T["nubot_common/msg/PassCommands"](
        pass_id=0, catch_id=0, pass_pt=point(x=0.0, y=0.0), catch_pt=point(x=0.0, y=0.0), is_passout=False,
        is_dynamic_pass=False, is_static_pass=False, is_valid=False)
    return T["nubot_common/msg/StrategyInfo"](
        header=header(t), AgentID=int(robot[-1]), targetNum1=0, targetNum2=0, targetNum3=0, targetNum4=0,
        staticpassNum=0, staticcatchNum=0, role=0 if robot in GOALIES else 1, action=0, is_dribble=False,
        is_kickoff=False, role_time=t, pass_cmd=pass_cmd)


def game_state(t):
    running = 1.0 <= t < 12.0 or 14.0 <= t < 19.0
    game_time = min(max(t - 1.0, 0.0), 11.0) + min(max(t - 14.0, 0.0), 5.0)
    score = [int(t >= 12.0), int(t >= 19.0)]
    event = ("" if t < 1.0 else "kick-off for nubot" if t < 12.0 else "goal for nubot" if t < 14.0
             else "kick-off for rival" if t < 19.0 else "goal for rival")
    return T["nubot_common/msg/GameState"](
        header=header(t), teams=["nubot", "rival"], score=np.array(score, dtype=np.int32),
        attack=np.array([1, -1], dtype=np.int32), match_mode=np.array([15, 15], dtype=np.uint8), half=1,
        game_time=game_time, running=running, last_event=event)


TOUCHES = [(2.0, "nubot2"), (4.0, "nubot3"), (6.0, "nubot2"), (8.0, "rival1"), (10.0, "nubot1"), (13.0, "nubot4"),
           (15.0, "rival2"), (17.0, "nubot3")]
KICKS = [  # t, robot, kind, velocity, ball position (passes aimed at a teammate, the clearance at nobody)
    (3.0, "nubot2", -1, (3.0, 0.71), (-1.1, 1.0)),  # at nubot3 (1.0, 1.5)
    (5.0, "nubot3", -1, (-2.0, -2.0), (1.0, 2.5)),  # at nubot2 (-0.5, 1.0)
    (7.0, "nubot2", -1, (1.4, 2.9), (-0.2, 1.0)),  # at nubot3 (1.0, 3.5)
    (9.0, "rival1", -1, (-6.0, 0.5), (-5.0, 0.0)),
    (10.5, "nubot1", -1, (3.8, -3.3), (-7.5, 0.0)),  # at nubot4 (-4, -3)
    (11.0, "nubot1", 1, (4.0, 0.0), (3.0, 0.0)),
    (13.0, "nubot4", -1, (6.0, 0.0), (-4.0, -3.0)),
    (16.0, "rival2", -1, (8.0, 0.0), (6.0, -2.0)),
    (18.0, "nubot3", -1, (-8.0, 0.0), (-5.0, 0.0)),
]
GOALS = [(12.0, 1, "nubot1"), (19.0, -1, "nubot3")]
GOALIES = {"nubot1", "rival2"}  # announce the role GOALIE in their StrategyInfo; the others ACTIVE
COACH = [(0.5, "nubot", 1), (0.5, "rival", 2), (1.0, "nubot", 15), (1.0, "rival", 15)]


WORLD_TOPIC, WORLD_TYPE = "/sim_visual/world_description", "nubot_common/msg/WorldDescription"
WORLD = WorldDescription()  # the simulator's default: 18 x 12 m
WIDE = WorldDescription(field=FieldGeometry.msl_current())  # 22 x 14 m


def scripted_messages(referee=True, clock=True, world=WORLD):
    """Yield (topic, msgtype, sim time, message) in publication order."""
    if world is not None:
        yield WORLD_TOPIC, WORLD_TYPE, 0.0, world_description(world)
    events = []
    for t, robot in TOUCHES:
        events.append((t, "/sim_visual/ball_touch", "BallTouch",
                       T["nubot_common/msg/BallTouch"](header=header(t), robot=robot, ball_pos=point3(0.0, 0.0))))
    for t, robot, kind, (vx, vy), (x, y) in KICKS:
        events.append((t, "/sim_visual/kick", "KickEvent", T["nubot_common/msg/KickEvent"](
            header=header(t), robot=robot, kind=kind, velocity=point3(vx, vy, 3.0 if kind == 1 else 0.0),
            ball_pos=point3(x, y, 0.11))))
    for t, side, last in GOALS:
        events.append((t, "/sim_visual/goal", "GoalEvent", T["nubot_common/msg/GoalEvent"](
            header=header(t), side=side, ball_pos=point3(9.2 * side, 0.1, 0.2), last_touch=last)))
    for t in np.arange(0.0, END, 0.5):
        for robot in ("nubot1", "nubot2", "nubot3", "nubot4", "rival1", "rival2"):
            events.append((float(t), f"/{robot}/nubotcontrol/strategy", "StrategyInfo", strategy_info(float(t), robot)))
    if referee:
        for t in np.arange(0.0, END + 0.5, 1.0):
            events.append((float(t), "/referee/state", "GameState", game_state(float(t))))
        for t, team, mode in COACH:
            events.append((t, f"/{team}/receive_from_coach", "CoachInfo", T["nubot_common/msg/CoachInfo"](
                header=header(t), MatchMode=mode, MatchType=0, TestMode=0, pointA=T["nubot_common/msg/Point2d"](
                    x=0.0, y=0.0), pointB=T["nubot_common/msg/Point2d"](x=0.0, y=0.0), angleA=0, angleB=0, idA=0,
                idB=0, kickforce=0)))
    events.sort(key=lambda e: e[0])
    k = 0
    for step in range(round(END / DT) + 1):
        t = step * DT
        if clock:
            yield "/clock", "rosgraph_msgs/msg/Clock", t, T["rosgraph_msgs/msg/Clock"](clock=time_msg(t))
        while k < len(events) and events[k][0] <= t + 1e-9:
            te, topic, name, msg = events[k]
            yield topic, f"nubot_common/msg/{name}", te, msg
            k += 1
        yield "/sim_visual/model_states", "nubot_common/msg/ModelStates", t, model_states(t)


def write_bag(path, messages, store=STORE):
    connections = {}
    with Writer(path) as writer:
        for topic, msgtype, t, msg in messages:
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, msgtype, typestore=store)
            stamp = round((WALL_START + t + RECEIVE_LAG) * 1e9)
            writer.write(connections[topic], stamp, store.serialize_ros1(msg, msgtype))
    return path


@pytest.fixture(scope="module")
def match_bag(tmp_path_factory):
    return write_bag(tmp_path_factory.mktemp("match") / "match.bag", scripted_messages())


@pytest.fixture(scope="module")
def report(match_bag, tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    assert match_report.main([str(match_bag), "--out", str(out)]) == 0
    return out, json.loads((out / "report.json").read_text())


def test_report_has_the_scripted_score_and_goals(report):
    _, r = report
    assert r["teams"] == ["nubot", "rival"]
    assert r["score"] == {"nubot": 1, "rival": 1}
    assert r["score_from_referee"] == {"nubot": 1, "rival": 1}
    assert r["score_agrees"] is True
    assert [(g["t"], g["team"], g["last_touch"], g["own_goal"], g["half"], g["game_time"]) for g in r["goals"]] == [
        (12.0, "nubot", "nubot1", False, 1, 11.0), (19.0, "rival", "nubot3", True, 1, 16.0)]


def test_report_times_are_sim_times(report):
    _, r = report
    assert (r["start_s"], r["end_s"], r["duration_s"], r["running_time_s"]) == (0.0, 20.0, 20.0, 16.0)


def test_report_possession(report):
    _, r = report
    assert r["possession"] == {"nubot": {"share": round(11 / 16, 4), "seconds": 11.0},
                               "rival": {"share": 0.25, "seconds": 4.0},
                               "nobody": {"share": 0.0625, "seconds": 1.0}}


def test_report_passes_and_shots(report):
    _, r = report
    assert r["passes"] == {
        "nubot": {"tried": 5, "completed": 2, "failed": 3, "intercepted": 1, "lost": 2, "unresolved": 0},
        "rival": {"tried": 0, "completed": 0, "failed": 0, "intercepted": 0, "lost": 0, "unresolved": 0}}
    assert r["clearances"] == {"nubot": 0, "rival": 1}
    assert r["shots"] == {"nubot": 1, "rival": 1}
    assert r["kicks_outside_play"] == 1
    assert [(k["t"], k["pass"], k["receiver"]) for k in r["kicks"] if k["pass"]] == [
        (3.0, "completed", "nubot3"), (5.0, "completed", "nubot2"), (7.0, "intercepted", "rival1"),
        (10.5, "lost", ""), (18.0, "lost", "")]


def test_report_explains_the_shots_and_goals_with_the_goalies_the_strategies_announced(report):
    _, r = report
    shots = r["shot_report"]
    assert shots["goalies"] == {"nubot": "nubot1", "rival": "rival2"}  # rival2 announced GOALIE, not AgentID 1
    assert [(s["t"], s["robot"], s["kind"], s["outcome"], s["by"]) for s in shots["shots"]] == [
        (9.0, "rival1", "flat", "saved", "nubot1"), (11.0, "nubot1", "lob", "goal", "")]
    first, second = shots["goals"]
    assert (first["scorer"], first["cause"], first["shot"]["t"], first["height_at_line_m"]) == ("nubot1", "turnover",
                                                                                                 11.0, 0.2)
    assert first["goalie"]["robot"] == "rival2" and first["defenders"][0]["robot"] == "rival1"
    assert (second["scorer"], second["own_goal"], second["cause"], second["shot"]) == ("nubot3", True, "own goal",
                                                                                       None)


def test_report_referee_events_coach_commands_and_distances(report):
    _, r = report
    assert [(e["t"], e["event"]) for e in r["referee_events"]] == [
        (1.0, "kick-off for nubot"), (12.0, "goal for nubot"), (14.0, "kick-off for rival"), (19.0, "goal for rival")]
    assert [(c["t"], c["team"], c["match_mode"]) for c in r["coach_commands"]] == [
        (0.5, "nubot", 1), (0.5, "rival", 2), (1.0, "nubot", 15), (1.0, "rival", 15)]
    assert r["distance_run_m"] == {"nubot1": 0.0, "nubot2": 3.0, "nubot3": 7.0, "nubot4": 0.0, "rival1": 3.0,
                                   "rival2": 0.0}


def test_report_json_keys_and_pngs(report):
    out, r = report
    assert {"bag", "teams", "score", "score_from_referee", "goals", "possession", "passes", "shots",
            "referee_events", "distance_run_m", "collisions", "ball_reach", "hull_radius_m", "definitions", "files",
            "warnings"} <= set(r)
    assert r["warnings"] == []
    assert r["field"] == {"length_m": 18.0, "width_m": 12.0, "goal_width_m": 2.4, "source": "bag"}
    assert r["ball_time_in_play_s"] == 16.0  # the running time: the heat map covers all of it
    assert {"collisions", "ball_reach", "time", "ball_time_in_play"} <= set(r["definitions"])
    assert r["hull_radius_m"] == 0.26
    assert (r["collisions"]["total"], r["collisions"]["events"]) == (0, [])  # the scripted robots keep 2 m apart
    for name in ("heatmap.png", "trajectories.png", "shots.png"):
        data = (out / name).read_bytes()
        assert data.startswith(b"\x89PNG") and len(data) > 10_000


def test_summary_and_progress_are_printed(match_bag, tmp_path, capsys):
    assert match_report.main([str(match_bag), "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert "field 18 x 12 m, goals 2.4 m wide (bag's world description)" in out
    assert "running 16.0 s (ball samples cover 16.0 s of it)" in out
    assert "score: nubot 1 - rival 1  (referee agrees)" in out
    assert ("goal at 12.0 s: half 1 0:11 nubot: nubot1; lob 5.0 m/s from (+3.0, +0.0) attacking +x, 6.0 m out, "
            "0.20 m high at the line; turnover; goalie rival2 2.0 m off the line; nearest defenders rival1 1.0 m"
            ) in out
    assert "goal at 19.0 s: half 1 0:16 rival: own goal by nubot3; no shot, 0.20 m high at the line; own goal" in out
    assert "shots (on target; goal/saved/blocked/wide): nubot 1 (1; 1/0/0/0), rival 1 (1; 0/1/0/0)" in out
    assert "goals from: own goal 1, turnover 1" in out
    assert "passes completed/tried: nubot 2/5, rival 0/0" in out
    assert "nubot: nubot1 0.0, nubot2 3.0, nubot3 7.0, nubot4 0.0" in out
    assert "collisions: 0 (0.00 per running minute): opponents 0, nubot-nubot 0, rival-rival 0" in out
    assert "free balls reached: " in out
    assert err == ""  # a short bag: no progress lines


def test_summary_prints_collisions_and_ball_reach(tmp_path):
    t = np.arange(0, 301) / 30.0  # 0-10 s, all running

    def track(name, x, y):
        return ma.Track(name, t, np.column_stack([np.broadcast_to(x, t.shape), np.broadcast_to(y, t.shape)]))

    tracks = [track("football", 3.0, 0.0), track("nubot1", 0.0, 0.0),
              track("rival1", np.interp(t, [0.0, 2.1], [-2.0, -0.5]), 0.0),  # runs into nubot1 at 2.03 s
              track("nubot2", np.where(t < 4.0, 3.3, 6.0), 0.0),  # leaves the ball free at 4 s
              track("rival2", 3.0, np.where(t < 6.0, 3.0, 0.3))]  # reaches it at 6 s
    log = ma.MatchLog(tracks={tr.name: tr for tr in tracks}, start=0.0, end=10.0)
    lines = match_report.format_summary(ma.analyse(log, WORLD), tmp_path / "m.bag", tmp_path).splitlines()
    assert "  collisions: 1 (6.00 per running minute): opponents 1, nubot-nubot 0, rival-rival 0" in lines
    assert "  free balls reached: 1 (median 2.00 s, mean 2.00 s to reach); nubot 0, rival 1 (median 2.00 s)" in lines


def test_progress_is_reported_every_tenth_of_the_messages(match_bag):
    calls = []
    read_match(match_bag, lambda done, total, t: calls.append((done, total, t)))
    total = calls[0][1]
    assert len(calls) == 10 and calls[-1] == (total, total, 20.0)
    assert [10 * done // total for done, _, _ in calls] == list(range(1, 11))


def test_report_goes_next_to_the_bag_by_default(tmp_path):
    bag = write_bag(tmp_path / "match.bag", (m for m in scripted_messages() if m[2] <= 3.0))
    assert match_report.main([str(bag)]) == 0
    assert {"report.json", "heatmap.png", "trajectories.png"} <= {p.name for p in tmp_path.iterdir()}


def test_without_referee_and_clock_the_attack_option_credits_goals(tmp_path):
    bag = write_bag(tmp_path / "match.bag", scripted_messages(referee=False, clock=False))
    assert match_report.main([str(bag), "--out", str(tmp_path / "a")]) == 0
    default = json.loads((tmp_path / "a" / "report.json").read_text())
    assert default["score"] == {"nubot": 1, "rival": 1} and default["score_from_referee"] is None
    assert (default["start_s"], default["end_s"], default["running_time_s"]) == (0.0, 20.0, 20.0)
    assert "no referee state recorded" in default["warnings"][0]
    assert default["clearances"]["nubot"] == 1  # the 13 s kick is in play now: a clearance, aimed at nobody
    assert match_report.main([str(bag), "--out", str(tmp_path / "b"), "--attack", "nubot=-x"]) == 0
    swapped = json.loads((tmp_path / "b" / "report.json").read_text())
    assert [(g["team"], g["own_goal"]) for g in swapped["goals"]] == [("rival", True), ("nubot", False)]


def test_missing_bag_exits_2(tmp_path, capsys):
    assert match_report.main([str(tmp_path / "nope.bag")]) == 2
    assert f"match_report: error: no such bag file: {tmp_path / 'nope.bag'}" in capsys.readouterr().err


def test_bag_without_match_topics_exits_2(tmp_path, capsys):
    msg = T["std_msgs/msg/String"](data="hello")
    bag = write_bag(tmp_path / "chatter.bag", [("/chatter", "std_msgs/msg/String", 0.0, msg)])
    assert match_report.main([str(bag), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "has none of the expected topics" in err and "it has: /chatter" in err
    assert not (tmp_path / "out").exists()


def test_not_a_bag_exits_2(tmp_path, capsys):
    (tmp_path / "junk.bag").write_text("not a bag\n")
    assert match_report.main([str(tmp_path / "junk.bag")]) == 2
    assert "is not a readable ROS 1 bag" in capsys.readouterr().err


def test_read_match_raises_for_a_missing_bag(tmp_path):
    with pytest.raises(MatchBagError, match="no such bag file"):
        read_match(tmp_path / "nope.bag")


@pytest.mark.parametrize("argv", [["--attack", "nubot"], ["--attack", "nubot=+y"]])
def test_bad_attack_option_exits_2(match_bag, argv, capsys):
    with pytest.raises(SystemExit) as exit_info:
        match_report.main([str(match_bag), *argv])
    assert exit_info.value.code == 2
    assert "expected TEAM=+x or TEAM=-x" in capsys.readouterr().err


def test_bad_field_size_exits_2(match_bag, capsys):
    assert match_report.main([str(match_bag), "--goal-width", "0"]) == 2
    assert "match_report: error: bad field: goal_width must be positive, got 0.0" in capsys.readouterr().err


def test_unknown_field_exits_2(match_bag, tmp_path, capsys):
    assert match_report.main([str(match_bag), "--field", str(tmp_path / "nope.yaml"), "--out", str(tmp_path)]) == 2
    assert "bad field: no world description" in capsys.readouterr().err
    assert not (tmp_path / "report.json").exists()


def test_an_out_folder_below_a_file_exits_2_naming_it(match_bag, tmp_path, capsys):
    notes = tmp_path / "notes.txt"
    notes.write_text("not a folder\n")
    assert match_report.main([str(match_bag), "--out", str(notes / "report")]) == 2
    assert f"match_report: error: cannot write the report to {notes / 'report'}: Not a directory (choose " \
        "another folder with --out)" in capsys.readouterr().err
    assert [p.name for p in tmp_path.iterdir()] == ["notes.txt"] and notes.read_text() == "not a folder\n"


def test_a_report_that_cannot_be_finished_leaves_the_earlier_one_whole(match_bag, tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.json").write_text("the earlier report\n")

    def disk_full(*_args, **_kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(match_plots, "plot_trajectories", disk_full)  # report.json and heatmap.png made by then
    assert match_report.main([str(match_bag), "--out", str(out)]) == 2
    assert f"cannot write the report to {out}: No space left on device" in capsys.readouterr().err
    assert [p.name for p in out.iterdir()] == ["report.json"]
    assert (out / "report.json").read_text() == "the earlier report\n"


def test_field_flags_refine_the_bag_s_field(match_bag, tmp_path):
    assert match_report.main([str(match_bag), "--out", str(tmp_path), "--field-length", "20", "--goal-width",
                              "2.0"]) == 0
    r = json.loads((tmp_path / "report.json").read_text())
    assert r["field"] == {"length_m": 20.0, "width_m": 12.0, "goal_width_m": 2.0, "source": "flags", "refines": "bag"}


# --- the timing match: sample times, the world description ------------------------------------------------------

TIMING_END = 10.0
TIMING_DT = 0.01  # model states at 100 Hz [s]


def timing_positions(t):
    """Planar position [m] of every model of the timing match at sim time t."""
    return {
        "nubot1": (0.0, 0.0),
        "rival1": (float(np.interp(t, [0, 2.1, 4, 5, 6.1, 8, 9], [2.0, 0.5, 0.5, 1.0, 0.5, 0.5, 2.0])), 0.0),
        "nubot2": (-5.0 + 2.0 * math.cos(0.5 * t), 3.0 + 2.0 * math.sin(0.5 * t)),
        "rival2": (3.3 + 2.7 * min(max(t - 4.0, 0.0) / 0.5, 1.0), -3.0),  # leaves the ball at 4 s
        "nubot3": (3.0, -3.3 - 2.7 * min(max(7.0 - t, 0.0), 1.0)),  # reaches it at 7 s
        "football": (3.0, -3.0),
    }


def timing_state(t):
    running = 1.0 <= t < 9.0
    return T["nubot_common/msg/GameState"](
        header=header(t), teams=["nubot", "rival"], score=np.array([0, 0], dtype=np.int32),
        attack=np.array([1, -1], dtype=np.int32), match_mode=np.array([15, 15], dtype=np.uint8), half=1,
        game_time=min(max(t - 1.0, 0.0), 8.0), running=running, last_event="kick-off for nubot" if t >= 1.0 else "")


def timing_messages(stamped=True, clock_period=TIMING_DT, clock_lag=0.0, world=WORLD):
    """Yield the timing match: model states with header stamps (or none), /clock every ``clock_period`` [s]
    showing ``clock_lag`` [s] less than the sim time."""
    if world is not None:
        yield WORLD_TOPIC, WORLD_TYPE, 0.0, world_description(world)
    clock_every = round(clock_period / TIMING_DT)
    for step in range(round(TIMING_END / TIMING_DT) + 1):
        t = step * TIMING_DT
        if step % clock_every == 0:
            yield "/clock", "rosgraph_msgs/msg/Clock", t, T["rosgraph_msgs/msg/Clock"](
                clock=time_msg(max(t - clock_lag, 0.0)))
        if step % 50 == 0:
            yield "/referee/state", "nubot_common/msg/GameState", t, timing_state(t)
        if step == 300:
            yield "/sim_visual/kick", "nubot_common/msg/KickEvent", t, T["nubot_common/msg/KickEvent"](
                header=header(t), robot="nubot1", kind=-1, velocity=point3(6.0, 0.0), ball_pos=point3(9.5, 0.0, 0.11))
        yield "/sim_visual/model_states", "nubot_common/msg/ModelStates", t, model_states(t, timing_positions, stamped)


def report_of(folder, messages, *flags, store=STORE):
    folder.mkdir(parents=True, exist_ok=True)
    bag = write_bag(folder / "match.bag", messages, store)
    assert match_report.main([str(bag), "--out", str(folder), *flags]) == 0
    return json.loads((folder / "report.json").read_text())


@pytest.fixture(scope="module")
def good_stamps(tmp_path_factory):
    return report_of(tmp_path_factory.mktemp("good"), timing_messages())


def timed_events(r):
    """The statistics that depend on sample times, as a user reads them."""
    return ([(round(e["t"], 2), e["robots"]) for e in r["collisions"]["events"]],
            [(round(e["t_free"], 2), round(e["t_reached"], 2), e["robot"]) for e in r["ball_reach"]["events"]])


def test_the_timing_match_with_good_stamps(good_stamps):
    r = good_stamps
    assert (r["start_s"], r["end_s"], r["running_time_s"], r["ball_time_in_play_s"]) == (0.0, 10.0, 8.0, 8.0)
    # centres closer than 0.55 m after 2.03 s and 5.99 s (at the next samples); rival2 1.002 m from the ball at
    # 4.13 s; nubot3 within 0.45 m after 6.944 s
    assert timed_events(r) == ([(2.03, ["nubot1", "rival1"]), (5.99, ["nubot1", "rival1"])],
                               [(4.13, 6.95, "nubot3")])
    assert r["distance_run_m"]["nubot2"] == pytest.approx(10.0, abs=0.01)  # 2 m radius, 0.5 rad/s for 10 s


def test_model_states_sharing_clock_times_are_spread_out(good_stamps, tmp_path):
    # a bag of the simulator before ModelStates had a header, on a busy machine: /clock at 10 Hz while the model
    # states come at 100 Hz, so 9 in 10 consecutive samples got the same time from the latest /clock
    messages = timing_messages(stamped=False, clock_period=0.1)
    r = report_of(tmp_path, messages, store=OLD_STORE)
    assert r["running_time_s"] == 8.0
    assert r["ball_time_in_play_s"] == pytest.approx(r["running_time_s"], rel=0.03)
    assert r["distance_run_m"] == good_stamps["distance_run_m"]
    assert timed_events(r) == timed_events(good_stamps)
    assert r["collisions"]["per_minute"] == good_stamps["collisions"]["per_minute"]
    ball = read_match(tmp_path / "match.bag").tracks["football"]
    assert (np.diff(ball.t) > 0).all()  # no two samples share a time


def test_header_stamps_win_over_a_stale_clock(good_stamps, tmp_path):
    r = report_of(tmp_path, timing_messages(clock_lag=0.5))  # /clock shows 0.5 s less than the sim time
    assert (r["start_s"], r["end_s"], r["ball_time_in_play_s"]) == (0.0, 10.0, 8.0)
    assert timed_events(r) == timed_events(good_stamps)


def test_the_field_comes_from_the_bag_s_world_description(tmp_path):
    bag_field = report_of(tmp_path / "bag", timing_messages(world=WIDE))
    assert bag_field["field"] == {"length_m": 22.0, "width_m": 14.0, "goal_width_m": 2.4, "source": "bag"}
    assert bag_field["shots"] == {"nubot": 1, "rival": 0}  # from 9.5 m: 1.5 m before the 22 m field's goal line
    assert bag_field["warnings"] == []
    log = read_match(tmp_path / "bag" / "match.bag")
    assert log.world == WIDE
    fig = match_plots.plot_trajectories(log.tracks, ["nubot", "rival"], log.world.field, tmp_path / "traj.png")
    assert (fig.axes[0].get_xlim(), fig.axes[0].get_ylim()) == ((-12.0, 12.0), (-8.0, 8.0))


def test_the_field_option_overrides_the_bag_s(tmp_path, capsys):
    r = report_of(tmp_path, timing_messages(world=WIDE), "--field", "18x12")
    assert r["field"] == {"length_m": 18.0, "width_m": 12.0, "goal_width_m": 2.4, "source": "--field"}
    assert r["shots"] == {"nubot": 0, "rival": 0} and r["clearances"]["nubot"] == 1  # behind the goal line
    assert "field 18 x 12 m, goals 2.4 m wide (--field world description)" in capsys.readouterr().out


def test_without_a_world_description_the_default_field_is_used_and_said(tmp_path, capsys):
    r = report_of(tmp_path, timing_messages(world=None))
    assert r["field"] == {"length_m": 18.0, "width_m": 12.0, "goal_width_m": 2.4, "source": "default"}
    assert r["warnings"] == ["no world description in the bag (/sim_visual/world_description) and no --field: "
                             "using the default 18 x 12 m field"]
    out = capsys.readouterr().out
    assert "field 18 x 12 m, goals 2.4 m wide (default field: the bag has no world description)" in out
    assert "warning: no world description in the bag" in out


def test_an_invalid_world_description_is_ignored_with_a_warning(tmp_path, capsys):
    def broken(messages):
        for topic, msgtype, t, msg in messages:
            if topic == WORLD_TOPIC:
                msg.ball_name = "ball7"  # a robot's name
            yield topic, msgtype, t, msg

    r = report_of(tmp_path, broken(timing_messages()))
    assert r["field"]["source"] == "default"
    assert ("match_report: warning: ignored /sim_visual/world_description: ball_name must be a name not ending in a "
            "digit, got 'ball7'") in capsys.readouterr().err


def test_a_bag_whose_ball_is_never_seen_in_play_says_so(tmp_path):
    r = report_of(tmp_path, (m for m in timing_messages() if m[2] < 0.5))  # stops before play starts
    assert (r["running_time_s"], r["ball_time_in_play_s"]) == (0.0, 0.0)
    assert "no ball (football) position during running time" in r["warnings"][0]
    assert (tmp_path / "heatmap.png").stat().st_size > 10_000

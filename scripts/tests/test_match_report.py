"""Round trip of the match report: write a scripted match bag with the repo's messages, report, compare.

The scripted match (sim time, 0-20 s, nubot attacks +x, rival -x):

- play runs 1-12 s (kick-off nubot) and 14-19 s (kick-off rival); the referee stops it at each goal;
- touches: 2 nubot2, 4 nubot3, 6 nubot2, 8 rival1, 10 nubot1, 13 nubot4 (stopped), 15 rival2, 17 nubot3;
- kicks: 3 nubot2 -> nubot3 (completed), 5 nubot3 -> nubot2 (completed), 7 nubot2 -> rival1 (intercepted),
  9 rival1 ground shot at the -x goal, 10.5 nubot1 wide (lost: it kicks again), 11 nubot1 lob (shot),
  13 nubot4 (outside play), 16 rival2 -> nubot3 (intercepted), 18 nubot3 back (lost: own goal at 19);
- goals: 12 at +x (nubot, by nubot1), 19 at -x (rival, own goal by nubot3);
- runs: nubot2 3 m, nubot3 7 m, rival1 3 m with a 5 m teleport, rival2 only a 4 m teleport, others still.
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag1 import Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

import match_analysis as ma
import match_report

MSG_DIR = Path(__file__).resolve().parents[2] / "src" / "nubot_common" / "msg"
WALL_START = 1_700_000_000.0  # bag (receive) times are wall time: the report must use sim time
RECEIVE_LAG = 0.001  # [s]
DT = 0.02  # model-state period [s]
END = 20.0


def nubot_typestore():
    store = get_typestore(Stores.ROS1_NOETIC)
    types = {}
    for path in sorted(MSG_DIR.glob("*.msg")):
        types.update(get_types_from_msg(path.read_text(), f"nubot_common/msg/{path.stem}"))
    store.register(types)
    return store


STORE = nubot_typestore()
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


def model_states(t):
    names, poses, twists = [], [], []
    for name, (x, y) in positions(t).items():
        names.append(name)
        poses.append(T["geometry_msgs/msg/Pose"](
            position=T["geometry_msgs/msg/Point"](x=x, y=y, z=0.0),
            orientation=T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)))
        zero = T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)
        twists.append(T["geometry_msgs/msg/Twist"](linear=zero, angular=zero))
    return T["nubot_common/msg/ModelStates"](name=names, pose=poses, twist=twists)


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
KICKS = [  # t, robot, kind, velocity, ball position
    (3.0, "nubot2", -1, (0.5, 3.0), (-1.1, 1.0)),
    (5.0, "nubot3", -1, (-2.0, 1.0), (1.0, 2.5)),
    (7.0, "nubot2", -1, (1.0, -3.0), (-0.2, 1.0)),
    (9.0, "rival1", -1, (-6.0, 0.5), (-5.0, 0.0)),
    (10.5, "nubot1", -1, (5.0, 3.0), (-7.5, 0.0)),
    (11.0, "nubot1", 1, (4.0, 0.0), (-7.5, 0.0)),
    (13.0, "nubot4", -1, (6.0, 0.0), (-4.0, -3.0)),
    (16.0, "rival2", -1, (8.0, 0.0), (6.0, -2.0)),
    (18.0, "nubot3", -1, (-8.0, 0.0), (-5.0, 0.0)),
]
GOALS = [(12.0, 1, "nubot1"), (19.0, -1, "nubot3")]
COACH = [(0.5, "nubot", 1), (0.5, "rival", 2), (1.0, "nubot", 15), (1.0, "rival", 15)]


def scripted_messages(referee=True, clock=True):
    """Yield (topic, msgtype, sim time, message) in publication order."""
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


def write_bag(path, messages):
    connections = {}
    with Writer(path) as writer:
        for topic, msgtype, t, msg in messages:
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, msgtype, typestore=STORE)
            stamp = round((WALL_START + t + RECEIVE_LAG) * 1e9)
            writer.write(connections[topic], stamp, STORE.serialize_ros1(msg, msgtype))
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
        "rival": {"tried": 1, "completed": 0, "failed": 1, "intercepted": 1, "lost": 0, "unresolved": 0}}
    assert r["shots"] == {"nubot": 1, "rival": 1}
    assert r["kicks_outside_play"] == 1
    assert [(k["t"], k["pass"], k["receiver"]) for k in r["kicks"] if k["pass"]] == [
        (3.0, "completed", "nubot3"), (5.0, "completed", "nubot2"), (7.0, "intercepted", "rival1"),
        (10.5, "lost", ""), (16.0, "intercepted", "nubot3"), (18.0, "lost", "")]


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
    assert {"collisions", "ball_reach"} <= set(r["definitions"])
    assert r["hull_radius_m"] == 0.26
    assert (r["collisions"]["total"], r["collisions"]["events"]) == (0, [])  # the scripted robots keep 2 m apart
    for name in ("heatmap.png", "trajectories.png"):
        data = (out / name).read_bytes()
        assert data.startswith(b"\x89PNG") and len(data) > 10_000


def test_summary_and_progress_are_printed(match_bag, tmp_path, capsys):
    assert match_report.main([str(match_bag), "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert "score: nubot 1 - rival 1  (referee agrees)" in out
    assert "goal at 19.0 s for rival (own goal by nubot3, half 1 at 16.0 s game time)" in out
    assert "passes completed/tried: nubot 2/5, rival 0/1" in out
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
    lines = match_report.format_summary(ma.analyse(log, ma.FieldSize()), tmp_path / "m.bag", tmp_path).splitlines()
    assert "  collisions: 1 (6.00 per running minute): opponents 1, nubot-nubot 0, rival-rival 0" in lines
    assert "  free balls reached: 1 (median 2.00 s, mean 2.00 s to reach); nubot 0, rival 1 (median 2.00 s)" in lines


def test_progress_is_reported_every_tenth_of_the_messages(match_bag):
    calls = []
    match_report.read_match(match_bag, lambda done, total, t: calls.append((done, total, t)))
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
    assert default["passes"]["nubot"]["tried"] == 6  # the 13 s kick is in play now
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
    with pytest.raises(match_report.MatchReportError, match="no such bag file"):
        match_report.read_match(tmp_path / "nope.bag")


@pytest.mark.parametrize("argv", [["--attack", "nubot"], ["--attack", "nubot=+y"]])
def test_bad_attack_option_exits_2(match_bag, argv, capsys):
    with pytest.raises(SystemExit) as exit_info:
        match_report.main([str(match_bag), *argv])
    assert exit_info.value.code == 2
    assert "expected TEAM=+x or TEAM=-x" in capsys.readouterr().err


def test_bad_field_size_exits_2(match_bag, capsys):
    assert match_report.main([str(match_bag), "--goal-width", "0"]) == 2
    assert "field goal_width must be positive" in capsys.readouterr().err

"""The bag of a lockstep match: what the match report reads from it, what ROS 1's own tools make of it, and
what an interrupted match leaves behind.

One short two-vs-two match (two 10 s halves; seed 6: three kicks and a goal the referee disallows) is played once for
the module with a ``BagRecorder`` (robots' topics too) and a ``MatchLogRecorder``: the report read from the
bag must agree with the statistics of the log the engine handed over directly.
"""

import io
import json
import math
import re
import subprocess
import time

import pytest
import yaml
from rosbags.rosbag1 import Reader

from nubot_common import msg as nubot_msgs
from nubot_common.processes import RosMaster, wait_until
from nubot_match import NubotMatchError
from nubot_match import match_analysis as ma
from nubot_match.bag import TIME_MIN_NS, BagRecorder, RawClock, active_path, clock_msg
from nubot_match.bag_reader import read_match
from nubot_match.config import match_config
from nubot_match.engine import LockstepMatch
from nubot_match.record import MatchLogRecorder

HALF_SECONDS = 10.0
SEED = 6  # a match with kicks (no seed of 0..39 has a referee call in 2 x 10 s with today's teams: a call recorded in a
# bag and reported is tested on a real ROS match, coach4sim/test/integration/test_referee_node.py)
TEAM_POSES = [{"x": -8.4, "y": 0.0}, {"x": -1.0, "y": 0.5}]  # a goalie and a field player (team frame [m])
MATCH_TOPICS = {"/clock", "/sim_visual/model_states", "/sim_visual/world_description", "/referee/state",
                "/nubot/receive_from_coach", "/rival/receive_from_coach"}
ROBOT_TOPICS = ("omnivision/OmniVisionInfo", "worldmodel/worldmodelinfo", "nubotcontrol/strategy",
                "nubotcontrol/velcmd")
EVENT_TOPICS = {"/sim_visual/goal", "/sim_visual/kick", "/sim_visual/ball_touch", "/sim_visual/ball_holder",
                "/referee/foul"}  # only when they happen


@pytest.fixture(scope="module")
def played(tmp_path_factory):
    """The module's match: (bag, its recorder, the direct MatchLog, the world, the engine)."""
    folder = tmp_path_factory.mktemp("match")
    teams = []
    for prefix, attack in (("nubot", 1), ("rival", -1)):
        teams.append(folder / f"{prefix}.yaml")
        teams[-1].write_text(yaml.safe_dump({"name": prefix.title(), "prefix": prefix, "attack": attack,
                                             "goalie": 1, "robots": TEAM_POSES}))
    bag = folder / "match.bag"
    config = match_config(*teams, half_seconds=HALF_SECONDS, halves=2)
    recorder, direct = BagRecorder(bag), MatchLogRecorder()
    match = LockstepMatch(config, [recorder, direct])
    match.reset(SEED)
    match.run()
    match.close()
    return bag, recorder, direct.finish(), config.world, match


@pytest.fixture(scope="module")
def short_config():
    return match_config(half_seconds=4.0, halves=1)


def _close_to(a, b, tol=2e-3):
    """Nested JSON equality, floats within ``tol`` (bag times are ns and kick velocities float32)."""
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_close_to(a[k], b[k], tol) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_close_to(x, y, tol) for x, y in zip(a, b))
    if isinstance(a, float) or isinstance(b, float):
        return isinstance(a, (int, float)) and isinstance(b, (int, float)) and math.isclose(a, b, abs_tol=tol)
    return a == b


# --- read back -------------------------------------------------------------------------------------------
def test_the_bag_read_back_gives_the_statistics_of_the_match_log(played):
    bag, _recorder, log, world, match = played
    read = read_match(bag)
    assert read.world == world
    report = json.loads(json.dumps(ma.analyse(read, read.world).to_json()))  # as report.json holds it
    direct = ma.analyse(log, world).to_json()
    assert report["score"] == direct["score"] == dict(zip(match.state().teams, match.state().score))
    assert report["score_agrees"]
    assert report["end_s"] == pytest.approx(match.time, abs=0.02)
    for key in ("goals", "goals_outside_play", "passes", "shots", "kicks", "kicks_outside_play", "referee_events",
                "coach_commands", "possession", "distance_run_m", "running_time_s", "fouls", "referee_calls"):
        assert _close_to(report[key], direct[key]), (key, report[key], direct[key])
    assert report["kicks"], "the match should have kicks to compare"
    assert [c["kind"] for c in report["referee_calls"]] == [c.kind for c in log.calls]
    assert len(report["referee_events"]) >= 4  # both halves begin and end
    assert report["collisions"]["total"] == direct["collisions"]["total"]


# --- ROS 1's own tools ----------------------------------------------------------------------------------
def test_rosbag_reads_every_message_with_the_generated_types(played):
    import rosbag  # Debian's python3-rosbag: the reference reader

    bag, recorder, _log, _world, match = played
    robots = list(match.agents)
    expected = MATCH_TOPICS | {f"/{r}/{t}" for r in robots for t in ROBOT_TOPICS}
    with rosbag.Bag(str(bag)) as reader:
        info = reader.get_type_and_topic_info()
        assert expected <= set(info.topics) <= expected | EVENT_TOPICS
        for topic, entry in info.topics.items():
            name = entry.msg_type.split("/")[1]
            generated = getattr(nubot_msgs, name, None) or clock_msg(0.0)
            assert (entry.msg_type, info.msg_types[entry.msg_type]) == (generated._type, generated._md5sum), topic
        count, last = 0, {}
        for topic, msg, t in reader.read_messages():
            count += 1
            assert t.to_nsec() >= max(last.get(topic, 0), TIME_MIN_NS), topic  # rosbag play drops time 0
            last[topic] = t.to_nsec()
            if topic == "/sim_visual/model_states":
                # the stamp is genpy's (truncated to ns), the bag time rounded to ns
                assert abs((msg.header.stamp - t).to_nsec()) <= 1 and len(msg.name) == len(robots) + 1
    assert count == recorder.messages
    with Reader(bag) as reader:  # a late subscriber to rosbag play still gets the world: it is latched
        assert {c.topic for c in reader.connections if c.ext.latching} == {"/sim_visual/world_description"}


def test_rosbag_info_describes_the_bag(played):
    bag, recorder, _log, _world, match = played
    done = subprocess.run(["rosbag", "info", "--yaml", str(bag)], capture_output=True, text=True, timeout=30)
    assert done.returncode == 0, done.stderr
    info = yaml.safe_load(done.stdout)
    assert info["messages"] == recorder.messages
    assert info["duration"] == pytest.approx(match.time, abs=0.02)
    states = next(t for t in info["topics"] if t["topic"] == "/sim_visual/model_states")
    assert states["type"] == "nubot_common/ModelStates"


@pytest.mark.integration
def test_rosbag_play_publishes_the_model_states(played, tmp_path):
    bag = played[0]
    with RosMaster(tmp_path / "ros") as master:
        echo = master.launch("echo", ["rostopic", "echo", "-n", "3", "/sim_visual/model_states/header/stamp"])
        world = master.launch("world", ["rostopic", "echo", "-n", "1", "/sim_visual/world_description/ball_name"])
        time.sleep(1.0)  # the subscribers register before the first message is played
        play = master.launch("play", ["rosbag", "play", "--clock", "-q", "-d", "0.5", "-u", "2", str(bag)])
        wait_until(lambda: not echo.alive() and not world.alive(), 20.0,
                   f"model states and the world description from rosbag play:\n{play.log_text()[-2000:]}")
        stamps = re.findall(r"secs: (\d+)\s+nsecs:\s+(\d+)", echo.log_text())
        seconds = [int(secs) + int(nsecs) * 1e-9 for secs, nsecs in stamps]
        assert len(seconds) == 3 and seconds == sorted(seconds) and 0.0 < seconds[0] < 2.0, echo.log_text()
        assert "ball" in world.log_text()


# --- interrupted matches and misuse -------------------------------------------------------------------
def _play_until(config, recorder, until):
    match = LockstepMatch(config, [recorder])
    match.reset(SEED)
    match.run(until=until)
    return match


def test_a_recorder_closed_mid_match_leaves_a_readable_bag(short_config, tmp_path):
    bag = tmp_path / "cut.bag"
    recorder = BagRecorder(bag, robots=False)
    _play_until(short_config, recorder, 1.0)
    assert active_path(bag).exists() and not bag.exists()
    recorder.close()
    recorder.close()  # idempotent
    assert bag.exists() and not active_path(bag).exists()
    with Reader(bag) as reader:
        topics = {c.topic for c in reader.connections}
        assert MATCH_TOPICS - {"/rival/receive_from_coach", "/nubot/receive_from_coach"} <= topics
        assert not any("/nubotcontrol/" in t or "/omnivision/" in t for t in topics)  # robots=False
        assert reader.duration == pytest.approx(1.0e9, abs=2e7)
    log = read_match(bag)
    assert log.world == short_config.world and log.end == pytest.approx(1.0, abs=0.02)


def test_a_recorder_never_closed_leaves_no_bag_under_its_final_name(short_config, tmp_path):
    bag = tmp_path / "lost.bag"
    _play_until(short_config, BagRecorder(bag, robots=False), 0.5)
    assert not bag.exists() and active_path(bag).exists()


def test_an_existing_bag_is_never_overwritten(tmp_path):
    bag = tmp_path / "old.bag"
    bag.write_bytes(b"earlier match")
    with pytest.raises(NubotMatchError, match="old.bag exists already"):
        BagRecorder(bag)
    active_path(tmp_path / "busy.bag").write_bytes(b"")
    with pytest.raises(NubotMatchError, match=r"busy.bag.active exists already"):
        BagRecorder(tmp_path / "busy.bag")
    assert bag.read_bytes() == b"earlier match"


def test_a_bag_holds_one_match_and_nothing_after_close(short_config, tmp_path):
    with BagRecorder(tmp_path / "one.bag") as recorder:
        recorder.start(short_config.world, 0.0)
        with pytest.raises(NubotMatchError, match="holds one match"):
            recorder.start(short_config.world, 0.0)
    assert recorder.closed and (tmp_path / "one.bag").exists()
    with pytest.raises(NubotMatchError, match="one.bag is closed"):
        recorder.clock(1.0)


def test_the_hand_made_clock_is_rosgraph_msgs_clock():
    from rosgraph_msgs.msg import Clock

    from nubot_common.conversions import stamp

    for t in (0.0, 0.005, 12.34, 3600.999999999):
        raw, reference = io.BytesIO(), io.BytesIO()
        RawClock(t).serialize(raw)
        Clock(clock=stamp(t)).serialize(reference)
        assert raw.getvalue() == reference.getvalue()
    assert (RawClock._type, RawClock._md5sum) == (Clock._type, Clock._md5sum)
    assert RawClock._full_text.strip() == Clock._full_text.strip().splitlines()[-1]  # past its comments

"""Replay without a browser: a lockstep match's bag becomes a timeline of drawn frames with its marks; the replay
clock plays, pauses, seeks and changes speed; bad bags and bad controls get clear errors."""

import json

import pytest
from rosbags.rosbag1 import Reader, Writer

from coach4sim.viewer_server import ViewerInputError
from nubot_common.world_description import WorldDescription
from nubot_match.bag import BagRecorder
from nubot_match.bag_reader import MatchBagError
from nubot_match.config import match_config
from nubot_match.engine import LockstepMatch
from nubot_tools.replay import ReplayBackend, ReplayClock, load_timeline, main


@pytest.fixture(scope="module")
def bag(tmp_path_factory):
    path = tmp_path_factory.mktemp("replay") / "match.bag"
    match = LockstepMatch(match_config(half_seconds=4.0, halves=1), [BagRecorder(path)])
    match.reset(1)
    match.run()
    match.close()
    return path


def test_a_lockstep_bag_becomes_frames_at_the_rate_with_the_referee_s_decisions_as_marks(bag):
    timeline = load_timeline(bag, rate=20.0)
    span = timeline.end - timeline.start
    assert span > 6.0  # the kickoff's setup, then 4 s of play
    assert len(timeline.frames) == pytest.approx(span * 20.0, rel=0.05)
    first, last = json.loads(timeline.frames[0]), json.loads(timeline.frames[-1])
    assert len(first["robots"]) == 10 and first["ball"] is not None
    assert {r["role"] for r in last["robots"]} - {None}, "roles from the robots' strategy topics"
    texts = [m.text for m in timeline.marks]
    assert any("kickoff" in t for t in texts) and any("end of the match" in t for t in texts)
    assert timeline.at(timeline.start - 5.0) == timeline.frames[0] and timeline.at(1e9) == timeline.frames[-1]
    assert last["referee"]["half"] == 1 and not last["referee"]["running"]


def test_a_bag_without_the_world_description_replays_on_the_default_field_with_a_warning(bag, tmp_path):
    """An older bag or a partial recording: no /sim_visual/world_description (the reader must not be handed an empty
    selection, which it takes for every topic)."""
    partial = tmp_path / "partial.bag"
    with Reader(bag) as source, Writer(partial) as out:
        kept = {c.id: out.add_connection(c.topic, c.msgtype, msgdef=c.msgdef.data, md5sum=c.digest)
                for c in source.connections if c.topic != "/sim_visual/world_description"}
        for conn, stamp, raw in source.messages(connections=[c for c in source.connections if c.id in kept]):
            out.write(kept[conn.id], stamp, raw)
    timeline = load_timeline(partial)
    assert timeline.world == WorldDescription() and len(timeline.frames) == len(load_timeline(bag).frames)
    assert timeline.warnings == ["no world description in the bag (/sim_visual/world_description): drawing the "
                                 "default 18 x 12 m field"]


def test_the_replay_clock_plays_pauses_seeks_and_stops_at_the_end():
    now = [100.0]
    clock = ReplayClock(10.0, 20.0, lambda: now[0])
    assert clock.t() == 10.0 and not clock.playing
    clock.play()
    now[0] += 2.0
    assert clock.t() == pytest.approx(12.0)
    clock.set_speed(4.0)
    now[0] += 1.0
    assert clock.t() == pytest.approx(16.0)
    clock.pause()
    now[0] += 5.0
    assert clock.t() == pytest.approx(16.0)
    clock.seek(-3.0)
    assert clock.t() == 10.0  # clamped to the span
    clock.seek(19.0)
    clock.play()
    now[0] += 1.0
    assert clock.t() == 20.0 and not clock.playing  # the end stops it
    clock.play()
    assert clock.t() == 10.0, "play at the end starts again"
    with pytest.raises(ViewerInputError, match="speed"):
        clock.set_speed(1000.0)


def test_the_backend_adds_where_the_replay_is_to_each_frame_and_refuses_commands(bag):
    backend = ReplayBackend(load_timeline(bag), "match.bag")
    hello = backend.hello()
    assert hello["mode"] == "replay" and hello["teams"] == ["nubot", "rival"] and hello["replay"]["marks"]
    backend.control({"type": "replay", "action": "seek", "t": backend.timeline.start + 3.0})
    frame = json.loads(backend.frame(""))
    assert frame["replay"] == {"t": pytest.approx(backend.timeline.start + 3.0, abs=1e-3), "playing": False,
                               "speed": 1.0}
    assert abs(frame["t"] - frame["replay"]["t"]) <= 0.05 + 1e-9
    assert backend.command(None, "nubot")[0] is False
    with pytest.raises(ViewerInputError, match="needs"):
        backend.control({"type": "replay", "action": "seek"})


def test_bags_that_cannot_be_replayed_get_one_clear_line(tmp_path, capsys):
    assert main([str(tmp_path / "nothing.bag")]) == 2
    assert "no such bag file" in capsys.readouterr().err
    junk = tmp_path / "junk.bag"
    junk.write_bytes(b"not a bag at all")
    assert main([str(junk)]) == 2
    assert "not a readable ROS 1 bag" in capsys.readouterr().err
    with pytest.raises(MatchBagError, match="no such bag"):
        load_timeline(tmp_path / "nothing.bag")

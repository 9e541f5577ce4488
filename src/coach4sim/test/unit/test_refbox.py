"""Unit tests of the RefBox protocol core (coach4sim.refbox): the stream decoder, the command mapping for both
teams, the worldstate builder and its validator, and the connection's bookkeeping."""

import json
import math
import re

import pytest

from coach4sim.refbox import (
    BALL_KEYS,
    COMMAND_RULES,
    OBSTACLE_KEYS,
    ROBOT_KEYS,
    WORLDSTATE_KEYS,
    Backoff,
    BallSnapshot,
    CommandKind,
    FrameDecoder,
    ObstacleSnapshot,
    OutageLog,
    RateMeter,
    RefboxClientParams,
    RefboxCommand,
    RefboxError,
    RobotSnapshot,
    TeamIdentity,
    build_worldstate,
    check_worldstate,
    choose_ball,
    encode_message,
    map_command,
    merge_obstacles,
    parse_command,
    team_book,
    worldstate_problems,
)
from nubot_common.match_mode import MatchMode as M
from nubot_common.params import from_mapping

US = TeamIdentity("224.16.32.53", "NuBot")
THEM = "224.16.32.127"

# Every command of the box, targeted at us, at the other team and at nobody: our MatchMode (None: no game command).
# The mapping decided in coach4sim.refbox, written out so that a change to it must change this table too.
MAPPING = {
    # command: (for us, for them, no target)
    "START": (M.STARTROBOT, M.STARTROBOT, M.STARTROBOT),
    "STOP": (M.STOPROBOT, M.STOPROBOT, M.STOPROBOT),
    "DROP_BALL": (M.DROPBALL, M.DROPBALL, M.DROPBALL),
    "PARK": (M.PARKINGROBOT, M.PARKINGROBOT, M.PARKINGROBOT),
    "END_PART": (M.STOPROBOT, M.STOPROBOT, M.STOPROBOT),
    "RESET": (M.STOPROBOT, M.STOPROBOT, M.STOPROBOT),
    "HALF_TIME": (M.STOPROBOT, M.STOPROBOT, M.STOPROBOT),
    "END_GAME": (M.STOPROBOT, M.STOPROBOT, M.STOPROBOT),
    "GAMEOVER": (M.STOPROBOT, M.STOPROBOT, M.STOPROBOT),
    "KICKOFF": (M.OUR_KICKOFF, M.OPP_KICKOFF, None),
    "FREEKICK": (M.OUR_FREEKICK, M.OPP_FREEKICK, None),
    "GOALKICK": (M.OUR_GOALKICK, M.OPP_GOALKICK, None),
    "THROWIN": (M.OUR_THROWIN, M.OPP_THROWIN, None),
    "CORNER": (M.OUR_CORNERKICK, M.OPP_CORNERKICK, None),
    "PENALTY": (M.OUR_PENALTY, M.OPP_PENALTY, None),
    **{name: (None, None, None) for name in (
        "WELCOME", "GOAL", "SUBGOAL", "FIRST_HALF", "SECOND_HALF", "FIRST_HALF_OVERTIME", "SECOND_HALF_OVERTIME",
        "YELLOW_CARD", "RED_CARD", "DOUBLE_YELLOW", "REPAIR", "SUBSTITUTION", "TESTMODE_ON", "TESTMODE_OFF")},
}


def frames(decoder, *chunks):
    out = []
    for chunk in chunks:
        out += decoder.feed(chunk)
    return out


# --- the wire ------------------------------------------------------------------------------------------------
def test_a_message_is_compact_json_and_a_zero_byte_and_decodes_back():
    data = encode_message({"command": "KICKOFF", "targetTeam": US.address})
    assert data == b'{"command":"KICKOFF","targetTeam":"224.16.32.53"}\0'
    [frame] = FrameDecoder().feed(data)
    assert (frame.message, frame.error) == ({"command": "KICKOFF", "targetTeam": "224.16.32.53"}, "")


def test_nan_is_refused_before_it_reaches_the_box():
    with pytest.raises(RefboxError, match="cannot encode the message as JSON: Out of range float values"):
        encode_message({"ageMs": math.nan})


def test_a_message_split_over_many_reads_comes_out_once_when_its_zero_byte_arrives():
    data = encode_message({"command": "START", "targetTeam": ""})
    decoder = FrameDecoder()
    pieces = [data[i:i + 3] for i in range(0, len(data), 3)]
    assert all(decoder.feed(piece) == [] for piece in pieces[:-1])
    assert decoder.pending == len(data) - len(pieces[-1])
    [frame] = decoder.feed(pieces[-1])
    assert frame.message == {"command": "START", "targetTeam": ""}
    assert decoder.pending == 0


def test_several_messages_in_one_read_come_out_in_order_and_a_tail_waits():
    commands = ["STOP", "THROWIN", "START"]
    data = b"".join(encode_message({"command": c}) for c in commands) + b'{"command": "PA'
    decoder = FrameDecoder()
    assert [f.message["command"] for f in decoder.feed(data)] == commands
    assert [f.message["command"] for f in decoder.feed(b'RK"}\0')] == ["PARK"]
    assert (decoder.messages, decoder.errors) == (4, 0)


def test_empty_frames_between_messages_are_skipped_silently():
    decoder = FrameDecoder()
    assert [f.message for f in decoder.feed(b'\0\0 \0{"command":"STOP"}\0\0')] == [{"command": "STOP"}]
    assert decoder.errors == 0


@pytest.mark.parametrize(("raw", "error"), [
    (b'{"command": "STOP"', r"malformed JSON \(Expecting ',' delimiter at character 18\): '\{\"command\": \"STOP\"'"),
    (b"KICKOFF", r"malformed JSON \(Expecting value at character 0\): 'KICKOFF'"),
    (b'["STOP"]', r"JSON list, not an object: '\[\"STOP\"\]'"),
    (b"\xff\xfe{}", r"message is not UTF-8 \(invalid start byte at byte 0\)"),
    (b'{"robotID": ' + b"9" * 5000 + b"}", r"JSON that cannot be decoded \(Exceeds the limit .*"),
    (b"[" * 40000 + b"]" * 40000, r"JSON nested 40000 deep, more than 32: .*"),
    (b'{"ageMs": Infinity}', r"malformed JSON \(Infinity is not a JSON number.*|.*Infinity is not a JSON number.*"),
], ids=["unterminated_object", "bare_word", "list", "not_utf8", "huge_integer", "deep_nesting", "infinity"])
def test_a_malformed_message_is_an_error_frame_counted_and_the_stream_goes_on(raw, error):
    decoder = FrameDecoder()
    bad, good = frames(decoder, raw + b"\0" + encode_message({"command": "START"}))
    assert bad.message is None and bad.size == len(raw)
    assert re.fullmatch(error, bad.error), bad.error
    assert good.message == {"command": "START"}
    assert (decoder.messages, decoder.errors) == (1, 1)


def test_an_oversized_message_is_dropped_up_to_its_zero_byte_even_across_reads():
    decoder = FrameDecoder(max_size=1000)
    out = frames(decoder, b'{"command": "' + b"x" * 600, b"y" * 600, b"z" * 5000,
                 b'zz"}\0' + encode_message({"command": "STOP"}))
    assert [f.error for f in out] == ["message longer than 1000 bytes without its zero byte; dropped up to the next "
                                      "zero byte", ""]
    assert out[1].message == {"command": "STOP"}
    assert (decoder.messages, decoder.errors, decoder.pending) == (1, 1, 0)


def test_an_oversized_message_ending_in_the_same_read_does_not_swallow_the_next():
    decoder = FrameDecoder(max_size=100)
    out = decoder.feed(b"a" * 200 + b"\0" + encode_message({"command": "STOP"}))
    assert [f.message for f in out] == [None, {"command": "STOP"}]


def test_a_message_of_exactly_the_limit_passes():
    message = {"command": "STOP", "pad": "p" * 50}
    size = len(encode_message(message)) - 1
    assert FrameDecoder(max_size=size).feed(encode_message(message))[0].message == message
    assert FrameDecoder(max_size=size - 1).feed(encode_message(message))[0].message is None


def test_a_tiny_limit_is_refused():
    with pytest.raises(RefboxError, match="max_size must be a whole number of bytes of at least 2, got 1"):
        FrameDecoder(max_size=1)


# --- commands -----------------------------------------------------------------------------------------------
def test_parse_command_reads_the_fields_and_normalises_the_name():
    assert parse_command({"command": " kickoff ", "targetTeam": " 224.16.32.53 ", "robotID": 3}) == \
        RefboxCommand("KICKOFF", "224.16.32.53", 3)
    assert parse_command({"command": "START"}) == RefboxCommand("START", "", None)
    assert parse_command({"command": "START", "targetTeam": None}).target_team == ""


@pytest.mark.parametrize(("message", "error"), [
    ({"targetTeam": ""}, 'a command message needs a non-empty string "command"'),
    ({"command": 7}, 'a command message needs a non-empty string "command"'),
    ({"command": "KICKOFF", "targetTeam": 53}, '"targetTeam" must be a string, got 53'),
    ({"command": "REPAIR", "robotID": "2"}, "\"robotID\" must be a whole number, got '2'"),
    ({"command": "REPAIR", "robotID": True}, '"robotID" must be a whole number, got True'),
])
def test_parse_command_refuses_missing_or_mistyped_fields(message, error):
    with pytest.raises(RefboxError, match=re.escape(error)):
        parse_command(message)


def test_the_mapping_table_covers_every_command_of_the_box_and_nothing_else():
    assert sorted(COMMAND_RULES) == sorted(MAPPING)
    assert len(MAPPING) == 29


@pytest.mark.parametrize("name", sorted(MAPPING))
def test_every_command_maps_for_our_team_by_target(name):
    ours, theirs, nobody = MAPPING[name]
    for target, expected in ((US.address, ours), ("NUBOT", ours), (THEM, theirs), ("", nobody)):
        effect = map_command(RefboxCommand(name, target), US)
        assert effect.mode == expected, (name, target, effect.text)
        assert effect.known
        if expected is None:
            assert name in effect.text and ("no game command" in effect.text or "ignored" in effect.text)


@pytest.mark.parametrize("name", sorted(MAPPING))
def test_when_both_teams_are_ours_the_other_team_gets_the_mirror_of_every_command(name):
    """nubot is the box's team A (our address), rival its team B: whoever the box names, the two agree."""
    ours, theirs, _ = MAPPING[name]
    for target, nubot_mode, rival_mode in ((US.address, ours, theirs), (THEM, theirs, ours)):
        effect = map_command(RefboxCommand(name, target), US)
        if effect.mode is None:
            assert nubot_mode is None and rival_mode is None
            continue
        book = team_book(("nubot", "rival"))
        book.command("nubot", effect.mode)
        assert {t.spec.prefix: t.mode for t in book.teams} == {"nubot": nubot_mode, "rival": rival_mode}


def test_a_single_team_gets_only_its_own_command_and_a_repeated_one_keeps_the_previous():
    book = team_book(("nubot",))
    book.command("nubot", M.OUR_CORNERKICK)
    book.command("nubot", M.STARTROBOT)
    book.command("nubot", M.STARTROBOT)
    assert [(t.spec.prefix, t.mode, t.previous) for t in book.teams] == [("nubot", M.STARTROBOT, M.OUR_CORNERKICK)]


def test_the_robot_id_of_a_card_is_reported_and_changes_nothing():
    effect = map_command(RefboxCommand("YELLOW_CARD", US.address, 3), US)
    assert effect.mode is None
    assert effect.text == ("YELLOW_CARD for 224.16.32.53 robot 3: no game command (a card; a robot sent off is "
                           "taken off the field by hand)")


def test_an_unknown_command_is_ignored_and_says_so():
    effect = map_command(RefboxCommand("WORLD_STATE"), US)
    assert (effect.mode, effect.known, effect.text) == (None, False, "WORLD_STATE: unknown command, ignored")


def test_rule_kinds_agree_with_their_modes():
    for name, rule in COMMAND_RULES.items():
        assert (rule.mode is None) == (rule.kind is CommandKind.NONE), name
        if rule.kind is CommandKind.SET_PIECE:
            assert rule.mode.is_ours, name


def test_our_team_is_known_by_address_or_name_and_never_by_an_empty_target():
    assert US.is_us("224.16.32.53") and US.is_us("nubot") and not US.is_us("") and not US.is_us("224.16.32.5")
    assert TeamIdentity(name="NuBot").is_us("NUBOT") and not TeamIdentity(name="NuBot").is_us("")
    with pytest.raises(RefboxError, match="our team needs an address or a name as the box knows it"):
        TeamIdentity(" ", "")


# --- the worldstate -----------------------------------------------------------------------------------------
def robot(agent=1, **kwargs):
    values = {"x": -2.0, "y": 1.0, "theta": 0.5, "vx": 1.0, "vy": -0.5, "omega": 0.25, "target": (3.0, -1.0),
              "intention": "ACTIVE", "holding": True, "battery_level": 87.5}
    values.update(kwargs)
    return RobotSnapshot(agent, **values)


def test_the_worldstate_has_exactly_the_required_keys_and_passes_the_validator():
    ball = choose_ball([BallSnapshot(1.0, 2.0, 0.5, 0.0, own=True, stamp=1.0)])
    message = build_worldstate("NuBot", "OUR_KICKOFF", 42.4, [robot(2), robot(1, holding=False)], ball,
                               [ObstacleSnapshot(4.0, -1.0, 0.25, 0.5)])
    assert tuple(message) == WORLDSTATE_KEYS
    assert [tuple(r) for r in message["robots"]] == [ROBOT_KEYS, ROBOT_KEYS]
    assert tuple(message["balls"][0]) == BALL_KEYS and tuple(message["obstacles"][0]) == OBSTACLE_KEYS
    assert worldstate_problems(message) == []
    assert (message["type"], message["teamName"], message["intention"], message["ageMs"]) == \
        ("worldstate", "NuBot", "OUR_KICKOFF", 42)
    assert [r["id"] for r in message["robots"]] == [1, 2], "sorted by AgentID"
    json.loads(encode_message(message)[:-1])  # the box gets plain JSON


def test_the_worldstate_is_in_the_box_axes_y_towards_the_attacked_goal_x_to_the_right():
    """Team frame (+x attacked goal, +y left) -> the box's (+y attacked goal, +x right); headings keep their
    number (0 faces the attacked goal in both)."""
    ball = choose_ball([BallSnapshot(5.0, -2.0, 1.5, 0.5, own=False, stamp=1.0)])
    message = build_worldstate("NuBot", "", 0.0, [robot()], ball, [ObstacleSnapshot(4.0, 3.0, 0.25, 1.0, 0.2, 0.1)])
    r = message["robots"][0]
    assert r["pose"] == [-1.0, -2.0, 0.5]
    assert r["targetPose"] == [1.0, 3.0, 0.5], "the target, facing as the robot does now"
    assert r["velocity"] == [0.5, 1.0, 0.25]
    assert (r["intention"], r["batteryLevel"], r["ballEngaged"]) == ("ACTIVE", 87.5, 1)
    assert message["balls"] == [{"position": [2.0, 5.0, 0.0], "velocity": [-0.5, 1.5, 0.0], "confidence": 0.5}]
    assert message["obstacles"] == [{"position": [-3.0, 4.0], "radius": 0.25, "velocity": [-0.1, 0.2],
                                     "confidence": 1.0}]


def test_numbers_are_rounded_to_a_millimetre_and_a_robot_without_target_aims_where_it_stands():
    message = build_worldstate("NuBot", "", 12.6, [robot(x=1.23456, y=-0.0004, theta=-0.00002, target=None)])
    r = message["robots"][0]
    assert r["pose"] == [0.0, 1.235, 0.0] and r["targetPose"] == [0.0, 1.235, 0.0]
    assert "-0.0" not in json.dumps(message)
    assert message["ageMs"] == 13


def test_entries_with_numbers_json_cannot_carry_are_left_out_not_the_whole_message():
    message = build_worldstate("NuBot", "", math.nan, [robot(1, x=math.nan), robot(2, omega=math.inf), robot(3)],
                               (BallSnapshot(math.nan, 0.0), 1.0), [ObstacleSnapshot(0.0, math.inf, 0.25, 1.0)])
    assert [r["id"] for r in message["robots"]] == [3]
    assert (message["balls"], message["obstacles"], message["ageMs"]) == ([], [], 0)
    check_worldstate(message)
    encode_message(message)


def test_an_empty_team_still_sends_a_valid_worldstate():
    message = build_worldstate("NuBot", "STOPROBOT", 0.0, [])
    assert worldstate_problems(message) == [] and message["robots"] == message["balls"] == []


def test_the_team_ball_is_the_newest_one_a_robot_saw_itself():
    relayed_newest = BallSnapshot(9.0, 9.0, own=False, stamp=5.0)
    own_old = BallSnapshot(1.0, 1.0, own=True, stamp=1.0)
    own_new = BallSnapshot(2.0, 2.0, own=True, stamp=2.0)
    assert choose_ball([relayed_newest, own_old, own_new]) == (own_new, 1.0)
    assert choose_ball([relayed_newest]) == (relayed_newest, 0.5)
    assert choose_ball([]) is None and choose_ball([BallSnapshot(math.nan, 0.0)]) is None


def test_opponents_seen_by_several_robots_are_merged_with_a_confidence_of_who_sees_them():
    seen = [[(4.0, 0.0), (-3.0, 2.0)], [(4.2, 0.1)], [(4.1, -0.1), (8.0, 8.0)], []]
    obstacles = merge_obstacles(seen, merge_distance=0.5, radius=0.25)
    assert [(round(o.x, 3), round(o.y, 3), o.confidence) for o in obstacles] == \
        [(4.1, 0.0, 0.75), (-3.0, 2.0, 0.25), (8.0, 8.0, 0.25)]
    assert merge_obstacles([], 0.5, 0.25) == []


# --- the validator -------------------------------------------------------------------------------------------
def valid_worldstate():
    return build_worldstate("NuBot", "", 10.0, [robot()], choose_ball([BallSnapshot(0.0, 0.0)]),
                            [ObstacleSnapshot(1.0, 1.0, 0.25, 1.0)])


@pytest.mark.parametrize(("change", "problem"), [
    (lambda w: w.pop("ageMs"), 'worldstate lacks "ageMs"'),
    (lambda w: w.update(type="teams"), "worldstate.type must be \"worldstate\", got 'teams'"),
    (lambda w: w.update(ageMs=1.5), "worldstate.ageMs must be a whole number >= 0, got 1.5"),
    (lambda w: w.update(robots={}), "worldstate.robots must be a list, got {}"),
    (lambda w: w["robots"][0].pop("ballEngaged"), 'robots[0] lacks "ballEngaged"'),
    (lambda w: w["robots"][0].update(pose=[1, 2]), "robots[0].pose must be [x, y, theta], got [1, 2]"),
    (lambda w: w["robots"][0].update(id=True), "robots[0].id must be a whole number, got True"),
    (lambda w: w["robots"][0].update(ballEngaged=2), "robots[0].ballEngaged must be 0 or 1, got 2"),
    (lambda w: w["balls"][0].update(confidence=1.5), "balls[0].confidence must be a number in [0, 1], got 1.5"),
    (lambda w: w["balls"][0].update(position=[0, 0]), "balls[0].position must be [x, y, z], got [0, 0]"),
    (lambda w: w["obstacles"][0].pop("radius"), 'obstacles[0] lacks "radius"'),
    (lambda w: w["obstacles"].append("x"), "obstacles[1] is not an object"),
])
def test_the_validator_names_each_missing_or_mistyped_key(change, problem):
    message = valid_worldstate()
    change(message)
    assert worldstate_problems(message) == [problem]
    with pytest.raises(RefboxError, match="^invalid worldstate: " + re.escape(problem) + "$"):
        check_worldstate(message)


def test_the_validator_lists_every_problem_and_allows_extra_keys():
    assert worldstate_problems([]) == ["worldstate is not an object"]
    assert len(worldstate_problems({"type": "worldstate"})) == 6
    message = valid_worldstate()
    message["extra"] = {"ours": 1}
    assert worldstate_problems(message) == []


# --- bookkeeping and parameters ---------------------------------------------------------------------------
def test_backoff_doubles_up_to_its_maximum_and_resets():
    backoff = Backoff(0.5, 3.0)
    assert [backoff.next_delay() for _ in range(5)] == [0.5, 1.0, 2.0, 3.0, 3.0]
    backoff.reset()
    assert backoff.next_delay() == 0.5
    with pytest.raises(RefboxError, match="reconnect delays need 0 < initial <= maximum"):
        Backoff(2.0, 1.0)


def test_an_outage_is_logged_once_however_many_attempts_fail():
    log = OutageLog("127.0.0.1:28097")
    lines = [log.failed(t, "Connection refused") for t in (0.0, 0.5, 1.5)]
    assert lines[1:] == [None, None] and "cannot reach the RefBox at 127.0.0.1:28097" in lines[0]
    assert log.up(3.5) == "connected to the RefBox at 127.0.0.1:28097 after 3.5 s (3 failed attempts)"
    assert "lost the RefBox at 127.0.0.1:28097 (the box closed the connection)" in log.lost(10.0, "the box "
                                                                                              "closed the connection")
    assert [log.failed(t, "refused") for t in (10.5, 11.5)] == [None, None], "the loss was the outage's line"
    assert log.up(12.0) == "connected to the RefBox at 127.0.0.1:28097 after 2.0 s (2 failed attempts)"
    assert (log.outages, log.connections) == (2, 2)


def test_a_first_connection_says_just_connected():
    assert OutageLog("box:1").up(0.0) == "connected to the RefBox at box:1"


def test_rate_meter_counts_events_per_second_in_its_window():
    meter = RateMeter(window=2.0)
    for i in range(61):
        meter.add(i * 0.05)
    assert meter.rate(3.0) == pytest.approx(20.0)
    assert meter.rate(10.0) == 0.0 and meter.count == 61


@pytest.mark.parametrize(("params", "error"), [
    ({"worldstate_rate": 5.0}, r"worldstate_rate must lie in \[10, 200\] Hz \(the box requires at least 10\)"),
    ({"team": "nubot1"}, "a team prefix is letters and underscores"),
    ({"other_team": "nubot"}, "other_team must differ from team 'nubot'"),
    ({"team_address": "", "team_name": ""}, "our team needs an address or a name as the box knows it"),
    ({"port": 0}, r"port must lie in \[1, 65535\], got 0"),
    ({"reconnect_initial": 3.0, "reconnect_max": 1.0}, "reconnect_max 1.0 s is shorter than reconnect_initial"),
    ({"hots": "box"}, "unknown parameter"),
])
def test_bad_client_parameters_are_refused_by_name(params, error):
    from nubot_common import NubotCommonError

    with pytest.raises(NubotCommonError, match=error):
        from_mapping(RefboxClientParams, params, "~")


def test_the_config_file_is_the_defaults(config_dir):
    from nubot_common.params import load_yaml

    assert load_yaml(RefboxClientParams, config_dir / "refbox_client.yaml") == RefboxClientParams()
    assert RefboxClientParams(other_team="rival").teams == ("nubot", "rival")

"""Tests for nubot_common.match_mode: the chapter's MatchMode enum and its parser."""

import pytest

from nubot_common import NubotCommonError
from nubot_common.match_mode import MatchMode, parse_match_mode

CHAPTER_VALUES = {
    "STOPROBOT": 0,
    "OUR_KICKOFF": 1,
    "OPP_KICKOFF": 2,
    "OUR_THROWIN": 3,
    "OPP_THROWIN": 4,
    "OUR_PENALTY": 5,
    "OPP_PENALTY": 6,
    "OUR_GOALKICK": 7,
    "OPP_GOALKICK": 8,
    "OUR_CORNERKICK": 9,
    "OPP_CORNERKICK": 10,
    "OUR_FREEKICK": 11,
    "OPP_FREEKICK": 12,
    "DROPBALL": 13,
    "STARTROBOT": 15,
    "PARKINGROBOT": 25,
    "TEST": 27,
}


def test_enum_has_exactly_the_chapter_names_and_values():
    assert {m.name: m.value for m in MatchMode} == CHAPTER_VALUES


def test_enum_members_are_in_ascending_value_order():
    values = [m.value for m in MatchMode]
    assert values == sorted(values)


@pytest.mark.parametrize(("name", "value"), sorted(CHAPTER_VALUES.items(), key=lambda item: item[1]))
def test_parse_accepts_number_name_digit_string_and_char_byte(name, value):
    expected = MatchMode[name]
    assert parse_match_mode(value) is expected
    assert parse_match_mode(name) is expected
    assert parse_match_mode(name.lower()) is expected
    assert parse_match_mode(f" {name} ") is expected
    assert parse_match_mode(str(value)) is expected
    assert parse_match_mode(bytes([value])) is expected


def test_parse_returns_an_existing_member_unchanged():
    assert parse_match_mode(MatchMode.DROPBALL) is MatchMode.DROPBALL


@pytest.mark.parametrize("bad", [14, "14", b"\x0e", -1, "-1", 26, 255])
def test_parse_rejects_unknown_numbers_naming_the_value(bad):
    number = bad[0] if isinstance(bad, bytes) else int(bad)
    with pytest.raises(NubotCommonError, match=rf"unknown MatchMode {number}\b"):
        parse_match_mode(bad)


def test_parse_error_for_unknown_number_lists_the_known_values():
    with pytest.raises(NubotCommonError, match=r"known: STOPROBOT=0, .*DROPBALL=13, STARTROBOT=15.*TEST=27"):
        parse_match_mode(14)


@pytest.mark.parametrize("bad", ["FOO", "", "OUR_KICK", "kickoff"])
def test_parse_rejects_unknown_names_naming_the_value(bad):
    with pytest.raises(NubotCommonError, match=rf"unknown MatchMode name '{bad}'; known: STOPROBOT, "):
        parse_match_mode(bad)


@pytest.mark.parametrize("bad", [b"", b"\x01\x02"])
def test_parse_rejects_bytes_that_are_not_one_char(bad):
    with pytest.raises(NubotCommonError, match=r"MatchMode must be one byte, got b'"):
        parse_match_mode(bad)


def test_unknown_number_error_is_a_value_error():
    with pytest.raises(ValueError, match="unknown MatchMode 14"):
        parse_match_mode(14)


def test_parse_rejects_unicode_digit_strings_with_the_library_error():
    with pytest.raises(NubotCommonError, match="MatchMode"):
        parse_match_mode("²")


PAIRS = [
    (MatchMode.OUR_KICKOFF, MatchMode.OPP_KICKOFF),
    (MatchMode.OUR_THROWIN, MatchMode.OPP_THROWIN),
    (MatchMode.OUR_PENALTY, MatchMode.OPP_PENALTY),
    (MatchMode.OUR_GOALKICK, MatchMode.OPP_GOALKICK),
    (MatchMode.OUR_CORNERKICK, MatchMode.OPP_CORNERKICK),
    (MatchMode.OUR_FREEKICK, MatchMode.OPP_FREEKICK),
]


@pytest.mark.parametrize(("ours", "theirs"), PAIRS)
def test_mirrored_swaps_our_and_opp(ours, theirs):
    assert ours.mirrored() is theirs
    assert theirs.mirrored() is ours


@pytest.mark.parametrize(
    "mode",
    [MatchMode.STOPROBOT, MatchMode.DROPBALL, MatchMode.STARTROBOT, MatchMode.PARKINGROBOT, MatchMode.TEST],
)
def test_mirrored_keeps_team_neutral_commands(mode):
    assert mode.mirrored() is mode


@pytest.mark.parametrize("mode", list(MatchMode))
def test_mirrored_is_an_involution_that_keeps_the_kind_of_restart(mode):
    assert mode.mirrored().mirrored() is mode
    assert mode.mirrored().name.split("_", 1)[-1] == mode.name.split("_", 1)[-1]
    assert mode.mirrored().is_set_play == mode.is_set_play


def test_is_set_play_covers_the_restarts_and_dropball_only():
    set_plays = {m for m in MatchMode if m.is_set_play}
    assert set_plays == {m for m in MatchMode if m.name.startswith(("OUR_", "OPP_"))} | {MatchMode.DROPBALL}
    for mode in (MatchMode.STOPROBOT, MatchMode.STARTROBOT, MatchMode.PARKINGROBOT, MatchMode.TEST):
        assert not mode.is_set_play


def test_ours_and_theirs_split_the_set_pieces_and_mirror_into_each_other():
    from nubot_common.match_mode import OUR_SET_PLAYS, THEIR_SET_PLAYS

    assert len(OUR_SET_PLAYS) == len(THEIR_SET_PLAYS) == 6
    assert {m.mirrored() for m in OUR_SET_PLAYS} == THEIR_SET_PLAYS
    for mode in MatchMode:
        assert not (mode.is_ours and mode.is_theirs)
    for neither in (MatchMode.STOPROBOT, MatchMode.STARTROBOT, MatchMode.DROPBALL, MatchMode.PARKINGROBOT,
                    MatchMode.TEST):
        assert not neither.is_ours and not neither.is_theirs


@pytest.mark.parametrize(("mode", "kind"), [
    ("OUR_KICKOFF", "kickoff"), ("OPP_THROWIN", "throw-in"), ("OUR_PENALTY", "penalty"),
    ("OPP_GOALKICK", "goal kick"), ("OUR_CORNERKICK", "corner kick"), ("OPP_FREEKICK", "free kick"),
    ("DROPBALL", "dropped ball")])
def test_each_set_piece_names_its_restart_for_either_team(mode, kind):
    restart = MatchMode[mode].restart
    assert restart is not None and restart.value == kind
    assert MatchMode[mode].mirrored().restart is restart
    assert restart.ours().restart is restart and (restart.ours().is_ours or restart.ours() is MatchMode.DROPBALL)


def test_stop_start_park_and_test_are_no_restart():
    for mode in (MatchMode.STOPROBOT, MatchMode.STARTROBOT, MatchMode.PARKINGROBOT, MatchMode.TEST):
        assert mode.restart is None

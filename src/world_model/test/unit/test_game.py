"""Unit tests of coach commands and pass commands (world_model.game and through the WorldModel)."""

import pytest

from nubot_common.match_mode import MatchMode
from nubot_common.team_play import PassCommand, StrategyReport
from nubot_common.world_state import CoachExtras, GameState
from world_model import WorldModelError
from world_model.game import next_game_state, parse_coach_command, select_pass


def test_the_chapter_command_parses_with_its_previous_mode():
    command = parse_coach_command(10, 0)
    assert (command.mode, command.previous) == (MatchMode.OPP_CORNERKICK, MatchMode.STOPROBOT)
    command = parse_coach_command(15, 10)
    assert (command.mode, command.previous) == (MatchMode.STARTROBOT, MatchMode.OPP_CORNERKICK)


def test_char_bytes_and_names_parse_and_test_fields_pass_through():
    extras = CoachExtras(test_mode=2, point_a=(1.0, -1.0), angle_a=90, id_a=3, kickforce=6)
    command = parse_coach_command(b"\x1b", "STARTROBOT", extras)
    assert (command.mode, command.previous, command.extras) == (MatchMode.TEST, MatchMode.STARTROBOT, extras)


@pytest.mark.parametrize("mode", [14, 99, 255, -1])
def test_an_unknown_match_mode_is_refused_naming_the_value(mode):
    with pytest.raises(WorldModelError, match=rf"coach command refused: MatchMode {mode} is not a game command"):
        parse_coach_command(mode, 0)


def test_an_unknown_match_type_is_refused_naming_the_field():
    with pytest.raises(WorldModelError, match="MatchType 99 is not a game command"):
        parse_coach_command(10, 99)


def test_world_model_starts_stopped_and_refuses_an_unknown_mode_keeping_the_previous(make_model):
    model = make_model()
    assert (model.game.mode, model.game.previous) == (MatchMode.STOPROBOT, MatchMode.STOPROBOT)
    model.on_coach(5.0, 10, 0)
    for bad in (14, 99):
        with pytest.raises(WorldModelError, match=f"MatchMode {bad}"):
            model.on_coach(6.0, bad, 10)
    game = model.snapshot(7.0).game
    assert (game.mode, game.previous, game.since, game.stamp) == (MatchMode.OPP_CORNERKICK, MatchMode.STOPROBOT,
                                                                  5.0, 5.0)


def test_since_is_kept_while_the_coach_repeats_and_restarts_on_a_change():
    state = GameState()
    for t in (1.0, 1.03, 1.06):
        state = next_game_state(state, t, parse_coach_command(1, 0))
    assert (state.since, state.stamp) == (1.0, 1.06)
    state = next_game_state(state, 2.0, parse_coach_command(15, 1))
    assert (state.mode, state.previous, state.since) == (MatchMode.STARTROBOT, MatchMode.OUR_KICKOFF, 2.0)


def _strategy(agent_id, stamp, pass_id, catch_id, valid=True):
    return StrategyReport(stamp, agent_id, pass_cmd=PassCommand(pass_id, catch_id, (0.0, 0.0), (3.0, 1.0),
                                                                is_valid=valid))


def test_pass_selection_takes_the_valid_fresh_command_of_the_team():
    assert select_pass(1, [], 10.0, 0.3, 5) is None
    assert select_pass(1, [StrategyReport(10.0, 2)], 10.0, 0.3, 5) is None, "no pass command at all"
    assert select_pass(1, [_strategy(2, 10.0, 2, 3, valid=False)], 10.0, 0.3, 5) is None
    assert select_pass(1, [_strategy(2, 9.6, 2, 3)], 10.0, 0.3, 5) is None, "stale strategy"
    assert select_pass(1, [_strategy(2, 10.0, 2, 9)], 10.0, 0.3, 5) is None, "catcher outside the team"
    assert select_pass(1, [_strategy(2, 10.0, 2, 3)], 10.0, 0.3, 5).catch_id == 3


def test_pass_selection_prefers_a_pass_involving_this_robot_then_the_newest():
    strategies = [_strategy(2, 10.0, 2, 3), _strategy(4, 9.9, 4, 1), _strategy(5, 9.95, 5, 1)]
    assert select_pass(1, strategies, 10.0, 0.3, 5).pass_id == 5
    assert select_pass(3, strategies, 10.0, 0.3, 5).pass_id == 2


def test_world_model_finds_the_pass_in_own_or_teammates_strategy(make_model):
    model = make_model(agent_id=3)
    assert model.snapshot(10.0).pass_cmd is None
    model.on_teammate_strategy(10.0, _strategy(2, 10.0, 2, 3))
    assert model.on_teammate_strategy(10.0, _strategy(3, 10.0, 3, 4)) is False, "own, relayed back: ignored"
    assert model.snapshot(10.1).pass_cmd.pass_id == 2
    model.on_strategy(10.2, _strategy(3, 10.2, 3, 4))
    assert model.snapshot(10.25).pass_cmd.pass_id == 3, "both involve 3: the newest"
    assert model.snapshot(10.6).pass_cmd is None, "all stale"

"""Unit tests of the game state and manual commands (coach4sim.game)."""

import pytest

from coach4sim import CoachError
from coach4sim.game import GameController, team_of_robot
from coach4sim.params import DEFAULT_TEAMS, TeamSpec
from nubot_common import NubotCommonError
from nubot_common.match_mode import MatchMode


@pytest.fixture
def game() -> GameController:
    return GameController(DEFAULT_TEAMS)


def test_a_command_reaches_the_other_team_mirrored(game):
    assert game.command("nubot", MatchMode.OUR_THROWIN) == "OUR_THROWIN for nubot"
    assert game.status("nubot").mode == MatchMode.OUR_THROWIN
    assert game.status("rival").mode == MatchMode.OPP_THROWIN
    game.command("rival", "our_cornerkick")
    assert (game.status("rival").mode, game.status("nubot").mode) == (MatchMode.OUR_CORNERKICK,
                                                                       MatchMode.OPP_CORNERKICK)


def test_match_type_carries_the_previous_command_and_a_repeat_keeps_it(game):
    game.command("nubot", 1)
    game.command("nubot", "STARTROBOT")
    assert game.status("nubot").previous == MatchMode.OUR_KICKOFF
    assert game.status("rival").previous == MatchMode.OPP_KICKOFF
    game.command("rival", 15)
    assert game.status("nubot").previous == MatchMode.OUR_KICKOFF, "repeating STARTROBOT must not erase the kickoff"


def test_unknown_match_mode_is_refused_and_nothing_changes(game):
    game.command("nubot", MatchMode.OUR_KICKOFF)
    before = game.state()
    with pytest.raises(NubotCommonError, match="unknown MatchMode 14"):
        game.command("nubot", 14)
    with pytest.raises(NubotCommonError, match="unknown MatchMode name 'KICK'"):
        game.command("nubot", "KICK")
    assert game.state() == before


def test_unknown_team_is_refused_by_name_and_nothing_changes(game):
    before = game.state()
    with pytest.raises(CoachError, match="unknown team 'robots'; teams: nubot, rival"):
        game.command("robots", MatchMode.STARTROBOT)
    assert game.state() == before


def test_a_goal_counts_for_the_team_attacking_that_goal(game):
    assert game.goal(1) == "nubot"
    assert game.goal(-1) == "rival"
    assert game.goal(1) == "nubot"
    assert game.state().score == (2, 1)
    with pytest.raises(CoachError, match="goal side must be 1"):
        game.goal(0)


def test_game_clock_runs_only_while_the_ball_is_in_play(game):
    game.tick(10.0)
    game.command("nubot", MatchMode.OUR_KICKOFF)
    game.tick(14.0)
    assert game.game_time == 0.0
    game.command("nubot", MatchMode.STARTROBOT)
    game.tick(20.0)
    assert game.game_time == pytest.approx(6.0)
    game.command("nubot", MatchMode.STOPROBOT)
    game.tick(30.0)
    assert game.game_time == pytest.approx(6.0)
    game.start_half(2)
    assert (game.half, game.game_time) == (2, 0.0)


def test_state_has_every_team_in_order(game):
    game.command("rival", MatchMode.OUR_FREEKICK)
    game.goal(-1)
    state = game.state()
    assert state.teams == ("nubot", "rival")
    assert state.attack == (1, -1)
    assert state.score == (0, 1)
    assert state.match_mode == (MatchMode.OPP_FREEKICK, MatchMode.OUR_FREEKICK)
    assert not state.running and state.last_event == "OUR_FREEKICK for rival"


def test_award_gives_the_restart_by_attacked_side_even_with_one_team():
    solo = GameController([TeamSpec("nubot", 1)])
    solo.award(-1, MatchMode.OUR_GOALKICK)  # for the absent team attacking -x
    assert solo.status("nubot").mode == MatchMode.OPP_GOALKICK
    assert solo.goal(-1) is None and solo.state().score == (0,)


def test_robots_belong_to_teams_by_prefix_and_number():
    assert team_of_robot(DEFAULT_TEAMS, "rival3") == "rival"
    assert team_of_robot(DEFAULT_TEAMS, "nubot12") == "nubot"
    assert team_of_robot(DEFAULT_TEAMS, "nubot") is None
    assert team_of_robot(DEFAULT_TEAMS, "football") is None


@pytest.mark.parametrize(("teams", "message"), [
    ([TeamSpec("nubot", 1), TeamSpec("rival", 1)], "must attack opposite goals"),
    ([TeamSpec("nubot", 1), TeamSpec("nubot", -1)], "prefixes must differ"),
    ([], "one or two teams"),
])
def test_bad_team_lists_are_refused(teams, message):
    with pytest.raises(CoachError, match=message):
        GameController(teams)

"""The referee node's core: the simulator's reports judged once, commands by hand in auto and manual mode, and the
game's state published on change or once a period."""

import pytest

from coach4sim.params import RefereeNodeParams
from coach4sim.referee_desk import RefereeDesk, decision_line
from nubot_common import NubotCommonError
from nubot_common.match_mode import MatchMode

ROBOTS = {"nubot1": (2.0, 1.0), "nubot2": (3.0, -1.0), "rival1": (-2.0, 0.0), "rival2": (-3.0, 1.0)}
BALL = (0.0, 0.0, 0.11)


def _modes(desk: RefereeDesk, now: float = 0.0) -> dict[str, str]:
    modes, _state = desk.modes(now)
    return {team: mode.name for team, mode, _previous in modes}


def test_positions_are_judged_once_and_positions_without_a_time_not_at_all():
    desk = RefereeDesk(RefereeNodeParams())
    assert desk.judge() is None  # nothing seen yet
    desk.seen_world(0.0, BALL, ROBOTS)  # before the first /clock: no time yet
    assert desk.judge() is None
    desk.seen_world(0.1, None, ROBOTS)  # no ball among the model states
    assert desk.judge() is None
    desk.seen_world(0.1, BALL, ROBOTS)
    kickoff = desk.judge()
    assert kickoff is not None and "kickoff for nubot" in kickoff.event and kickoff.ball == (0.0, 0.0)
    assert "ball placed at (+0.00, +0.00)" in decision_line(kickoff)
    assert desk.judge() is None  # the same positions are not judged twice
    assert _modes(desk) == {"nubot": "OUR_KICKOFF", "rival": "OPP_KICKOFF"}


def test_a_goal_reported_between_two_looks_is_counted():
    desk = RefereeDesk(RefereeNodeParams())
    t = 0.1
    desk.seen_world(t, BALL, ROBOTS)
    desk.judge()
    while t < 4.5:  # the kickoff's setup time, then STARTROBOT
        t += 0.25
        desk.seen_world(t, BALL, ROBOTS)
        desk.judge()
    desk.seen_touch("nubot1")
    desk.seen_kick("nubot2")  # two robots of the kicking team played it: a goal may follow
    desk.seen_world(t + 0.25, (4.0, 0.0, 0.11), ROBOTS)
    assert desk.judge() is None
    desk.seen_goal(1, "nubot2")
    desk.seen_world(t + 0.5, (9.2, 0.0, 0.11), ROBOTS)
    decision = desk.judge()
    assert decision is not None and desk.game.state().score == (1, 0)


@pytest.mark.parametrize("auto", [True, False])
def test_a_command_by_hand_goes_to_the_named_team_or_the_first_and_a_bad_one_changes_nothing(auto):
    desk = RefereeDesk(RefereeNodeParams(auto=auto))
    text = desk.command("", "OUR_FREEKICK", 1.0)
    assert "nubot" in text and _modes(desk, 1.0) == {"nubot": "OUR_FREEKICK", "rival": "OPP_FREEKICK"}
    desk.command(" rival ", MatchMode.OUR_CORNERKICK, 2.0)
    with pytest.raises(NubotCommonError):
        desk.command("nubot", "NO_SUCH_MODE", 3.0)
    with pytest.raises(NubotCommonError):
        desk.command("nobody", "STOPROBOT", 3.0)
    assert _modes(desk, 3.0) == {"nubot": "OPP_CORNERKICK", "rival": "OUR_CORNERKICK"}


def test_the_state_is_published_on_change_and_once_a_period():
    desk = RefereeDesk(RefereeNodeParams(auto=False, state_period=1.0))
    _modes_now, state = desk.modes(0.0)
    assert desk.state_due(state, 10.0)  # the first
    assert not desk.state_due(state, 10.5)
    assert desk.state_due(state, 11.0)  # a period later, unchanged
    desk.command("nubot", "OUR_THROWIN", 0.2)
    _modes_now, changed = desk.modes(0.2)
    assert desk.state_due(changed, 11.1)  # changed: at once
    assert not desk.state_due(changed, 11.2)

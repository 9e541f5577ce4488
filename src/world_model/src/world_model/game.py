"""Game commands from the coach and pass commands from the team's strategies.

Requires: the coach's raw ``MatchMode`` / ``MatchType`` values (number, name or one
``char`` byte) and ``CoachExtras``; the team's ``StrategyReport``s. Provides:
``parse_coach_command`` (a ``CoachCommand``, or ``WorldModelError`` naming the unknown
value and the field it came in), ``next_game_state`` (keeps ``since`` while the command
repeats: the coach resends every 30 ms) and ``select_pass`` (the valid pass command
in force: fresh, both AgentIDs in the team; one involving this robot first, then the
newest, then the lowest sender ID). Times [s].
"""

from __future__ import annotations

from collections.abc import Sequence

from nubot_common import NubotCommonError
from nubot_common.match_mode import MatchMode, parse_match_mode
from nubot_common.team_play import PassCommand, StrategyReport
from nubot_common.world_state import CoachCommand, CoachExtras, GameState
from world_model import WorldModelError


def _parse(value: int | str | bytes, field_name: str) -> MatchMode:
    try:
        return parse_match_mode(value)
    except NubotCommonError as exc:
        raise WorldModelError(f"coach command refused: {field_name} {value!r} is not a game command ({exc})") from None


def parse_coach_command(mode: int | str | bytes, match_type: int | str | bytes = 0,
                        extras: CoachExtras | None = None) -> CoachCommand:
    """Validate a coach command: ``mode`` is the current MatchMode, ``match_type`` the previous one."""
    return CoachCommand(_parse(mode, "MatchMode"), _parse(match_type, "MatchType"), extras or CoachExtras())


def next_game_state(state: GameState, t: float, command: CoachCommand) -> GameState:
    """The game state after ``command`` arrived at ``t``."""
    same = (command.mode, command.previous) == (state.mode, state.previous)
    since = state.since if same and state.stamp > float("-inf") else t
    return GameState(command, since, t)


def select_pass(agent_id: int, strategies: Sequence[StrategyReport], t: float, timeout: float,
                team_size: int) -> PassCommand | None:
    """The valid pass command among fresh ``strategies`` (this robot's included), or None."""
    candidates = []
    for s in strategies:
        cmd = s.pass_cmd
        if cmd is None or not cmd.is_valid or t - s.stamp > timeout:
            continue
        if not (1 <= cmd.pass_id <= team_size and 1 <= cmd.catch_id <= team_size):
            continue
        involves_me = agent_id in (cmd.pass_id, cmd.catch_id)
        candidates.append(((not involves_me, -s.stamp, s.agent_id), cmd))
    return min(candidates, key=lambda c: c[0])[1] if candidates else None

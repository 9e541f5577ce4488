"""The state of a refereed match and the commands in force (no rules here; see ``referee``).

Requires: the teams (``params.TeamSpec``: robot-name prefix, attacked goal +1/-1).
Provides: ``GameController``, which keeps the score, the half, the game clock [s]
(it advances with ``tick(now)`` only while the ball is in play), each team's current
and previous ``MatchMode`` (in that team's own view, OUR_/OPP_), whether play is
running and the last event in words; ``command`` applies a manual command to one
team and the mirrored one to the other, ``award`` gives a restart to the team
attacking a side, ``goal`` scores; ``state()`` returns ``GameStateData`` (the
content of ``nubot_common/GameState``). Invalid input raises ``CoachError`` (a
``NubotCommonError``) naming the bad value, and changes nothing.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

from coach4sim import CoachError
from coach4sim.params import TeamSpec, validate_teams
from nubot_common.match_mode import MatchMode, parse_match_mode
from nubot_common.naming import is_robot_name, team_of
from nubot_common.records import fast_init

HALF_NAMES = {1: "first half", 2: "second half"}


def half_name(half: int) -> str:
    return HALF_NAMES.get(half, f"half {half}")


@dataclass
class TeamStatus:
    """One team's part of the game (mutable: the controller updates it)."""

    spec: TeamSpec
    score: int = 0
    mode: MatchMode = MatchMode.STOPROBOT
    previous: MatchMode = MatchMode.STOPROBOT


@fast_init
@dataclass(frozen=True)
class GameStateData:
    """A snapshot of the game; index i of each tuple is team i."""

    teams: tuple[str, ...]
    score: tuple[int, ...]
    attack: tuple[int, ...]  # the goal each team attacks: 1 at +x, -1 at -x (world frame)
    match_mode: tuple[MatchMode, ...]  # in force for each team, in its own view
    previous_mode: tuple[MatchMode, ...]  # the one before it (CoachInfo.MatchType)
    half: int  # 0 before the match, then 1, 2, ...
    game_time: float  # game clock of this half [s]
    running: bool  # the ball is in play (after STARTROBOT)
    last_event: str

    def without_clock(self) -> tuple:
        """Everything but the game clock: what makes a state 'changed' for publishing."""
        return (self.teams, self.score, self.attack, self.match_mode, self.previous_mode, self.half, self.running,
                self.last_event)


def team_of_robot(teams: Sequence[TeamSpec], robot: str) -> str | None:
    """The prefix of the team ``robot`` (e.g. ``rival3``) belongs to, or None."""
    team = team_of(robot) if is_robot_name(robot) else None
    return team if team in {t.prefix for t in teams} else None


class GameController:
    def __init__(self, teams: Sequence[TeamSpec]):
        try:
            validate_teams(teams)
        except ValueError as exc:
            raise CoachError(str(exc)) from None
        self.teams = [TeamStatus(spec) for spec in teams]
        self.half = 0
        self.game_time = 0.0
        self.last_event = ""
        self._last_tick: float | None = None

    # --- queries --------------------------------------------------------------------------
    @property
    def team_names(self) -> list[str]:
        return [t.spec.prefix for t in self.teams]

    @property
    def running(self) -> bool:
        return self.teams[0].mode == MatchMode.STARTROBOT

    def status(self, team: str) -> TeamStatus:
        for status in self.teams:
            if status.spec.prefix == team:
                return status
        raise CoachError(f"unknown team {team!r}; teams: {', '.join(self.team_names)}")

    def team_attacking(self, side: int) -> str | None:
        """The team attacking the goal at +x (side 1) or -x (side -1), or None if it does not play."""
        return next((t.spec.prefix for t in self.teams if t.spec.attack == side), None)

    def team_of_robot(self, robot: str) -> str | None:
        return team_of_robot([t.spec for t in self.teams], robot)

    def state(self) -> GameStateData:
        return GameStateData(
            teams=tuple(self.team_names),
            score=tuple(t.score for t in self.teams),
            attack=tuple(t.spec.attack for t in self.teams),
            match_mode=tuple(t.mode for t in self.teams),
            previous_mode=tuple(t.previous for t in self.teams),
            half=self.half,
            game_time=self.game_time,
            running=self.running,
            last_event=self.last_event,
        )

    def score_text(self) -> str:
        return ", ".join(f"{t.spec.prefix} {t.score}" for t in self.teams)

    # --- changes ----------------------------------------------------------------------------
    def tick(self, now: float) -> None:
        """Advance the game clock to the sim time ``now`` [s] if the ball is in play."""
        if self._last_tick is not None and self.running and now > self._last_tick:
            self.game_time += now - self._last_tick
        self._last_tick = now

    def command(self, team: str, mode: MatchMode | int | str) -> str:
        """Send ``mode`` to ``team`` and its mirror (OUR_x <-> OPP_x) to the other team; return it in words."""
        status = self.status(team)
        parsed = parse_match_mode(mode)
        self._apply({t.spec.prefix: parsed if t is status else parsed.mirrored() for t in self.teams})
        self.last_event = f"{parsed.name} for {team}" if parsed.is_set_play else parsed.name
        return self.last_event

    def award(self, side: int, mode: MatchMode) -> None:
        """Give ``mode`` (as its beneficiary sees it) to the team attacking ``side``; the others get its mirror."""
        if side not in (1, -1):
            raise CoachError(f"side must be 1 (+x) or -1 (-x), got {side!r}")
        self._apply({t.spec.prefix: mode if t.spec.attack == side else mode.mirrored() for t in self.teams})

    def send_all(self, mode: MatchMode) -> None:
        """Send the same ``mode`` to every team (STOPROBOT, STARTROBOT, DROPBALL, ...)."""
        self._apply({t.spec.prefix: mode for t in self.teams})

    def goal(self, side: int) -> str | None:
        """Count a goal in the goal at +x (side 1) or -x (side -1) for the team attacking it; return that team."""
        if side not in (1, -1):
            raise CoachError(f"goal side must be 1 (+x) or -1 (-x), got {side!r}")
        scorer = self.team_attacking(side)
        if scorer is not None:
            self.status(scorer).score += 1
        return scorer

    def switch_ends(self) -> None:
        """Every team attacks the other goal from now on."""
        for status in self.teams:
            status.spec = replace(status.spec, attack=-status.spec.attack)

    def start_half(self, half: int) -> None:
        """Begin half number ``half`` (1, 2, ...) with the game clock at zero."""
        if half < 1:
            raise CoachError(f"half must be 1 or more, got {half}")
        self.half, self.game_time = half, 0.0

    def _apply(self, modes: dict[str, MatchMode]) -> None:
        for status in self.teams:
            mode = modes[status.spec.prefix]
            if mode != status.mode:  # a repeated command keeps the previous one (MatchType) meaningful
                status.previous, status.mode = status.mode, mode

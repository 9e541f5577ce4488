"""What the environments need of a ``LockstepMatch`` beyond its API (candidates for the engine itself).

Requires: a ``LockstepMatch`` after ``reset``. Provides: ``start_play_now`` (the ball in play at once,
without the kick-off's set-up time: STARTROBOT by hand, as a coach would give it), ``place_robot`` and
``place_ball`` (a model put at rest at a world-frame pose [m], [rad]), ``team_attack`` (the world goal a
team attacks now: 1 at +x, -1 at -x; it changes at half time), ``score_of`` (a team's goals) and
``interruption`` (why the referee stopped play in a step: "goal", "out", "dropped ball" or "time").
"""

from __future__ import annotations

from coach4sim.game import GameStateData
from coach4sim.referee import RefereeDecision
from nubot_common.match_mode import MatchMode, RestartKind
from nubot_match.engine import LockstepMatch
from sim_visual.simulator import Simulator
from sim_visual.world import BallState, RobotState

_OUT = (RestartKind.THROWIN, RestartKind.GOALKICK, RestartKind.CORNERKICK)


def _sim(match: LockstepMatch) -> Simulator:
    assert match.sim is not None, "reset the match first"
    return match.sim


def start_play_now(match: LockstepMatch) -> None:
    match.command(match.config.teams[0].config.prefix, MatchMode.STARTROBOT)


def place_robot(match: LockstepMatch, name: str, x: float, y: float, theta: float) -> None:
    _sim(match).set_model_state(name, RobotState(x, y, theta, 0.0, 0.0, 0.0))


def place_ball(match: LockstepMatch, x: float, y: float) -> None:
    world = match.config.world
    _sim(match).set_model_state(world.ball_name, BallState(x, y, world.ball.radius, 0.0, 0.0, 0.0))


def team_attack(state: GameStateData, team: str) -> int:
    return state.attack[state.teams.index(team)]


def score_of(state: GameStateData, team: str) -> int:
    return state.score[state.teams.index(team)]


def interruption(decisions: list[RefereeDecision]) -> str:
    """Why play stopped in these decisions ("" if it did not): the restart each one set up tells."""
    for decision in decisions:
        modes = {mode for _team, mode in decision.commands}
        if MatchMode.STOPROBOT in modes:
            return "time"
        restarts = {mode.restart for mode in modes}
        if RestartKind.KICKOFF in restarts:
            return "goal"
        if restarts & set(_OUT):
            return "out"
        if RestartKind.DROPBALL in restarts:
            return "dropped ball"
    return ""

"""The referee node's core, without ROS: the game and the automatic referee behind one lock for the node's
callback threads, what the simulator reported since the last judgement, commands by hand, and when the game's
state is worth publishing.

Requires: ``RefereeNodeParams`` (with the world). Provides: ``RefereeDesk``: ``seen_*`` take the simulator's
reports (model states, goals, kicks, touches, the holder), ``judge()`` hands the latest positions and those reports
to the ``AutomaticReferee`` once, ``command`` takes a MatchMode for a team (the automatic referee's manual
command in auto mode, the game's own otherwise), ``modes`` gives every team's command to send, and
``state_due`` says whether the game's state changed or was last published a ``state_period`` ago.
"""

from __future__ import annotations

import threading
from collections.abc import Mapping

from coach4sim.game import GameController, GameStateData
from coach4sim.params import RefereeNodeParams
from coach4sim.referee import AutomaticReferee, RefereeDecision, RefereeInputs
from nubot_common.match_mode import MatchMode


class RefereeDesk:
    def __init__(self, params: RefereeNodeParams):
        self.params = params
        self.game = GameController(params.teams)
        self.referee = AutomaticReferee(params, self.game)
        self.lock = threading.Lock()
        self._world: tuple[float, tuple[float, float, float], Mapping[str, tuple[float, float]]] | None = None
        self._inputs = RefereeInputs()  # goals, kicks, touches, last touch and holder since the last judgement
        self._published: GameStateData | None = None
        self._published_at = -float("inf")

    # --- what the simulator reports (any thread) ----------------------------------------------------------
    def seen_world(self, stamp: float, ball: tuple[float, float, float] | None,
                   robots: Mapping[str, tuple[float, float]]) -> None:
        """The latest model states at sim time ``stamp`` [s]; ones without a ball or a time are ignored."""
        if ball is not None and stamp > 0.0:
            with self.lock:
                self._world = (stamp, ball, robots)

    def seen_goal(self, side: int, last_touch: str) -> None:
        with self.lock:
            self._inputs.goal(side, last_touch)

    def seen_touch(self, robot: str) -> None:
        with self.lock:
            self._inputs.touch(robot)

    def seen_kick(self, robot: str) -> None:
        with self.lock:
            self._inputs.kick(robot)

    def seen_holder(self, robot: str) -> None:
        with self.lock:
            self._inputs.holder = robot

    # --- decisions ------------------------------------------------------------------------------------------
    def command(self, team: str, command: MatchMode | int | str, now: float) -> str:
        """A command by hand for ``team`` (empty: the first team); its text. Raises ``NubotCommonError``."""
        team = team.strip() or self.params.teams[0].prefix
        with self.lock:
            if self.params.auto:
                return self.referee.manual_command(team, command, now)
            self.game.tick(now)
            return self.game.command(team, command)

    def judge(self) -> RefereeDecision | None:
        """The referee's decision on the positions and reports since the last call (None: nothing new, or
        nothing to decide)."""
        with self.lock:
            if self._world is None:
                return None
            now, ball, robots = self._world
            self._world = None
            return self.referee.update(self._inputs.snapshot(now, ball, robots))

    def keep_ends(self) -> None:
        """The simulator could not switch ends: the game keeps the old ends too (the two must agree)."""
        with self.lock:
            self.game.switch_ends()

    def modes(self, now: float) -> tuple[list[tuple[str, MatchMode, MatchMode]], GameStateData]:
        """Every team's (prefix, command, previous command) to send at ``now`` [s], and the game's state."""
        with self.lock:
            if not self.params.auto:
                self.game.tick(now)
            return [(t.spec.prefix, t.mode, t.previous) for t in self.game.teams], self.game.state()

    def state_due(self, state: GameStateData, wall: float) -> bool:
        """Whether to publish ``state`` at wall time ``wall`` [s]: it changed (the clock aside) or the last one is
        ``state_period`` old. Counts it as published when due."""
        published = self._published
        if published is not None and state.without_clock() == published.without_clock() and \
                wall - self._published_at < self.params.state_period:
            return False
        self._published, self._published_at = state, wall
        return True


def decision_line(decision: RefereeDecision) -> str:
    """The referee's decision in one log line."""
    commands = ", ".join(f"{team} {mode.name}" for team, mode in decision.commands)
    placed = f"; ball placed at ({decision.ball[0]:+.2f}, {decision.ball[1]:+.2f})" if decision.ball is not None else ""
    return f"referee: {decision.event} [{commands}]{placed}"

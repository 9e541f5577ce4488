from pathlib import Path

import pytest

from coach4sim.game import GameController
from coach4sim.params import DEFAULT_TEAMS, RefereeParams
from coach4sim.referee import AutomaticReferee, WorldSnapshot


@pytest.fixture
def config_dir() -> Path:
    return Path(__file__).resolve().parents[2] / "config"


class Match:
    """An automatic referee over nubot (attacks +x) and rival (attacks -x), driven with hand-made snapshots."""

    def __init__(self, **params: float):
        self.game = GameController(DEFAULT_TEAMS)
        self.referee = AutomaticReferee(RefereeParams(**params), self.game)
        self.time = 0.0
        self.ball = (0.0, 0.0, 0.11)
        # each robot in the half it attacks, away from the areas and the others: its shots count (RC-10.1.1)
        self.robots = {"nubot1": (2.0, 1.0), "nubot2": (3.0, -1.0), "rival1": (-2.0, 0.0), "rival2": (-3.0, 1.0)}
        self.last_touch = ""

    def step(self, dt: float = 0.0, **events):
        """Advance sim time by ``dt`` [s] and let the referee look once."""
        self.time += dt
        snap = WorldSnapshot(self.time, self.ball, dict(self.robots), events.pop("last_touch", self.last_touch),
                             **events)
        decision = self.referee.update(snap)
        if decision is not None and decision.ball is not None:  # as the node does through the simulator
            self.ball = (*decision.ball, 0.11)
        return decision

    def run(self, seconds: float, dt: float = 0.25):
        """Look every ``dt`` for ``seconds``; return the decisions taken."""
        decisions = []
        for _ in range(round(seconds / dt)):
            decision = self.step(dt)
            if decision is not None:
                decisions.append(decision)
        return decisions

    def modes(self) -> dict:
        return {t.spec.prefix: t.mode.name for t in self.game.teams}

    def kickoff_and_play(self) -> None:
        """Start the match and let the first kickoff be taken and passed on (two of nubot's robots touched the ball:
        a goal may follow, RC-8.4.1): the ball is in play."""
        self.step()
        self.run(4.0)
        assert self.game.running
        self.step(0.25, touches=("nubot1",))
        self.step(0.25, touches=("nubot2",))
        assert not self.referee.restart_pending


@pytest.fixture
def make_match():
    """Build a ``Match`` with other rule numbers, e.g. ``make_match(half_duration=20.0)``."""
    return Match


@pytest.fixture
def match() -> Match:
    return Match()

"""What a lockstep match leaves behind, as it happens: the listeners of ``LockstepMatch``.

Requires: the engine's calls, in sim time [s] and the world frame [m]. Provides: ``MatchListener`` (the
calls a listener may take; every one optional), ``MatchLogRecorder`` (builds the ``MatchLog`` that
``nubot_tools.match_analysis`` turns into the statistics of a report, the same records a bag gives),
and ``MatchEvents`` (every event as one plain tuple: what the determinism test compares).
"""

from __future__ import annotations

from array import array
from typing import Any

import numpy as np

from coach4sim.fouls import RefereeCall
from coach4sim.game import GameStateData
from nubot_common.match_mode import MatchMode
from nubot_common.percepts import RobotView
from nubot_common.team_play import Role
from nubot_common.world_description import WorldDescription
from nubot_control.agent import AgentStep
from nubot_tools import match_analysis as ma
from sim_visual.simulator import BallKicked, BallTouched, GoalScored, SimEvent
from sim_visual.world import BallState, RobotState

ModelStates = list[tuple[str, RobotState | BallState]]


class MatchListener:
    """Override what you need; the engine calls each method at the moment the ROS match would publish."""

    def start(self, world: WorldDescription, t: float) -> None:
        """The match's world, once at the start (``/sim_visual/world_description``)."""

    def model_states(self, t: float, states: ModelStates) -> None:
        """Every model at ``model_states_rate`` (``/sim_visual/model_states``)."""

    def sim_event(self, event: SimEvent) -> None:
        """A goal, kick, touch, capture or release (``/sim_visual/goal``, ``kick``, ``ball_touch``)."""

    def game_state(self, t: float, state: GameStateData) -> None:
        """The referee's state, on change and every second (``/referee/state``)."""

    def coach(self, t: float, team: str, mode: MatchMode, previous: MatchMode) -> None:
        """A new command for ``team`` in its own view (``/<team>/receive_from_coach``)."""

    def referee_call(self, call: RefereeCall) -> None:
        """A foul or another call of the referee (``/referee/foul``)."""

    def vision(self, robot: str, view: RobotView) -> None:
        """A robot's percepts (``/<robot>/omnivision/OmniVisionInfo``)."""

    def robot_step(self, t: float, robot: str, step: AgentStep) -> None:
        """A robot's control cycle: its world model, strategy and velocity command."""

    def clock(self, t: float) -> None:
        """Sim time, at ``model_states_rate`` (``/clock``)."""

    def close(self) -> None:
        """The match is over (or was stopped)."""


class MatchLogRecorder(MatchListener):
    """Builds a ``match_analysis.MatchLog`` directly, without a bag.

    The model states (every model at 100 Hz: most of what a match leaves) are kept as packed machine numbers, 20
    bytes a model and sample instead of about 100 as Python numbers in lists: a 2 x 15 min match's tracks take about
    60 MiB instead of 300."""

    def __init__(self) -> None:
        self.log = ma.MatchLog()
        self._times = array("d")  # [s]
        self._positions: dict[str, tuple[array, array, array]] = {}  # per model: sample indices, x, y [m]
        self._goalie_cycles: dict[str, int] = {}  # control cycles each robot announced itself goalie

    def start(self, world: WorldDescription, t: float) -> None:
        self.log.world = world

    def model_states(self, t: float, states: ModelStates) -> None:
        index = len(self._times)
        self._times.append(t)
        for name, s in states:
            indices, xs, ys = self._positions.setdefault(name, (array("i"), array("d"), array("d")))
            indices.append(index)
            xs.append(s.x)
            ys.append(s.y)

    def sim_event(self, event: SimEvent) -> None:
        log = self.log
        if isinstance(event, GoalScored):
            log.goals.append(ma.Goal(event.time, event.side, (event.ball.x, event.ball.y), event.last_touch,
                                    event.ball.z))
        elif isinstance(event, BallKicked):
            log.kicks.append(ma.Kick(event.time, event.robot, int(event.kind), event.velocity, event.position[:2]))
        elif isinstance(event, BallTouched):
            log.touches.append(ma.Touch(event.time, event.robot))

    def game_state(self, t: float, state: GameStateData) -> None:
        self.log.referee.append(ma.RefereeState(t, state.teams, state.score, state.attack, state.half,
                                                state.game_time, state.running, state.last_event))

    def coach(self, t: float, team: str, mode: MatchMode, previous: MatchMode) -> None:
        self.log.coach.append(ma.CoachCommand(t, team, int(mode)))

    def referee_call(self, call: RefereeCall) -> None:
        self.log.calls.append(ma.Call(call.time, call.kind, call.team, call.robot, call.restart, call.position,
                                      call.rule, call.text))

    def robot_step(self, t: float, robot: str, step: AgentStep) -> None:
        if step.report.role == Role.GOALIE:
            self._goalie_cycles[robot] = self._goalie_cycles.get(robot, 0) + 1

    def finish(self) -> ma.MatchLog:
        """The log so far, with its tracks built (call once the match is over)."""
        times = np.array(self._times, dtype=float)
        log = self.log
        for name in list(self._positions):  # each model's numbers let go once its track is built
            indices, xs, ys = self._positions.pop(name)
            xy = np.empty((len(xs), 2))
            xy[:, 0], xy[:, 1] = np.frombuffer(xs), np.frombuffer(ys)
            log.tracks[name] = ma.Track(name, times[np.frombuffer(indices, dtype=np.intc)], xy)
            del indices, xs, ys
        log.goalies = ma.goalies_by_role(self._goalie_cycles)
        records: list[Any] = [*log.goals, *log.kicks, *log.touches, *log.referee, *log.coach, *log.calls]
        seen = [*((float(times.min()), float(times.max())) if len(times) else ()), *(r.t for r in records)]
        log.start, log.end = (float(min(seen)), float(max(seen))) if seen else (0.0, 0.0)
        return log


class MatchEvents(MatchListener):
    """Every event of a match as plain tuples, in order (for comparing two runs)."""

    def __init__(self) -> None:
        self.events: list[tuple] = []

    def sim_event(self, event: SimEvent) -> None:
        self.events.append((type(event).__name__, *(_plain(v) for v in vars(event).values())))

    def game_state(self, t: float, state: GameStateData) -> None:
        self.events.append(("GameState", t, state.score, state.half, round(state.game_time, 9), state.running,
                            state.last_event))

    def coach(self, t: float, team: str, mode: MatchMode, previous: MatchMode) -> None:
        self.events.append(("CoachInfo", t, team, int(mode), int(previous)))

    def referee_call(self, call: RefereeCall) -> None:
        self.events.append(("RefereeCall", call.time, call.kind, call.team, call.robot, call.restart))


def _plain(value: object) -> object:
    if isinstance(value, (BallState, RobotState)):
        return tuple(vars(value).values())
    return value

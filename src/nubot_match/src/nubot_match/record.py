"""What a lockstep match leaves behind, as it happens: the listeners of ``LockstepMatch``.

Requires: the engine's calls, in sim time [s] and the world frame [m]. Provides: ``MatchListener`` (the
calls a listener may take; every one optional), ``MatchLogRecorder`` (builds the ``MatchLog`` that
``nubot_match.match_analysis`` turns into the statistics of a report, the same records a bag gives),
and ``MatchEvents`` (every event as one plain tuple: what the determinism test compares).
"""

from __future__ import annotations

import mmap
import os
import tempfile
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
from nubot_match import match_analysis as ma
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


_BLOCK = 4096  # samples of a model kept in memory before they go to its file
_SAMPLE_BYTES = 16  # x, y


class _TrackSpill:
    """One model's positions as they come, in a file of its own: the latest ``_BLOCK`` samples in memory, the rest
    written out (x, y as float64, unchanged) and read back through a memory map once the match is over, so that a
    recording match's memory stays flat however long it plays. The file has no name (it is gone with the process);
    once the disk refuses a write (full, or a file size limit), the samples stay in memory from then on."""

    def __init__(self) -> None:
        self.runs: list[list[int]] = []  # [first, stop) of the sample indices the model was in
        self.pending = array("d")  # x, y, x, y, ... not yet written
        self.file: Any = tempfile.TemporaryFile(prefix="nubot-track-")
        self.size = 0  # bytes in the file, whole samples only
        self.spilling = True
        self.kept = array("d")  # after the file, what the disk refused

    def append(self, index: int, x: float, y: float) -> None:
        runs = self.runs
        if runs and runs[-1][1] == index:
            runs[-1][1] = index + 1
        else:
            runs.append([index, index + 1])
        self.pending.append(x)
        self.pending.append(y)
        if len(self.pending) >= 2 * _BLOCK:
            self._write()

    def _write(self) -> None:
        data = memoryview(self.pending).cast("B")
        written = 0
        if self.spilling:
            try:
                while written < len(data):
                    written += os.write(self.file.fileno(), data[written:])
            except OSError:
                self.spilling = False
                written -= written % _SAMPLE_BYTES
                os.ftruncate(self.file.fileno(), self.size + written)
            self.size += written
        self.kept.frombytes(data[written:])
        data.release()
        del self.pending[:]

    def positions(self) -> np.ndarray:
        """All the samples, (N, 2) [m]; call once, at the end."""
        self._write()
        parts = []
        if self.size:
            parts.append(np.frombuffer(mmap.mmap(self.file.fileno(), self.size, access=mmap.ACCESS_READ),
                                       dtype=float))
        self.file.close()
        if self.kept:
            parts.append(np.frombuffer(self.kept, dtype=float))
        flat = parts[0] if len(parts) == 1 else np.concatenate(parts) if parts else np.empty(0)
        return flat.reshape(-1, 2)


class MatchLogRecorder(MatchListener):
    """Builds a ``match_analysis.MatchLog`` directly, without a bag.

    The model states (every model at 100 Hz, 16 bytes a model and sample: most of what a match leaves, about 50 MiB
    for 2 x 15 min) go to unnamed files as they come and are read back through memory maps for the report, so the
    match's memory does not grow with its length (``_TrackSpill``)."""

    def __init__(self) -> None:
        self.log = ma.MatchLog()
        self._times = array("d")  # [s]
        self._positions: dict[str, _TrackSpill] = {}
        self._goalie_cycles: dict[str, int] = {}  # control cycles each robot announced itself goalie

    def start(self, world: WorldDescription, t: float) -> None:
        self.log.world = world

    def model_states(self, t: float, states: ModelStates) -> None:
        index = len(self._times)
        self._times.append(t)
        positions = self._positions
        for name, s in states:
            spill = positions.get(name)
            if spill is None:
                spill = positions[name] = _TrackSpill()
            spill.append(index, s.x, s.y)

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
        self._times = array("d")  # the copy above is what the tracks keep
        log = self.log
        for name in list(self._positions):
            spill = self._positions.pop(name)
            runs = spill.runs
            t = times if runs == [[0, len(times)]] else np.concatenate([times[a:b] for a, b in runs])
            log.tracks[name] = ma.Track(name, t, spill.positions())
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

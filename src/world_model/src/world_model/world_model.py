"""The world model of one robot (chapter 4.5): own perception + teammates + coach in one team-frame view.

Requires, as they arrive (sim time t [s], team frame):
  ``on_vision(frame)``                       own percepts (``RobotView``: self-localization, ball, obstacles);
  ``on_front_ball(stamp, relative)``         the front camera's ball, relative to this robot (FrontBallInfo);
  ``on_ball3d(ball)``                        the RGB-D cameras' ball in 3-D (``Ball3dPercept``, BallInfo3d);
  ``on_teammate(t, view)``                   a teammate's packet (TeamMessage via the team link);
  ``on_coach(t, mode, match_type, extras)``  a game command (CoachInfo); unknown values raise;
  ``on_strategy(t, report)``                 this robot's strategy (role, targets, pass command, target);
  ``on_teammate_strategy(t, report)``        a teammate's strategy (its pass command; that it still plays).
Provides: ``snapshot(t)`` -> ``WorldState`` (robots by AgentID with validity, fused ball, the ball's flight
in 3-D with its touchdown, labelled obstacles, game state with the time the command came into force, the
pass in force) and
``own_view(t)`` -> the ``RobotView`` this robot shares with its teammates.
Parameters: ``WorldModelParams`` and the match's ``WorldDescription`` (the field).
Rules: a robot (this one included) is valid while its state is fresh (``teammate_timeout``), it
reports itself valid and stands on the field (lines plus border); a teammate also stops being valid
when its strategy falls silent for ``strategy_timeout`` while the team's strategies are heard (its
control stopped: the others take over its role). Own perception older than ``ball_timeout`` is not
used; a ball seen outside the field plus border is a false detection. The ball comes from own
sensors first, in the original's order of trust among those that saw it within ``sensor_timeout``: omni
vision, then the front camera, then the RGB-D cameras (but the RGB-D ball while it flies: the cameras
that see the ball on the floor plane misplace a ball in the air); else the freshest own sighting within
``ball_timeout``; else the valid teammate nearest to its ball. A ball no valid robot sees is not known
and stays where it was last seen. Own obstacles are tracked from frame to frame (``ObstacleTracker``): the
snapshot has them smoothed, moved on to its time, with their velocities; the teammates get the smoothed positions.

The numbers are fused in C++ (``world_model._kernels.Fusion``, from ``cpp/fusion.cpp``: the clock, the robots'
validity, the ball tracks and their velocity fits, the choice of ball, its confidence, the obstacle tracks and
labels); this class keeps the records it was given (reports, balls, strategies, the game) and builds the
``WorldState`` and the shared ``RobotView`` from what the core decided.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING, Any, cast

from nubot_common.kernels import load_kernels
from nubot_common.percepts import Ball3dPercept, BallPercept, RobotReport, RobotView
from nubot_common.team_play import Point, StrategyReport
from nubot_common.world_description import WorldDescription
from nubot_common.world_state import (
    BallFlight,
    BallSensor,
    BallSource,
    CoachExtras,
    FusedBall,
    GameState,
    LabelledObstacle,
    ObstacleLabel,
    Teammate,
    WorldState,
)
from world_model import WorldModelError
from world_model.game import next_game_state, parse_coach_command, select_pass
from world_model.params import WorldModelParams

if TYPE_CHECKING:
    from world_model import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("world_model")

_SOURCES = {int(s): s for s in BallSource}
_SENSORS = {int(s): s for s in BallSensor}
_BallRow = tuple[float, float, float, float, float, bool]  # a ball the core decided: stamp, x, y, vx, vy, known
# A row of the core's obstacles (LabelledObstacle's fields in order) as the named tuple, without its field-by-field
# __new__: a dozen every cycle
_labelled_obstacle = cast(Callable[[tuple[Any, ...]], LabelledObstacle],
                          functools.partial(tuple.__new__, LabelledObstacle))
_TEAMMATE, _OPPONENT = ObstacleLabel.TEAMMATE, ObstacleLabel.OPPONENT


def _ball_row(ball: BallPercept | None) -> _BallRow | None:
    return None if ball is None else (ball.stamp, ball.x, ball.y, ball.vx, ball.vy, ball.velocity_known)


class WorldModel:
    """One robot's world model: feed it with the ``on_*`` methods, read it with ``snapshot``."""

    def __init__(self, params: WorldModelParams, agent_id: int, world: WorldDescription | None = None):
        if not 1 <= agent_id <= params.team_size:
            raise WorldModelError(f"agent_id must lie in 1..{params.team_size}, got {agent_id}")
        self.params = params
        self.agent_id = agent_id
        self.world = world or WorldDescription()
        field = self.world.field
        self._core = _kernels.Fusion(params, agent_id, field.half_length, field.half_width, field.border,
                                     self.world.ball.radius)
        self._game = GameState()
        self._noted = math.nan  # the time last given to the core's clock (only its clock keeps time)
        self._forget()

    def _forget(self) -> None:
        """The records given (the core forgets its numbers itself)."""
        self._vision: RobotView | None = None
        self._ball3d: Ball3dPercept | None = None
        self._mates: dict[int, RobotView] = {}
        self._strategy: StrategyReport | None = None
        self._mate_strategies: dict[int, StrategyReport] = {}
        self._made_report: tuple[RobotReport, StrategyReport, RobotReport] | None = None  # inputs and own report
        self._made_ball: tuple[_BallRow, BallPercept] | None = None  # the core's own ball and its record

    def _note_time(self, t: float) -> None:
        if t == self._noted:  # the core's clock has it already (a cycle's packets and strategies all come at t)
            return
        self._noted = t
        if self._core.note_time(t):  # the clock went back (a restarted simulation): everything is forgotten
            self._forget()

    def _teammate_id(self, agent_id: int, what: str) -> int:
        if not 1 <= agent_id <= self.params.team_size:
            raise WorldModelError(f"{what}: AgentID {agent_id} outside 1..{self.params.team_size}")
        return agent_id

    # --- inputs ---------------------------------------------------------------------------
    def on_vision(self, frame: RobotView) -> None:
        """Own percepts of the frame taken at ``frame.stamp``; ``frame.ball`` None when the ball is not seen."""
        self._note_time(frame.stamp)
        # The records are frozen: one that needs no change is kept as it is (replace costs microseconds, and
        # every robot takes several records a cycle).
        robot = frame.robot
        if robot.agent_id != self.agent_id:  # the sender's ID field may be unset on a real robot
            robot = replace(robot, agent_id=self.agent_id)
        pose = robot.pose
        kept = self._core.on_vision(frame.stamp, pose.x, pose.y, pose.theta, robot.valid, _ball_row(frame.ball),
                                    frame.obstacles)
        ball = frame.ball if kept else None
        self._vision = frame if robot is frame.robot and ball is frame.ball else replace(frame, robot=robot, ball=ball)

    def on_front_ball(self, stamp: float, relative: Point | None) -> None:
        """The front camera's ball at ``stamp`` [s]: (forward, left) [m] from this robot's centre; None: not seen.

        It is placed on the field with this robot's latest self-localization (ignored before there is one).
        """
        if relative is None:
            return
        rx, ry = relative
        if not all(math.isfinite(v) for v in (stamp, rx, ry)):
            raise WorldModelError(f"front camera ball must be finite, got {relative} at {stamp}")
        self._note_time(stamp)
        self._core.on_front_ball(stamp, rx, ry)

    def on_ball3d(self, ball: Ball3dPercept | None) -> None:
        """The RGB-D cameras' ball in 3-D (team frame); None: not seen."""
        if ball is None:
            return
        if not all(math.isfinite(v) for v in (ball.stamp, ball.x, ball.y, ball.z, ball.vx, ball.vy, ball.vz)):
            raise WorldModelError(f"3-D ball must be finite, got {ball}")
        self._note_time(ball.stamp)
        if self._core.on_ball3d(ball.stamp, ball.x, ball.y, ball.z, ball.vx, ball.vy, ball.vz, ball.velocity_known):
            self._ball3d = ball

    def on_teammate(self, t: float, view: RobotView) -> bool:
        """A teammate's shared state received at ``t``; False when ignored (this robot's own, or older)."""
        aid = view.robot.agent_id
        if aid == self.agent_id:
            return False
        self._teammate_id(aid, "teammate message")
        self._note_time(t)
        pose = view.robot.pose
        taken = self._core.on_teammate(t, aid, view.stamp, pose.x, pose.y, pose.theta, view.robot.valid,
                                       _ball_row(view.ball), view.obstacles)
        if taken is None:
            return False
        stamp, ball_kept = taken
        ball = view.ball if ball_kept else None
        if ball is not None and ball.stamp <= 0.0:
            ball = replace(ball, stamp=stamp)
        self._mates[aid] = view if stamp == view.stamp and ball is view.ball else replace(view, stamp=stamp, ball=ball)
        return True

    def on_coach(self, t: float, mode: int | str | bytes, match_type: int | str | bytes = 0,
                 extras: CoachExtras | None = None) -> GameState:
        """Apply a game command; an unknown MatchMode or MatchType raises and leaves the game state unchanged."""
        command = parse_coach_command(mode, match_type, extras)
        self._note_time(t)
        self._game = next_game_state(self._game, t, command)
        return self._game

    def on_strategy(self, t: float, strategy: StrategyReport) -> None:
        """This robot's own strategy (its role fields go into the state it shares)."""
        if strategy.agent_id not in (0, self.agent_id):
            raise WorldModelError(f"own strategy carries AgentID {strategy.agent_id}, this robot is {self.agent_id}")
        self._note_time(t)
        if strategy.agent_id != self.agent_id or not strategy.stamp > 0:
            strategy = replace(strategy, agent_id=self.agent_id, stamp=strategy.stamp if strategy.stamp > 0 else t)
        self._strategy = strategy

    def on_teammate_strategy(self, t: float, strategy: StrategyReport) -> bool:
        """A teammate's strategy received at ``t`` (its pass command; that it plays); False for this robot's own."""
        if strategy.agent_id == self.agent_id:
            return False
        self._teammate_id(strategy.agent_id, "teammate strategy")
        self._note_time(t)
        kept = strategy if strategy.stamp > 0 else replace(strategy, stamp=t)
        self._mate_strategies[strategy.agent_id] = kept
        self._core.on_teammate_strategy(strategy.agent_id, kept.stamp)
        return True

    # --- outputs --------------------------------------------------------------------------
    @property
    def game(self) -> GameState:
        return self._game

    def _own_report(self) -> RobotReport | None:
        if self._vision is None:
            return None
        report, s = self._vision.robot, self._strategy
        if s is None:
            return report
        made = self._made_report  # asked for twice a cycle (snapshot, own_view): made once per input
        if made is None or made[0] is not report or made[1] is not s:
            made = (report, s, report.replaced(role=s.role, role_time=s.role_time, target_nums=s.target_nums,
                                               static_pass=s.static_pass, static_catch=s.static_catch,
                                               target=s.target))
            self._made_report = made
        return made[2]

    def _own_ball(self, row: _BallRow | None) -> BallPercept | None:
        """The record of the own ball the core decided (made once per ball)."""
        if row is None:
            return None
        made = self._made_ball
        if made is None or made[0] != row:
            made = (row, BallPercept(*row))
            self._made_ball = made
        return made[1]

    def _flight(self, t: float) -> BallFlight | None:
        ball = self._ball3d
        if ball is None or t - ball.stamp > self.params.ball_timeout:
            return None
        return BallFlight.of(ball, self.world.ball.radius, self.params.air_margin)

    def own_view(self, t: float) -> RobotView | None:
        """What this robot shares: its state (role fields from its strategy), its own fresh ball and obstacles."""
        shared = self._core.own_view(t)
        report = self._own_report()
        if shared is None or self._vision is None or report is None:
            return None
        valid, ball, obstacles = shared
        if report.valid != valid:
            report = replace(report, valid=valid)
        return RobotView(self._vision.stamp, report, self._own_ball(ball), obstacles)

    def snapshot(self, t: float) -> WorldState:
        """The fused world model at ``t`` (also remembers the last fused ball position)."""
        self._note_time(t)
        states, own, mate_balls, fused, labelled = self._core.snapshot(t, _TEAMMATE, _OPPONENT)
        me, mates = self.agent_id, self._mates
        robots = tuple(Teammate(aid, valid, age, self._own_report() if aid == me else
                                (mates[aid].robot if aid in mates else None))
                       for aid, (valid, age) in enumerate(states, start=1))
        own_ball = self._own_ball(own)
        team_balls = tuple(own_ball if aid == me else (mates[aid].ball if counts else None)
                           for aid, counts in enumerate(mate_balls, start=1))
        x, y, vx, vy, known, moving, confidence, seen_by, source, source_id, stamp, angle, radius, sensor = fused
        ball = FusedBall(x, y, vx, vy, known, moving, confidence, seen_by, _SOURCES[source], source_id, stamp, angle,
                         radius, _SENSORS[sensor])
        obstacles = tuple(map(_labelled_obstacle, labelled))
        strategies = [s for s in (self._strategy, *self._mate_strategies.values()) if s is not None]
        p = self.params
        pass_cmd = select_pass(me, strategies, t, p.teammate_timeout, p.team_size)
        return WorldState(t, me, robots, ball, team_balls, obstacles, self._game, pass_cmd, self._flight(t))

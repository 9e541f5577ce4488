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
"""

from __future__ import annotations

import math
from dataclasses import replace

from nubot_common.geometry import Pose2D
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
    Teammate,
    WorldState,
)
from world_model import WorldModelError
from world_model.ball_fusion import BallCandidate, BallTrack, agreeing, ball_confidence, choose_ball
from world_model.game import next_game_state, parse_coach_command, select_pass
from world_model.obstacles import ObstacleTracker, label_obstacles
from world_model.params import WorldModelParams

_TIME_JUMP = 1.0  # the clock going back by more than this means a restarted simulation: forget everything [s]
_MAX_HEIGHT = 20.0  # a 3-D ball higher than this is a false detection [m]


class WorldModel:
    """One robot's world model: feed it with the ``on_*`` methods, read it with ``snapshot``."""

    def __init__(self, params: WorldModelParams, agent_id: int, world: WorldDescription | None = None):
        if not 1 <= agent_id <= params.team_size:
            raise WorldModelError(f"agent_id must lie in 1..{params.team_size}, got {agent_id}")
        self.params = params
        self.agent_id = agent_id
        self.world = world or WorldDescription()
        self._keep = max(params.velocity_window, params.ball_timeout) + 0.1  # history kept per ball track [s]
        self._clock = -math.inf
        self._game = GameState()
        self._obstacles = ObstacleTracker(params.obstacle_gate, params.obstacle_position_gain,
                                          params.obstacle_velocity_gain, params.obstacle_coast,
                                          params.obstacle_max_speed)
        self._forget()

    def _forget(self) -> None:
        self._vision: RobotView | None = None
        self._obstacles.reset()
        self._own_track = BallTrack(self._keep)  # omni vision
        self._front_track = BallTrack(self._keep)
        self._rgbd_track = BallTrack(self._keep)  # the 3-D ball's ground projections
        self._ball3d: Ball3dPercept | None = None
        self._mates: dict[int, RobotView] = {}
        self._mate_tracks: dict[int, BallTrack] = {}
        self._strategy: StrategyReport | None = None
        self._mate_strategies: dict[int, StrategyReport] = {}
        self._last_ball: Point | None = None
        self._made_report: tuple[RobotReport, StrategyReport, RobotReport] | None = None  # inputs and own report
        self._made_ball: tuple[BallPercept, tuple[float, float] | None, BallPercept, BallSensor] | None = None

    def _note_time(self, t: float) -> None:
        if t < self._clock - _TIME_JUMP:
            self._forget()
            self._clock = t
        else:
            self._clock = max(self._clock, t)

    def _teammate_id(self, agent_id: int, what: str) -> int:
        if not 1 <= agent_id <= self.params.team_size:
            raise WorldModelError(f"{what}: AgentID {agent_id} outside 1..{self.params.team_size}")
        return agent_id

    def _on_field(self, x: float, y: float) -> bool:
        field = self.world.field
        return field.is_inside(x, y, field.border)

    def _plausible(self, ball: BallPercept | None) -> BallPercept | None:
        return ball if ball is not None and self._on_field(ball.x, ball.y) else None

    # --- inputs ---------------------------------------------------------------------------
    def on_vision(self, frame: RobotView) -> None:
        """Own percepts of the frame taken at ``frame.stamp``; ``frame.ball`` None when the ball is not seen."""
        self._note_time(frame.stamp)
        # The records are frozen: one that needs no change is kept as it is (replace costs microseconds, and
        # every robot takes several records a cycle).
        robot = frame.robot
        if robot.agent_id != self.agent_id:  # the sender's ID field may be unset on a real robot
            robot = replace(robot, agent_id=self.agent_id)
        ball = self._plausible(frame.ball)
        self._vision = frame if robot is frame.robot and ball is frame.ball else replace(frame, robot=robot, ball=ball)
        self._obstacles.update(frame.stamp, frame.obstacles)
        if ball is not None:
            self._own_track.add(ball)

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
        if self._vision is None:
            return
        ball = self._plausible(BallPercept(stamp, *self._vision.robot.pose.to_world(rx, ry)))
        if ball is not None:
            self._front_track.add(ball)

    def on_ball3d(self, ball: Ball3dPercept | None) -> None:
        """The RGB-D cameras' ball in 3-D (team frame); None: not seen."""
        if ball is None:
            return
        if not all(math.isfinite(v) for v in (ball.stamp, ball.x, ball.y, ball.z, ball.vx, ball.vy, ball.vz)):
            raise WorldModelError(f"3-D ball must be finite, got {ball}")
        self._note_time(ball.stamp)
        if not (self._on_field(ball.x, ball.y) and -self.world.ball.radius <= ball.z <= _MAX_HEIGHT):
            return
        if self._ball3d is not None and ball.stamp <= self._ball3d.stamp:
            return  # a repeat or a late one
        self._ball3d = ball
        self._rgbd_track.add(ball.on_ground())

    def on_teammate(self, t: float, view: RobotView) -> bool:
        """A teammate's shared state received at ``t``; False when ignored (this robot's own, or older)."""
        aid = view.robot.agent_id
        if aid == self.agent_id:
            return False
        self._teammate_id(aid, "teammate message")
        self._note_time(t)
        stamp = view.stamp if view.stamp > 0.0 else t
        previous = self._mates.get(aid)
        if previous is not None and previous.stamp - _TIME_JUMP <= stamp < previous.stamp:
            return False
        ball = self._plausible(view.ball)
        if ball is not None and ball.stamp <= 0.0:
            ball = replace(ball, stamp=stamp)
        self._mates[aid] = view if stamp == view.stamp and ball is view.ball else replace(view, stamp=stamp, ball=ball)
        if ball is not None:
            self._mate_tracks.setdefault(aid, BallTrack(self._keep)).add(ball)
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
        self._mate_strategies[strategy.agent_id] = strategy if strategy.stamp > 0 else replace(strategy, stamp=t)
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
            made = (report, s, replace(report, role=s.role, role_time=s.role_time, target_nums=s.target_nums,
                                       static_pass=s.static_pass, static_catch=s.static_catch, target=s.target))
            self._made_report = made
        return made[2]

    def _playing(self, t: float, agent_id: int) -> bool:
        """A teammate plays unless its strategy fell silent while others' are heard (its control stopped)."""
        if agent_id == self.agent_id or not self._mate_strategies:
            return True
        strategy = self._mate_strategies.get(agent_id)
        return strategy is not None and t - strategy.stamp <= self.params.strategy_timeout

    def _robot(self, t: float, agent_id: int) -> Teammate:
        if agent_id == self.agent_id:
            report, stamp = self._own_report(), self._vision.stamp if self._vision else -math.inf
        else:
            view = self._mates.get(agent_id)
            report, stamp = (view.robot, view.stamp) if view else (None, -math.inf)
        age = max(0.0, t - stamp)
        valid = (report is not None and report.valid and age <= self.params.teammate_timeout
                 and self._on_field(report.pose.x, report.pose.y) and self._playing(t, agent_id))
        return Teammate(agent_id, valid, age, report)

    def _flying(self, t: float) -> Ball3dPercept | None:
        """The fresh 3-D ball while it flies."""
        ball = self._ball3d
        if ball is None or t - ball.stamp > self.params.sensor_timeout:
            return None
        return ball if ball.z > self.world.ball.radius + self.params.air_margin else None

    def _own_sighting(self, t: float) -> tuple[BallTrack, BallSensor] | None:
        """The own sensor to believe at ``t``, with its track."""
        p = self.params
        if self._flying(t) is not None:
            return self._rgbd_track, BallSensor.RGBD
        sensors = ((self._own_track, BallSensor.OMNI), (self._front_track, BallSensor.FRONT),
                   (self._rgbd_track, BallSensor.RGBD))  # the order of trust
        recent = [(track, sensor, latest.stamp) for track, sensor in sensors
                  if (latest := track.latest) is not None and t - latest.stamp <= p.ball_timeout]
        for track, sensor, stamp in recent:
            if t - stamp <= p.sensor_timeout:
                return track, sensor
        if not recent:
            return None
        track, sensor, _ = max(recent, key=lambda r: r[2])  # the freshest; max keeps the first of equals
        return track, sensor

    def _own_ball(self, t: float) -> BallPercept | None:
        sighting = self._own_sighting(t)
        if sighting is None:
            return None
        track, sensor = sighting
        latest = track.latest
        assert latest is not None
        flying = self._flying(t) if sensor is BallSensor.RGBD else None
        if flying is not None and flying.velocity_known:
            velocity: tuple[float, float] | None = (flying.vx, flying.vy)  # the parabola's, fitted by the cameras
        else:
            velocity = track.velocity(self.params.velocity_window, self.params.min_fit_samples)
        made = self._made_ball  # asked for twice a cycle (snapshot, own_view): made once per input
        if made is None or made[0] is not latest or made[1] != velocity:
            vx, vy = velocity or (0.0, 0.0)
            made = (latest, velocity, replace(latest, vx=vx, vy=vy, velocity_known=velocity is not None), sensor)
            self._made_ball = made
        return made[2]

    def _flight(self, t: float) -> BallFlight | None:
        ball = self._ball3d
        if ball is None or t - ball.stamp > self.params.ball_timeout:
            return None
        return BallFlight.of(ball, self.world.ball.radius, self.params.air_margin)

    def _mate_ball(self, t: float, agent_id: int) -> BallPercept | None:
        view = self._mates.get(agent_id)
        if view is None or view.ball is None or t - view.ball.stamp > self.params.ball_timeout:
            return None
        return view.ball

    def own_view(self, t: float) -> RobotView | None:
        """What this robot shares: its state (role fields from its strategy), its own fresh ball and obstacles."""
        me = self._robot(t, self.agent_id)
        if self._vision is None or me.report is None:
            return None
        fresh = t - self._vision.stamp <= self.params.ball_timeout
        report = me.report if me.report.valid == me.valid else replace(me.report, valid=me.valid)
        return RobotView(self._vision.stamp, report, self._own_ball(t),
                         self._obstacles.estimate(self._vision.stamp)[0] if fresh else ())

    def snapshot(self, t: float) -> WorldState:
        """The fused world model at ``t`` (also remembers the last fused ball position)."""
        self._note_time(t)
        p = self.params
        robots = tuple(self._robot(t, aid) for aid in range(1, p.team_size + 1))
        me_pose = self._vision.robot.pose if self._vision else Pose2D()
        mates = [r for r in robots if r.valid and r.agent_id != self.agent_id]
        team_balls = tuple(self._own_ball(t) if aid == self.agent_id else
                           self._mate_ball(t, aid) if robots[aid - 1].valid else None
                           for aid in range(1, p.team_size + 1))
        own_ball = team_balls[self.agent_id - 1]
        own = (BallCandidate(self.agent_id, BallSource.OWN, own_ball, me_pose, max(0.0, t - own_ball.stamp))
               if own_ball is not None else None)
        team = [BallCandidate(m.agent_id, BallSource.TEAMMATE, seen, m.report.pose, max(0.0, t - seen.stamp))
                for m in mates if (seen := team_balls[m.agent_id - 1]) is not None and m.report is not None]
        ball = self._fuse_ball(choose_ball(own, team), [c for c in (own, *team) if c is not None], me_pose)
        vision = self._vision
        own_obstacles, velocities = (self._obstacles.estimate(t) if vision is not None and
                                     t - vision.stamp <= p.ball_timeout else ((), ()))
        obstacles = label_obstacles(
            me_pose, self.agent_id, own_obstacles,
            {m.agent_id: self._mates[m.agent_id].obstacles for m in mates},
            {m.agent_id: (m.report.pose.x, m.report.pose.y) for m in mates if m.report is not None},
            p.teammate_radius, p.obstacle_merge_radius, velocities)
        strategies = [s for s in (self._strategy, *self._mate_strategies.values()) if s is not None]
        pass_cmd = select_pass(self.agent_id, strategies, t, p.teammate_timeout, p.team_size)
        return WorldState(t, self.agent_id, robots, ball, team_balls, obstacles, self._game, pass_cmd,
                          self._flight(t))

    def _fuse_ball(self, chosen: BallCandidate | None, candidates: list[BallCandidate], me: Pose2D) -> FusedBall:
        p = self.params
        if chosen is None:
            x, y = self._last_ball if self._last_ball is not None else (0.0, 0.0)
            return FusedBall(x, y, known=False, angle=me.bearing_to(x, y), radius=me.distance_to(x, y))
        obs = chosen.observation
        sensor = BallSensor.NONE
        if chosen.source is BallSource.OWN:
            velocity = (obs.vx, obs.vy) if obs.velocity_known else None  # already fitted by _own_ball
            sensor = self._made_ball[3] if self._made_ball is not None else BallSensor.NONE
        else:
            track = self._mate_tracks.get(chosen.agent_id)
            velocity = track.velocity(p.velocity_window, p.min_fit_samples) if track is not None else None
            if velocity is None and obs.velocity_known:
                velocity = (obs.vx, obs.vy)  # the teammate's own fit
        vx, vy = velocity or (0.0, 0.0)
        seen_by = agreeing(candidates, obs.x, obs.y, p.ball_agreement_radius)
        self._last_ball = (obs.x, obs.y)
        return FusedBall(obs.x, obs.y, vx, vy, True, velocity is not None,
                         ball_confidence(chosen.age, len(seen_by), p.ball_timeout, p.sighting_confidence),
                         seen_by, chosen.source, chosen.agent_id, obs.stamp,
                         me.bearing_to(obs.x, obs.y), me.distance_to(obs.x, obs.y), sensor)

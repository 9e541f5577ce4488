"""The view of the world one robot's strategy reads each cycle: the world model's decision, reshaped.

Requires: a ``WorldState`` (the world model's decision), the control time [s], the goalie's AgentID
and the field. Provides: ``TeamState`` and ``team_state`` which builds it without deciding anything
again: the robots the world model holds valid (this robot apart; each teammate where its packet's age
puts it now), its fused ball (known or where it was last seen) and its flight in 3-D, the obstacles it
labels opponents (moved on from the world model's time at their tracked velocity), the game command with
the time it came into force, the pass it holds in force. The team frame has the own goal at -x and the
opponent goal at +x.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

from nubot_common.field import FieldGeometry
from nubot_common.match_mode import MatchMode
from nubot_common.percepts import RobotReport
from nubot_common.records import fast_init
from nubot_common.team_play import PassCommand, Point
from nubot_common.world_state import BallFlight, FusedBall, ObstacleLabel, WorldState

MAX_PREDICTION = 0.3  # [s] a teammate is moved on by at most this (the world model's teammate_timeout)


@fast_init
@dataclass(frozen=True)
class TeamState:
    time: float  # [s], sim time of this control cycle
    me: RobotReport
    mates: tuple[RobotReport, ...]  # valid teammates, without me, moved on to ``time`` (``team_state``)
    ball: FusedBall  # check ``ball.known``: when not, (x, y) is where it was last seen
    opponents: tuple[Point, ...]  # obstacle positions labelled opponents [m], moved on to ``time``
    field: FieldGeometry
    mode: MatchMode = MatchMode.STOPROBOT
    previous_mode: MatchMode = MatchMode.STOPROBOT
    mode_since: float = 0.0  # [s] sim time the command came into force
    pass_cmd: PassCommand | None = None  # the pass in force
    goalie_id: int = 1
    flight: BallFlight | None = None  # the ball in 3-D with its touchdown (a goalie's RGB-D cameras), if fresh

    @cached_property  # read several times a cycle: sorted once, kept in the (frozen) instance's __dict__
    def team(self) -> tuple[RobotReport, ...]:
        """All valid robots of the team, me included, by AgentID."""
        return tuple(sorted((self.me, *self.mates), key=lambda m: m.agent_id))

    def obstacles(self) -> list[tuple[float, float]]:
        """Everything to avoid except me: teammates and opponents [m]."""
        return [(m.pose.x, m.pose.y) for m in self.mates] + list(self.opponents)


def team_state(world: WorldState, time: float, goalie_id: int, field: FieldGeometry) -> TeamState | None:
    """The strategy's view of ``world`` at control time ``time``; None while the robot itself is not valid.

    Each teammate is where its last packet puts it now: moved on at its reported velocity for the packet's age at
    ``time`` (at most ``MAX_PREDICTION``). Two teammates closing at 3 m/s on packets 50-70 ms old would each
    see the other 0.15-0.2 m farther than it is, more than the contact guard's margin. The opponents are where
    the world model put them at its time (its tracks moved on to it), moved on at their velocity to ``time``."""
    me = world.me
    if not me.valid or me.report is None:
        return None
    since = max(0.0, time - world.stamp)  # the world model's decision is this old; each packet older by its age
    aid = world.agent_id
    mates = tuple(r.report.moved_on(min(r.age + since, MAX_PREDICTION)) for r in world.robots
                  if r.agent_id != aid and r.valid and r.report is not None)
    ahead = min(since, MAX_PREDICTION)
    opponent = ObstacleLabel.OPPONENT
    opponents = tuple((o.x + o.vx * ahead, o.y + o.vy * ahead) for o in world.obstacles if o.label is opponent)
    game = world.game
    return TeamState(time, me.report, mates, world.ball, opponents, field,
                     game.mode, game.previous, game.since, world.pass_cmd, goalie_id, world.flight)

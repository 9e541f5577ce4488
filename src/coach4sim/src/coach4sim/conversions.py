"""Conversions between ROS messages and the coach's core types (the only place that knows both).

Requires: generated ``nubot_common`` messages, ``genpy`` (no rospy).
Provides: ``game_state_msg`` (GameState), ``referee_call_msg`` (RefereeCall: a foul or another call),
``score_view`` (GameState -> ``console.ScoreView``), ``world_from_model_states``
(ModelStates -> ball centre and robot positions, world frame [m]), ``ball_placement``
(a ModelState putting the ball at rest on the carpet) and ``watch_view``
(WorldModelInfo + GameState -> ``console.WatchView``) and ``refbox_view`` (one robot's WorldModelInfo and
StrategyInfo -> what the RefBox worldstate reports of it: ``refbox.RobotSnapshot``, ``refbox.BallSnapshot``,
the opponents it sees). CoachInfo and WorldModelInfo are ``nubot_common.conversions``'.
"""

from __future__ import annotations

from coach4sim.console import ScoreView, WatchView
from coach4sim.fouls import RefereeCall as Call
from coach4sim.game import GameStateData
from coach4sim.refbox import BallSnapshot, RobotSnapshot
from nubot_common import NubotCommonError
from nubot_common.conversions import model_state_msg, stamp, world_state
from nubot_common.msg import GameState, ModelState, ModelStates, Point3d, RefereeCall, StrategyInfo, WorldModelInfo
from nubot_common.naming import parse_robot_name
from nubot_common.team_play import Role
from nubot_common.world_state import BallSource, ObstacleLabel


def game_state_msg(state: GameStateData, t: float) -> GameState:
    msg = GameState(teams=list(state.teams), score=list(state.score), attack=list(state.attack),
                    match_mode=bytes(int(m) for m in state.match_mode), half=state.half,
                    game_time=state.game_time, running=state.running, last_event=state.last_event)
    msg.header.stamp = stamp(t)
    return msg


def referee_call_msg(call: Call) -> RefereeCall:
    msg = RefereeCall(kind=call.kind, team=call.team, robot=call.robot, restart=call.restart, rule=call.rule,
                      text=call.text)
    msg.header.stamp = stamp(call.time)
    msg.position = Point3d(call.position[0], call.position[1], 0.0)
    return msg


def score_view(msg: GameState) -> ScoreView:
    return ScoreView(tuple(msg.teams), tuple(msg.score), int(msg.half), float(msg.game_time), bool(msg.running),
                     msg.last_event)


def world_from_model_states(msg: ModelStates, ball_name: str
                            ) -> tuple[tuple[float, float, float] | None, dict[str, tuple[float, float]]]:
    """The ball centre (None if absent) and every other model's position, world frame [m]."""
    ball = None
    robots: dict[str, tuple[float, float]] = {}
    for name, pose in zip(msg.name, msg.pose):
        p = pose.position
        if name == ball_name:
            ball = (p.x, p.y, p.z)
        else:
            robots[name] = (p.x, p.y)
    return ball, robots


def ball_placement(ball_name: str, x: float, y: float, radius: float) -> ModelState:
    """The ball at (x, y) on the carpet, at rest, world frame [m]."""
    return model_state_msg(ball_name, x, y, radius)


def watch_view(robot: str, wm: WorldModelInfo, state: GameState | None) -> WatchView:
    """What ``coach --watch`` shows of ``robot``'s world model (team frame) and the referee's state."""
    try:
        world = world_state(wm, parse_robot_name(robot).agent_id)
    except NubotCommonError:
        return WatchView(robot=robot, stamp=wm.header.stamp.to_sec(),
                         score=score_view(state) if state is not None else None)
    me = world.me
    ball = world.ball
    source = {BallSource.OWN: "own", BallSource.TEAMMATE: "team"}.get(ball.source, "")
    return WatchView(
        robot=robot, stamp=world.stamp, pose=(me.pose.x, me.pose.y, me.pose.theta) if me.valid and me.pose else None,
        ball=ball.position if ball.known else None, ball_source=source if ball.known else "",
        teammates=tuple((r.agent_id, r.pose.x, r.pose.y) for r in world.teammates if r.valid and r.pose),
        opponents=tuple((o.x, o.y) for o in world.opponents),
        mode=int(world.game.mode), previous=int(world.game.previous),
        score=score_view(state) if state is not None else None)


def refbox_view(wm: WorldModelInfo, agent_id: int, strategy: StrategyInfo | None, battery_level: float
                ) -> tuple[RobotSnapshot | None, BallSnapshot | None, list[tuple[float, float]]]:
    """Robot ``agent_id`` as its own world model has it (None unless it is valid), the ball it believes in
    (None if unknown) and the opponents it sees; team frame. Its intention is its strategy's role (the world
    model's if no strategy is given), its target the world model's (none without a strategy), and it holds the
    ball if either says so."""
    try:
        world = world_state(wm, agent_id)
    except NubotCommonError:
        return None, None, []
    me = world.me
    robot = None
    if me.valid and me.report is not None:
        r = me.report
        role = Role.of(int(strategy.role)) if strategy is not None else r.role
        holding = r.holding or (strategy is not None and bool(strategy.is_dribble))
        target = r.target if strategy is not None else None  # without control, RobotInfo.target is unset
        robot = RobotSnapshot(agent_id, r.pose.x, r.pose.y, r.pose.theta, r.vx, r.vy, r.w, target, role.name,
                              holding, battery_level)
    b = world.ball
    ball = BallSnapshot(b.x, b.y, b.vx if b.velocity_known else 0.0, b.vy if b.velocity_known else 0.0,
                        b.source == BallSource.OWN, b.stamp) if b.known else None
    opponents = [(o.x, o.y) for o in world.obstacles if o.label == ObstacleLabel.OPPONENT]
    return robot, ball, opponents

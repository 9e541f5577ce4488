"""Conversions between ROS messages and the coach's core types (the only place that knows both).

Requires: generated ``nubot_common`` messages, ``genpy`` (no rospy).
Provides: ``coach_info_msg`` (CoachInfo for one team), ``game_state_msg`` (GameState),
``score_view`` (GameState -> ``console.ScoreView``), ``world_from_model_states``
(ModelStates -> ball centre and robot positions, world frame [m]), ``ball_placement``
(a ModelState putting the ball at rest on the carpet) and ``watch_view``
(WorldModelInfo + GameState -> ``console.WatchView``).
"""

from __future__ import annotations

import genpy

from coach4sim.console import ScoreView, WatchView
from coach4sim.game import GameStateData
from nubot_common.msg import CoachInfo, GameState, ModelState, ModelStates, WorldModelInfo


def stamp(t: float) -> genpy.Time:
    return genpy.Time.from_sec(max(t, 0.0))


def coach_info_msg(mode: int, previous: int, t: float) -> CoachInfo:
    msg = CoachInfo(MatchMode=int(mode), MatchType=int(previous))
    msg.header.stamp = stamp(t)
    return msg


def game_state_msg(state: GameStateData, t: float) -> GameState:
    msg = GameState(teams=list(state.teams), score=list(state.score), attack=list(state.attack),
                    match_mode=bytes(int(m) for m in state.match_mode), half=state.half,
                    game_time=state.game_time, running=state.running, last_event=state.last_event)
    msg.header.stamp = stamp(t)
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
    state = ModelState(model_name=ball_name, reference_frame="world")
    state.pose.position.x, state.pose.position.y, state.pose.position.z = x, y, radius
    state.pose.orientation.w = 1.0
    return state


def _agent_id(robot: str) -> int:
    digits = robot[len(robot.rstrip("0123456789")):]
    return int(digits) if digits else 0


def watch_view(robot: str, wm: WorldModelInfo, state: GameState | None) -> WatchView:
    """What ``coach --watch`` shows of ``robot``'s world model (team frame) and the referee's state."""
    me = _agent_id(robot)
    pose = None
    teammates = []
    for index, info in enumerate(wm.robotinfo):
        agent = info.AgentID or index + 1
        if agent == me:
            if info.isvalid:
                pose = (info.pos.x, info.pos.y, info.heading.theta)
        elif info.isvalid:
            teammates.append((agent, info.pos.x, info.pos.y))
    ball, source = None, ""
    own = wm.ballinfo[me - 1] if 0 < me <= len(wm.ballinfo) else None
    if own is not None and own.pos_known:
        ball, source = (own.pos.x, own.pos.y), "own"
    else:
        seen = next((b for b in wm.ballinfo if b.pos_known), None)
        if seen is not None:
            ball, source = (seen.pos.x, seen.pos.y), "team"
    return WatchView(
        robot=robot, stamp=wm.header.stamp.to_sec(), pose=pose, ball=ball, ball_source=source,
        teammates=tuple(teammates), opponents=tuple((p.x, p.y) for p in wm.oppinfo.pos),
        mode=int(wm.coachinfo.MatchMode), previous=int(wm.coachinfo.MatchType),
        score=score_view(state) if state is not None else None)

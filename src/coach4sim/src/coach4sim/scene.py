"""What the match viewer draws: the field once, then one frame of the match at a time, as plain JSON-ready data.

Requires: the match's ``WorldDescription``; then, in any order, messages of the match (rospy's or rosbags'
deserialised ones: only field names are read): ``ModelStates`` (world frame, every model), ``GameState``
(the referee), one team's ``TeamMessages`` (each robot's role and target, team frame), a robot's
``PlannedPath`` (team frame), a robot's ``StrategyInfo`` (its role, when no ``TeamMessages`` carry it: bags of
lockstep matches) and a robot's ``WorldModelInfo`` (what it believes, team frame).
Provides: ``field_layout(world)`` (every marking and both goals, world frame [m]) and ``Scene``, whose
``frame(watch)`` returns the latest state in the world frame [m], [rad]: each robot (team, number, pose,
role, target, planned path), the ball (with its height), the referee's score, half, clock and last decisions
and, for the robot named ``watch``, its world model.

Team-frame values are turned into the world frame with the team's ``TeamFrame``: the goal it attacks comes
from the referee; before the referee has said, a team attacks +x (the frame of a team playing alone).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from typing import Any

from nubot_common.field import FieldGeometry
from nubot_common.match_mode import MatchMode
from nubot_common.naming import is_robot_name, parse_robot_name, team_colour
from nubot_common.team_frame import TeamFrame
from nubot_common.team_play import Role
from nubot_common.world_description import WorldDescription

EVENTS_KEPT = 6  # the referee's last decisions shown


def stamp_seconds(stamp: Any) -> float:
    """A header stamp [s], from rospy (``secs``/``nsecs``) or rosbags (``sec``/``nanosec``)."""
    if hasattr(stamp, "secs"):
        return stamp.secs + stamp.nsecs * 1e-9
    return stamp.sec + stamp.nanosec * 1e-9


def _r(value: float, digits: int = 3) -> float | None:
    """A number for the page: rounded, None for NaN or infinity (JSON has neither)."""
    return round(float(value), digits) if math.isfinite(value) else None


def field_layout(world: WorldDescription) -> dict[str, Any]:
    """The field as the page draws it, world frame [m] and [rad]."""
    f: FieldGeometry = world.field
    goals = []
    for side in (1, -1):
        (x0, y0), (x1, y1) = f.goal_posts(side)
        goals.append({"side": side, "posts": [[x0, y0], [x1, y1]], "depth": f.goal_depth,
                      "height": f.goal_height, "post_radius": f.post_radius})
    return {
        "name": world.name, "length": f.length, "width": f.width, "border": f.border, "line_width": f.line_width,
        "segments": [[list(a), list(b)] for a, b in f.line_segments()],
        "arcs": [{"x": a.x, "y": a.y, "radius": a.radius, "start": a.start, "end": a.end} for a in f.arcs()],
        "spots": [list(s) for s in f.spots()], "spot_radius": f.spot_diameter / 2.0,
        "goals": goals, "robot_radius": world.robot.radius, "ball_radius": world.ball.radius,
        "ball_name": world.ball_name,
    }


def _yaw(q: Any) -> float:
    """Heading [rad] of a planar pose's quaternion."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


@dataclass
class _Referee:
    teams: tuple[str, ...] = ()
    score: tuple[int, ...] = ()
    attack: tuple[int, ...] = ()
    modes: tuple[str, ...] = ()
    half: int = 0
    game_time: float = 0.0
    running: bool = False


class Scene:
    """The latest state of a match, fed message by message; ``frame`` draws it (not thread-safe: lock around)."""

    def __init__(self, world: WorldDescription):
        self.world = world
        self.t = 0.0  # sim time of the latest message [s]
        self._states: Any = None  # the latest ModelStates, converted only when a frame is drawn
        self._referee = _Referee()
        self._referee_seen = False
        self._events: deque[tuple[float, str]] = deque(maxlen=EVENTS_KEPT)
        self._last_event = ""
        self._team_info: dict[str, dict[int, Any]] = {}  # team -> AgentID -> RobotInfo
        self._paths: dict[str, list[tuple[float, float]]] = {}  # robot -> planned path, team frame
        self._roles: dict[str, int] = {}  # robot -> role from its StrategyInfo
        self._beliefs: dict[str, Any] = {}  # robot -> its latest WorldModelInfo
        self.teams_seen: list[str] = []  # teams in the order first seen (model states, then the rest)

    # ---- input ------------------------------------------------------------------------------------------------

    def on_model_states(self, msg: Any) -> None:
        self._states = msg
        if hasattr(msg, "header"):
            self.t = max(self.t, stamp_seconds(msg.header.stamp))
        for name in msg.name:
            if is_robot_name(name):
                self._see_team(parse_robot_name(name).team)

    def on_referee(self, msg: Any) -> None:
        modes = msg.match_mode
        names = []
        for m in (modes.encode("latin-1") if isinstance(modes, str) else bytes(modes)):
            names.append(MatchMode(m).name if m in MatchMode._value2member_map_ else str(m))
        self._referee = _Referee(tuple(msg.teams), tuple(int(s) for s in msg.score),
                                 tuple(int(a) for a in msg.attack), tuple(names), int(msg.half),
                                 float(msg.game_time), bool(msg.running))
        self._referee_seen = True
        for team in msg.teams:
            self._see_team(team)
        t = stamp_seconds(msg.header.stamp)
        self.t = max(self.t, t)
        if msg.last_event and msg.last_event != self._last_event:
            self._events.append((t, msg.last_event))
        self._last_event = msg.last_event

    def on_teammates(self, team: str, msg: Any) -> None:
        """One team's ``TeamMessages``: the role and target of each robot that reported."""
        info = self._team_info.setdefault(team, {})
        for m in msg.messages:
            info[int(m.robot.AgentID)] = m.robot

    def on_path(self, robot: str, msg: Any) -> None:
        self._paths[robot] = [(p.x, p.y) for p in msg.points]

    def on_strategy(self, robot: str, msg: Any) -> None:
        self._roles[robot] = int(msg.role)

    def on_world_model(self, robot: str, msg: Any) -> None:
        self._beliefs[robot] = msg

    def _see_team(self, team: str) -> None:
        if team not in self.teams_seen:
            self.teams_seen.append(team)

    # ---- output -----------------------------------------------------------------------------------------------

    @property
    def teams(self) -> list[str]:
        """The referee's teams first, then the others seen."""
        ordered = list(self._referee.teams)
        return ordered + [t for t in self.teams_seen if t not in ordered]

    def colour(self, team: str) -> str:
        return team_colour(team, self.teams)  # the referee's teams first, then as seen

    def frame_of(self, team: str) -> TeamFrame:
        ref = self._referee
        if team in ref.teams and len(ref.attack) == len(ref.teams):
            attack = ref.attack[ref.teams.index(team)]
            if attack in (1, -1):
                return TeamFrame(attack)
        return TeamFrame(1)

    def frame(self, watch: str = "") -> dict[str, Any]:
        """The match now, world frame; ``watch``: a robot whose world model is drawn too ("" none)."""
        robots, ball = [], None
        frames = {team: self.frame_of(team) for team in self.teams}
        msg = self._states
        if msg is not None:
            for name, pose, twist in zip(msg.name, msg.pose, msg.twist):
                p = pose.position
                if name == self.world.ball_name:
                    v = twist.linear
                    ball = {"x": _r(p.x), "y": _r(p.y), "z": _r(p.z), "vx": _r(v.x, 2), "vy": _r(v.y, 2),
                            "vz": _r(v.z, 2)}
                elif is_robot_name(name):
                    robots.append(self._robot(name, p.x, p.y, _yaw(pose.orientation), frames))
        ref = self._referee
        referee = {"teams": list(ref.teams), "score": list(ref.score), "attack": list(ref.attack),
                   "modes": list(ref.modes), "half": ref.half, "game_time": _r(ref.game_time, 1),
                   "running": ref.running, "seen": self._referee_seen,
                   "events": [{"t": _r(t, 1), "text": text} for t, text in self._events]}
        return {"type": "frame", "t": _r(self.t), "robots": robots, "ball": ball, "referee": referee,
                "teams": [{"name": team, "colour": self.colour(team)} for team in self.teams],
                "belief": self._belief(watch) if watch else None}

    def _robot(self, name: str, x: float, y: float, theta: float, frames: dict[str, TeamFrame]) -> dict[str, Any]:
        robot = parse_robot_name(name)
        frame = frames.get(robot.team, TeamFrame(1))
        info = self._team_info.get(robot.team, {}).get(robot.agent_id)
        role = Role.of(self._roles[name]).name if name in self._roles else None
        target = None
        if info is not None:
            role = Role.of(int(info.current_role)).name
            tx, ty = frame.point_to_world(info.target.x, info.target.y)
            target = [_r(tx), _r(ty)]
        path = [[_r(px), _r(py)] for px, py in (frame.point_to_world(*p) for p in self._paths.get(name, ()))]
        return {"name": name, "team": robot.team, "id": robot.agent_id, "x": _r(x), "y": _r(y), "theta": _r(theta),
                "role": role, "target": target, "path": path}

    def _belief(self, robot: str) -> dict[str, Any] | None:
        """What ``robot`` believes, world frame: its own pose, teammates, ball and obstacles (None: unknown)."""
        msg = self._beliefs.get(robot)
        if msg is None or not is_robot_name(robot):
            return None
        name = parse_robot_name(robot)
        frame = self.frame_of(name.team)
        teammates = []
        for info in msg.robotinfo:
            if not info.isvalid:
                continue
            x, y = frame.point_to_world(info.pos.x, info.pos.y)
            teammates.append({"id": int(info.AgentID), "x": _r(x), "y": _r(y),
                              "theta": _r(frame.heading_to_world(info.heading.theta))})
        ball = None
        own = msg.ballinfo[name.agent_id - 1] if len(msg.ballinfo) >= name.agent_id else None
        known = [b for b in ([own] if own is not None else []) + list(msg.ballinfo) if b.pos_known]
        if known:
            bx, by = frame.point_to_world(known[0].pos.x, known[0].pos.y)
            ball = {"x": _r(bx), "y": _r(by), "own": bool(own is not None and own.pos_known and own.ballinfostate == 1)}
        opponents = [[_r(c) for c in frame.point_to_world(p.x, p.y)] for p in msg.oppinfo.pos]
        obstacles = [[_r(c) for c in frame.point_to_world(p.x, p.y)] for p in msg.obstacleinfo.pos]
        return {"robot": robot, "t": _r(stamp_seconds(msg.header.stamp)), "teammates": teammates, "ball": ball,
                "opponents": opponents, "obstacles": obstacles}

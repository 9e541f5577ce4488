"""What RViz shows of a match: the tf2 frames and the markers, as plain data (no rospy, no messages).

Requires: the match's ``WorldDescription``; the models' poses (``ModelPose``, world frame, from
/sim_visual/model_states); which goal each team attacks (``TeamSides``: the referee's GameState); each
robot's planned path (team frame, from /<robot>/nubotcontrol/path).
Provides:

- ``frame_transforms`` -> ``FrameTransform`` list: ``world`` -> each team's frame (named by its prefix:
  the world frame for a team attacking +x, turned half round the centre spot for a team attacking -x,
  as ``TeamFrame`` says), ``world`` -> ``<robot>/base_link`` for every robot, ``world`` -> ``ball``;
- ``field_markers`` -> ``Marker`` list (world frame): the carpet, every white line, the centre circle,
  the corner arcs and the spots of ``FieldGeometry``, both goals (posts, bar, net outline);
- ``scene_markers`` -> ``Marker`` list: each robot a cylinder in its team's colour with its number and a
  heading arrow, the ball at its height (all frame-locked to the robot's or the ball's frame, so RViz
  moves them with tf between two scene messages), each robot's planned path as a line strip in its
  team's frame; a DELETEALL first, so a robot that left takes its markers along;
- ``MatchMarkersParams``: the node's rates (``config/match_markers.yaml``);
- ``SimTimeThrottle``: lets a stream through at most once per period of sim time (and again at once
  after time ran backwards: a world reset, a bag played again).

``TeamSides`` decides a team's goal: the referee's latest word; before the referee has spoken, the
attack the simulator was configured with for the team's robots (``/sim_visual/sim/robots``); a team
known from neither attacks the goal a known team does not, and when no team is known the first team
in alphabetical order attacks +x (its frame is the world frame) and every other team -x (the half
turn), as the two shipped team files (nubot, rival) have it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from enum import IntEnum

from nubot_common.geometry import yaw_to_quaternion
from nubot_common.naming import is_robot_name, parse_robot_name, rgb, team_colour
from nubot_common.params import require_positive
from nubot_common.team_frame import TeamFrame
from nubot_common.world_description import WorldDescription

WORLD_FRAME = "world"
BALL_FRAME = "ball"
Vector = tuple[float, float, float]
Quaternion = tuple[float, float, float, float]  # x, y, z, w
Colour = tuple[float, float, float, float]  # red, green, blue, alpha in [0, 1]

CARPET: Colour = (0.13, 0.45, 0.18, 1.0)
WHITE: Colour = (1.0, 1.0, 1.0, 1.0)
BALL: Colour = (1.0, 0.45, 0.0, 1.0)
NET: Colour = (0.85, 0.85, 0.85, 0.8)
LINE_HEIGHT = 0.005  # the lines lie this far above the carpet [m], so that RViz draws them over it
ARC_STEP = math.radians(5.0)  # an arc is drawn as a line strip of chords this wide [rad]
PATH_HEIGHT = 0.02  # [m] a path lies on the carpet, over the lines
PATH_WIDTH = 0.05  # [m]
TEXT_HEIGHT = 0.4  # a robot's number [m]
ARROW_LENGTH = 0.35  # the heading arrow's reach beyond the robot's edge [m]


@dataclass(frozen=True)
class MatchMarkersParams:
    """The match_markers node's parameters."""

    tf_rate: float = 30.0  # the frames at most this often [Hz, sim time] (the model states come at 100 Hz)
    scene_rate: float = 10.0  # the scene this often while someone watches it [Hz, sim time]; tf moves it between

    def __post_init__(self) -> None:
        require_positive(self, "tf_rate", "scene_rate")


def base_link(robot: str) -> str:
    """The frame of a robot's body: ``nubot1/base_link``."""
    return f"{robot}/base_link"


@dataclass(frozen=True)
class ModelPose:
    """One model of /sim_visual/model_states, world frame."""

    name: str
    position: Vector  # [m]
    orientation: Quaternion = (0.0, 0.0, 0.0, 1.0)


@dataclass(frozen=True)
class FrameTransform:
    """The pose of frame ``child`` in frame ``parent`` (a tf2 transform)."""

    parent: str
    child: str
    translation: Vector  # [m]
    rotation: Quaternion


class MarkerKind(IntEnum):
    """visualization_msgs/Marker's type numbers."""

    ARROW = 0
    CUBE = 1
    SPHERE = 2
    CYLINDER = 3
    LINE_STRIP = 4
    LINE_LIST = 5
    TEXT_VIEW_FACING = 9
    DELETEALL = -1  # not a type: the action that clears every marker of the topic


@dataclass(frozen=True)
class Marker:
    """One RViz marker; ``points`` for lines and arrows, ``text`` for text, all in ``frame`` [m]."""

    ns: str
    id: int
    kind: MarkerKind
    frame: str = WORLD_FRAME
    position: Vector = (0.0, 0.0, 0.0)
    yaw: float = 0.0  # [rad] about the frame's z
    scale: Vector = (1.0, 1.0, 1.0)  # [m]; a line's width is scale[0]
    colour: Colour = WHITE
    points: tuple[Vector, ...] = ()
    text: str = ""
    frame_locked: bool = False  # RViz keeps the marker on its frame as tf moves it


class TeamSides:
    """Which goal each team attacks (1: +x, -1: -x), as the module's docstring says."""

    def __init__(self, configured: Mapping[str, int] | None = None):
        self.configured = {team: TeamFrame(attack).attack for team, attack in (configured or {}).items()}
        self.referee: dict[str, int] = {}
        self.order: tuple[str, ...] = ()  # the referee's order of teams

    def on_referee(self, teams: Sequence[str], attacks: Sequence[int]) -> None:
        """The referee's GameState: ``attacks[i]`` is the goal ``teams[i]`` attacks now."""
        self.referee = {team: TeamFrame(int(a)).attack for team, a in zip(teams, attacks)}
        self.order = tuple(teams)

    def teams(self, seen: Iterable[str]) -> list[str]:
        """Every team known: the referee's first, then the others in alphabetical order."""
        rest = sorted((set(seen) | set(self.configured)) - set(self.order))
        return [*self.order, *rest]

    def attack(self, team: str, seen: Iterable[str]) -> int:
        if team in self.referee:
            return self.referee[team]
        if team in self.configured:
            return self.configured[team]
        known = {**self.configured, **self.referee}
        if known:  # the goal a known team does not attack
            return -next(iter(known.values()))
        return 1 if team == min({team, *seen}) else -1

    def frame(self, team: str, seen: Iterable[str]) -> TeamFrame:
        return TeamFrame(self.attack(team, seen))

    def colour(self, team: str, seen: Iterable[str]) -> Colour:
        return (*rgb(team_colour(team, self.teams([team, *seen]))), 1.0)  # teams in the referee's order, then by name


def configured_attacks(robots: object) -> dict[str, int]:
    """Each team's attack from the simulator's configured robots (``/sim_visual/sim/robots``: a list of mappings
    with ``name`` and ``attack``); entries that are not so are skipped (the simulator refuses them itself)."""
    attacks: dict[str, int] = {}
    for robot in robots if isinstance(robots, list) else []:
        name = robot.get("name") if isinstance(robot, dict) else None
        if isinstance(name, str) and is_robot_name(name) and robot.get("attack", 1) in (1, -1):
            attacks[parse_robot_name(name).team] = int(robot.get("attack", 1))
    return attacks


def robot_teams(poses: Iterable[ModelPose]) -> list[str]:
    """The teams of the robots among ``poses``, each once, in order."""
    return list(dict.fromkeys(parse_robot_name(p.name).team for p in poses if is_robot_name(p.name)))


def team_frame_transform(team: str, frame: TeamFrame) -> FrameTransform:
    """``world`` -> the team's frame: where ``TeamFrame`` puts the team's origin and x axis in the world."""
    x, y = frame.point_to_world(0.0, 0.0)
    return FrameTransform(WORLD_FRAME, team, (x, y, 0.0), yaw_to_quaternion(frame.heading_to_world(0.0)))


def frame_transforms(poses: Sequence[ModelPose], sides: TeamSides, ball_name: str) -> list[FrameTransform]:
    """Every frame of the match at one instant: the teams' (also of a team the referee names without robots),
    each robot's body and the ball (its position only: a rolling ball's spin is of no use to a viewer)."""
    seen = robot_teams(poses)
    out = [team_frame_transform(team, sides.frame(team, seen)) for team in sides.teams(seen)]
    for pose in poses:
        if is_robot_name(pose.name):
            out.append(FrameTransform(WORLD_FRAME, base_link(pose.name), pose.position, pose.orientation))
        elif pose.name == ball_name:
            out.append(FrameTransform(WORLD_FRAME, BALL_FRAME, pose.position, (0.0, 0.0, 0.0, 1.0)))
    return out


# --- the field (world frame) ---------------------------------------------------------------------------------
def arc_points(x: float, y: float, radius: float, start: float, end: float, z: float = LINE_HEIGHT
               ) -> tuple[Vector, ...]:
    """Points along an arc from ``start`` to ``end`` [rad] counter-clockwise, both ends included."""
    count = max(2, math.ceil(abs(end - start) / ARC_STEP) + 1)
    return tuple((x + radius * math.cos(a), y + radius * math.sin(a), z)
                 for a in (start + (end - start) * k / (count - 1) for k in range(count)))


def field_markers(world: WorldDescription) -> list[Marker]:
    """The field of ``world`` as markers in the world frame (published once, latched)."""
    f = world.field
    width = f.line_width
    out = [Marker("carpet", 0, MarkerKind.CUBE, position=(0.0, 0.0, -0.01),
                  scale=(f.length + 2 * f.border, f.width + 2 * f.border, 0.02), colour=CARPET)]
    lines = tuple(p for a, b in f.line_segments() for p in ((*a, LINE_HEIGHT), (*b, LINE_HEIGHT)))
    out.append(Marker("lines", 0, MarkerKind.LINE_LIST, scale=(width, 0.0, 0.0), points=lines))
    for k, arc in enumerate(f.arcs()):
        out.append(Marker("arcs", k, MarkerKind.LINE_STRIP, scale=(width, 0.0, 0.0),
                          points=arc_points(arc.x, arc.y, arc.radius, arc.start, arc.end)))
    for k, (x, y) in enumerate(f.spots()):
        out.append(Marker("spots", k, MarkerKind.CYLINDER, position=(x, y, LINE_HEIGHT),
                          scale=(f.spot_diameter, f.spot_diameter, 2 * LINE_HEIGHT)))
    for side in (1, -1):
        out += _goal_markers(world, side, 0 if side == 1 else 10)
    return out


def _goal_markers(world: WorldDescription, side: int, first_id: int) -> list[Marker]:
    """The goal at +x (``side`` 1) or -x: two posts, the bar and the outline of its net."""
    f = world.field
    posts = f.goal_posts(side)
    diameter, height = 2 * f.post_radius, f.goal_height
    out = [Marker("goals", first_id + k, MarkerKind.CYLINDER, position=(x, y, height / 2),
                  scale=(diameter, diameter, height)) for k, (x, y) in enumerate(posts)]
    x = posts[0][0]
    out.append(Marker("goals", first_id + 2, MarkerKind.CUBE, position=(x, 0.0, height + f.post_radius),
                      scale=(diameter, posts[1][1] - posts[0][1] + diameter, diameter)))
    back, half = side * (f.half_length + f.goal_depth), f.goal_width / 2 + f.post_radius
    corners = [(x, -half), (back, -half), (back, half), (x, half)]  # the net's floor and roof outline
    edges: list[Vector] = []
    for z in (0.0, height):
        for (x0, y0), (x1, y1) in zip(corners, corners[1:]):
            edges += [(x0, y0, z), (x1, y1, z)]
    for y in (-half, half):  # the net's back posts
        edges += [(back, y, 0.0), (back, y, height)]
    out.append(Marker("goals", first_id + 3, MarkerKind.LINE_LIST, scale=(0.03, 0.0, 0.0), colour=NET,
                      points=tuple(edges)))
    return out


# --- the scene -------------------------------------------------------------------------------------------------
def scene_markers(poses: Sequence[ModelPose], world: WorldDescription, sides: TeamSides,
                  paths: Mapping[str, tuple[str, Sequence[tuple[float, float]]]]) -> list[Marker]:
    """The robots, the ball and the planned paths (``paths``: robot -> (its path's frame, points [m])) now."""
    out = [Marker("scene", 0, MarkerKind.DELETEALL)]
    seen = robot_teams(poses)
    r, h = world.robot.radius, world.robot.height
    for k, pose in enumerate(p for p in poses if is_robot_name(p.name)):
        name = parse_robot_name(pose.name)
        colour, frame = sides.colour(name.team, seen), base_link(pose.name)
        out += [Marker("robots", k, MarkerKind.CYLINDER, frame, (0.0, 0.0, h / 2), scale=(2 * r, 2 * r, h),
                       colour=colour[:3] + (0.9,), frame_locked=True),
                Marker("numbers", k, MarkerKind.TEXT_VIEW_FACING, frame, (0.0, 0.0, h + TEXT_HEIGHT),
                       scale=(0.0, 0.0, TEXT_HEIGHT), text=str(name.agent_id), frame_locked=True),
                Marker("headings", k, MarkerKind.ARROW, frame, scale=(0.06, 0.12, 0.12), colour=WHITE,
                       points=((0.0, 0.0, h + 0.02), (r + ARROW_LENGTH, 0.0, h + 0.02)), frame_locked=True)]
        path = paths.get(pose.name)
        if path is not None and len(path[1]) >= 2:
            out.append(Marker("paths", k, MarkerKind.LINE_STRIP, path[0], scale=(PATH_WIDTH, 0.0, 0.0),
                              colour=colour, points=tuple((x, y, PATH_HEIGHT) for x, y in path[1]),
                              frame_locked=True))
    d = 2 * world.ball.radius
    if any(p.name == world.ball_name for p in poses):
        out.append(Marker("ball", 0, MarkerKind.SPHERE, BALL_FRAME, scale=(d, d, d), colour=BALL, frame_locked=True))
    return out


class SimTimeThrottle:
    """Lets a stream through at most once per ``period`` [s] of sim time, on average once per period: 100 Hz
    model states thinned to 30 Hz pass every third or fourth."""

    def __init__(self, period: float):
        if not period > 0.0:
            raise ValueError(f"a throttle's period must be positive, got {period}")
        self.period = period
        self.last = -math.inf  # the last time let through [s]
        self.next = -math.inf  # the next time due [s]

    def due(self, t: float) -> bool:
        """True when ``t`` [s] is due, or before the last one let through (time ran backwards)."""
        if self.last <= t < self.next - 1e-9:
            return False
        on_time = self.last <= t < self.next + self.period  # keep the schedule; after a gap or a jump, restart it
        self.next = self.next + self.period if on_time else t + self.period
        self.last = t
        return True

"""The MSL RefBox protocol as a team's base station speaks it (RefBox v2: JSON over TCP), without ROS.

Requires: the bytes of the box's TCP stream; our robots, ball and obstacles in our team frame (own goal at -x,
[m], [m/s], [rad], [rad/s]).
Provides:
- ``encode_message`` (a JSON object and its terminating zero byte) and ``FrameDecoder`` (the stream cut into
  messages: split across reads or several in one read; a message over ``max_size`` bytes or one that is no JSON
  object becomes a ``Frame`` with an error, counted, and the stream goes on).
- ``parse_command`` (``{"command", "targetTeam", "robotID"}`` -> ``RefboxCommand``), ``COMMAND_RULES`` (what every
  box command means for our robots) and ``map_command`` -> ``CommandEffect``: the ``MatchMode`` our team gets
  (OUR_x when ``targetTeam`` is our address or name, OPP_x when it is another's), or none with the reason;
  ``team_book`` holds our team(s)' commands as the referee would: the other team, when ours too, gets the mirror.
- ``build_worldstate`` (the ``worldstate`` JSON the box logs, exactly its required keys), ``choose_ball``,
  ``merge_obstacles`` and ``worldstate_problems`` / ``check_worldstate`` (the box's required keys and types).
- ``Backoff`` (reconnect delays), ``OutageLog`` (one log line per outage), ``RateMeter`` and ``RefboxClientParams``.
Raises ``RefboxError`` (a ``CoachError``) naming the bad value.

Units and axes of the worldstate. The RefBox logs what teams send; its audience client draws each team's
worldstate in that team's own frame (the field's length along y, the second team's picture turned half round),
and teams' loggers turn their headings so that 0 faces the goal they attack. We send: metres, metres per second,
radians and radians per second; origin at the centre spot; +y towards the goal we attack, +x to our right seen
from our own goal (so MSL x = -our y, MSL y = our x); theta 0 facing +y, counter-clockwise positive (so an angle
is the same number as in our team frame, where 0 faces +x, the attacked goal). Numbers are rounded to 1 mm
(1 mrad, 1 mm/s); a ball on the carpet has z 0 (our world model is two-dimensional).

Mapping of the box's commands (our robots' ``MatchMode``; "none" changes nothing and is logged):
START -> STARTROBOT; STOP -> STOPROBOT; DROP_BALL -> DROPBALL; PARK -> PARKINGROBOT;
END_PART, HALF_TIME, END_GAME, GAMEOVER, RESET -> STOPROBOT;
KICKOFF, FREEKICK, GOALKICK, THROWIN, CORNER, PENALTY -> OUR_/OPP_ KICKOFF, FREEKICK, GOALKICK, THROWIN,
CORNERKICK, PENALTY by ``targetTeam`` (a set piece without a target team is ignored);
none: WELCOME, GOAL, SUBGOAL, FIRST_HALF, SECOND_HALF, FIRST_HALF_OVERTIME, SECOND_HALF_OVERTIME, YELLOW_CARD,
RED_CARD, DOUBLE_YELLOW, REPAIR, SUBSTITUTION, TESTMODE_ON, TESTMODE_OFF (``COMMAND_RULES`` says why for each).
"""

from __future__ import annotations

import json
import math
from collections import deque
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import Any

from coach4sim import CoachError
from coach4sim.game import GameController
from coach4sim.params import TeamSpec
from nubot_common import NubotCommonError
from nubot_common.match_mode import MatchMode
from nubot_common.naming import check_team_prefix
from nubot_common.params import require_positive
from nubot_common.untrusted import UntrustedInputError, json_object

DEFAULT_PORT = 28097  # the box's base-station port
MAX_MESSAGE = 100_000  # the box drops a message longer than this without its zero byte [bytes]
MIN_WORLDSTATE_RATE = 10.0  # the box requires a worldstate at least this often [Hz]
TERMINATOR = b"\0"
ROUND_DIGITS = 3  # 1 mm, 1 mrad, 1 mm/s: the precision the box's logging asks for


class RefboxError(CoachError):
    """Invalid RefBox input (a message, a command, a worldstate or a parameter)."""


# --- the wire: JSON objects, each followed by a zero byte ------------------------------------------------
def encode_message(message: Mapping[str, Any]) -> bytes:
    """``message`` as compact JSON and its zero byte; NaN or infinity raise ``RefboxError`` (JSON has neither)."""
    try:
        text = json.dumps(message, separators=(",", ":"), allow_nan=False, ensure_ascii=True)
    except (TypeError, ValueError) as exc:
        raise RefboxError(f"cannot encode the message as JSON: {exc}") from None
    return text.encode("ascii") + TERMINATOR


@dataclass(frozen=True)
class Frame:
    """One message cut from the stream: the JSON object, or (``message`` None) why it is not one."""

    message: dict[str, Any] | None
    error: str = ""
    size: int = 0  # [bytes], without the zero byte


class FrameDecoder:
    """Cuts a byte stream into zero-terminated JSON objects; never raises on what the peer sends."""

    def __init__(self, max_size: int = MAX_MESSAGE):
        if isinstance(max_size, bool) or not isinstance(max_size, int) or max_size < 2:
            raise RefboxError(f"max_size must be a whole number of bytes of at least 2, got {max_size!r}")
        self.max_size = max_size
        self.messages = 0  # JSON objects decoded
        self.errors = 0  # frames that were no JSON object, or too long
        self._buffer = bytearray()
        self._skipping = False  # inside an oversized message: drop bytes up to its zero byte

    @property
    def pending(self) -> int:
        """Bytes held for a message not terminated yet."""
        return len(self._buffer)

    def feed(self, data: bytes) -> list[Frame]:
        """The frames ``data`` completes (in order); keeps the tail of an unfinished message."""
        frames: list[Frame] = []
        start = 0
        while start < len(data):
            end = data.find(TERMINATOR, start)
            chunk = data[start:] if end < 0 else data[start:end]
            if self._skipping:
                if end >= 0:
                    self._skipping = False
            else:
                self._buffer += chunk
                if len(self._buffer) > self.max_size:
                    frames.append(self._error(f"message longer than {self.max_size} bytes without its zero byte; "
                                              "dropped up to the next zero byte", len(self._buffer)))
                    self._buffer.clear()
                    self._skipping = end < 0
                elif end >= 0:
                    frame = self._decode(bytes(self._buffer))
                    self._buffer.clear()
                    if frame is not None:
                        frames.append(frame)
            if end < 0:
                break
            start = end + 1
        return frames

    def _error(self, text: str, size: int) -> Frame:
        self.errors += 1
        return Frame(None, text, size)

    def _decode(self, raw: bytes) -> Frame | None:
        if not raw.strip():
            return None  # a lone zero byte (keep-alive, or two in a row) carries nothing
        try:
            message = json_object(raw)
        except UntrustedInputError as exc:
            return self._error(str(exc), len(raw))
        self.messages += 1
        return Frame(message, "", len(raw))


# --- commands ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RefboxCommand:
    command: str  # e.g. KICKOFF
    target_team: str = ""  # the team's address as the box knows it (or its name); "" = both teams
    robot_id: int | None = None  # the robot a card, repair or substitution is for

    def __str__(self) -> str:
        target = f" for {self.target_team}" if self.target_team else ""
        robot = f" robot {self.robot_id}" if self.robot_id is not None else ""
        return f"{self.command}{target}{robot}"

    def to_message(self) -> dict[str, Any]:
        message: dict[str, Any] = {"command": self.command, "targetTeam": self.target_team}
        if self.robot_id is not None:
            message["robotID"] = self.robot_id
        return message


def parse_command(message: Mapping[str, Any]) -> RefboxCommand:
    """The command in a message from the box; raises ``RefboxError`` when a field is missing or mistyped."""
    command = message.get("command")
    if not isinstance(command, str) or not command.strip():
        raise RefboxError(f"a command message needs a non-empty string \"command\", got {message!r:.120}")
    target = message.get("targetTeam", "")
    if target is None:
        target = ""
    if not isinstance(target, str):
        raise RefboxError(f"\"targetTeam\" must be a string, got {target!r}")
    robot = message.get("robotID")
    if robot is not None and (isinstance(robot, bool) or not isinstance(robot, int)):
        raise RefboxError(f"\"robotID\" must be a whole number, got {robot!r}")
    return RefboxCommand(command.strip().upper(), target.strip(), robot)


class CommandKind(Enum):
    ALL = "the same game command for every team"
    SET_PIECE = "OUR_x for the target team, OPP_x for the other"
    NONE = "no game command"


@dataclass(frozen=True)
class CommandRule:
    kind: CommandKind
    mode: MatchMode | None  # ALL: the command; SET_PIECE: its OUR_ form; NONE: None
    why: str


def _all(mode: MatchMode, why: str) -> CommandRule:
    return CommandRule(CommandKind.ALL, mode, why)


def _set_piece(mode: MatchMode) -> CommandRule:
    return CommandRule(CommandKind.SET_PIECE, mode, "a restart for the target team")


def _none(why: str) -> CommandRule:
    return CommandRule(CommandKind.NONE, None, why)


_PERIOD = "a period begins; the robots stay as they are until the box's kickoff"
_CARD = "a card; a robot sent off is taken off the field by hand"
COMMAND_RULES: dict[str, CommandRule] = {
    "START": _all(MatchMode.STARTROBOT, "play (on)"),
    "STOP": _all(MatchMode.STOPROBOT, "stop"),
    "DROP_BALL": _all(MatchMode.DROPBALL, "a dropped ball is nobody's restart"),
    "PARK": _all(MatchMode.PARKINGROBOT, "drive to the parking positions"),
    "END_PART": _all(MatchMode.STOPROBOT, "a part of the match ends: stand still"),
    "HALF_TIME": _all(MatchMode.STOPROBOT, "half time: stand still"),
    "END_GAME": _all(MatchMode.STOPROBOT, "the match ends: stand still"),
    "GAMEOVER": _all(MatchMode.STOPROBOT, "the match is over: stand still"),
    "RESET": _all(MatchMode.STOPROBOT, "the box resets the match: stand still"),
    "KICKOFF": _set_piece(MatchMode.OUR_KICKOFF),
    "FREEKICK": _set_piece(MatchMode.OUR_FREEKICK),
    "GOALKICK": _set_piece(MatchMode.OUR_GOALKICK),
    "THROWIN": _set_piece(MatchMode.OUR_THROWIN),
    "CORNER": _set_piece(MatchMode.OUR_CORNERKICK),
    "PENALTY": _set_piece(MatchMode.OUR_PENALTY),
    "WELCOME": _none("the box accepted our connection"),
    "GOAL": _none("a goal is counted; the box sends the kickoff next"),
    "SUBGOAL": _none("a goal is taken back"),
    "FIRST_HALF": _none(_PERIOD),
    "SECOND_HALF": _none(_PERIOD),
    "FIRST_HALF_OVERTIME": _none(_PERIOD),
    "SECOND_HALF_OVERTIME": _none(_PERIOD),
    "YELLOW_CARD": _none(_CARD),
    "RED_CARD": _none(_CARD),
    "DOUBLE_YELLOW": _none(_CARD),
    "REPAIR": _none("a robot leaves for repair; it is taken off by hand"),
    "SUBSTITUTION": _none("a robot is substituted by hand"),
    "TESTMODE_ON": _none("the box's own test mode, not our robots' TEST (which would move them)"),
    "TESTMODE_OFF": _none("the box's own test mode ends"),
}


@dataclass(frozen=True)
class TeamIdentity:
    """How the box names our team in ``targetTeam``: its address in the box's team table, or its name."""

    address: str = ""
    name: str = ""

    def __post_init__(self) -> None:
        if not self.address.strip() and not self.name.strip():
            raise RefboxError("our team needs an address or a name as the box knows it (team_address, team_name)")

    def is_us(self, target: str) -> bool:
        target = target.strip()
        return bool(target) and (target == self.address.strip() or target.lower() == self.name.strip().lower())


@dataclass(frozen=True)
class CommandEffect:
    """What a box command does to our team: ``mode`` in our team's view, or None (and ``text`` says why)."""

    command: RefboxCommand
    mode: MatchMode | None
    text: str
    known: bool = True  # the command is one of COMMAND_RULES


def map_command(command: RefboxCommand, us: TeamIdentity) -> CommandEffect:
    """The game command ``command`` gives our team, in our view (OUR_x is ours to take)."""
    rule = COMMAND_RULES.get(command.command)
    if rule is None:
        return CommandEffect(command, None, f"{command}: unknown command, ignored", known=False)
    if rule.kind is CommandKind.NONE or rule.mode is None:
        return CommandEffect(command, None, f"{command}: no game command ({rule.why})")
    if rule.kind is CommandKind.ALL:
        return CommandEffect(command, rule.mode, f"{command} -> {rule.mode.name}")
    if not command.target_team:
        return CommandEffect(command, None, f"{command}: a set piece without a target team, ignored")
    ours = us.is_us(command.target_team)
    mode = rule.mode if ours else rule.mode.mirrored()
    return CommandEffect(command, mode, f"{command} ({'us' if ours else 'them'}) -> {mode.name}")


def team_book(teams: Sequence[str]) -> GameController:
    """Our team(s), the first the box's, as the referee holds them: ``command(teams[0], mode)`` gives the second
    team, when it is ours too, the mirror; a repeated command keeps the previous one (MatchType) meaningful."""
    return GameController([TeamSpec(team, 1 - 2 * i) for i, team in enumerate(teams)])


# --- the worldstate --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RobotSnapshot:
    """One of our robots as we report it; team frame (own goal at -x)."""

    agent_id: int
    x: float  # [m]
    y: float  # [m]
    theta: float  # heading [rad], 0 facing the attacked goal
    vx: float = 0.0  # [m/s]
    vy: float = 0.0  # [m/s]
    omega: float = 0.0  # [rad/s], counter-clockwise
    target: tuple[float, float] | None = None  # where it heads [m]; None: where it is
    intention: str = ""  # e.g. its role
    holding: bool = False  # the ball is in its handler
    battery_level: float = 100.0  # [%]


@dataclass(frozen=True)
class BallSnapshot:
    """The ball as one robot's world model has it; team frame."""

    x: float  # [m]
    y: float  # [m]
    vx: float = 0.0  # [m/s]
    vy: float = 0.0  # [m/s]
    own: bool = True  # seen by that robot's own sensors (else relayed from a teammate)
    stamp: float = 0.0  # when it was seen [s]


@dataclass(frozen=True)
class ObstacleSnapshot:
    x: float  # [m], team frame
    y: float  # [m]
    radius: float  # [m]
    confidence: float  # 0..1
    vx: float = 0.0  # [m/s] (our world model does not track obstacles' velocities)
    vy: float = 0.0


OWN_BALL_CONFIDENCE = 1.0  # a ball seen by a robot's own sensors
RELAYED_BALL_CONFIDENCE = 0.5  # a ball only a teammate saw


def choose_ball(candidates: Iterable[BallSnapshot]) -> tuple[BallSnapshot, float] | None:
    """The team's ball and its confidence: the newest one a robot saw itself, else the newest relayed one."""
    balls = [b for b in candidates if _finite(b.x, b.y, b.vx, b.vy)]
    if not balls:
        return None
    best = max(balls, key=lambda b: (b.own, b.stamp))
    return best, OWN_BALL_CONFIDENCE if best.own else RELAYED_BALL_CONFIDENCE


def merge_obstacles(seen: Sequence[Sequence[tuple[float, float]]], merge_distance: float,
                    radius: float) -> list[ObstacleSnapshot]:
    """One obstacle per cluster of the opponents our robots see (``seen[i]``: robot i's, team frame [m]).

    Points closer than ``merge_distance`` [m] to a cluster's first point join it; a cluster's position is its
    mean and its confidence the share of the reporting robots that see it (each robot counted once).
    """
    clusters: list[tuple[float, float, list[tuple[float, float]], set[int]]] = []
    for robot, points in enumerate(seen):
        for x, y in points:
            if not _finite(x, y):
                continue
            for cx, cy, members, robots in clusters:
                if math.hypot(x - cx, y - cy) < merge_distance:
                    members.append((x, y))
                    robots.add(robot)
                    break
            else:
                clusters.append((x, y, [(x, y)], {robot}))
    reporters = max(len(seen), 1)
    return [ObstacleSnapshot(sum(p[0] for p in m) / len(m), sum(p[1] for p in m) / len(m), radius,
                             min(1.0, len(r) / reporters)) for _, _, m, r in clusters]


def team_to_msl(x: float, y: float) -> tuple[float, float]:
    """A point or vector of our team frame (+x attacked goal, +y left) in the box's axes (+y attacked goal,
    +x right)."""
    return -y, x


def _finite(*values: float) -> bool:
    return all(isinstance(v, (int, float)) and math.isfinite(v) for v in values)


def _r(value: float) -> float:
    return round(float(value), ROUND_DIGITS) + 0.0  # + 0.0: no "-0.0" in the log


def build_worldstate(team_name: str, intention: str, age_ms: float, robots: Iterable[RobotSnapshot],
                     ball: tuple[BallSnapshot, float] | None = None,
                     obstacles: Iterable[ObstacleSnapshot] = ()) -> dict[str, Any]:
    """The ``worldstate`` message with exactly the keys the box requires, in its axes (module docstring).

    An entry with a number that is not finite is left out: JSON has no NaN, and the box would refuse the
    whole message for one bad robot.
    """
    out_robots = []
    for r in sorted(robots, key=lambda r: r.agent_id):
        tx, ty = r.target if r.target is not None else (r.x, r.y)
        if not _finite(r.x, r.y, r.theta, r.vx, r.vy, r.omega, tx, ty, r.battery_level):
            continue
        x, y = team_to_msl(r.x, r.y)
        vx, vy = team_to_msl(r.vx, r.vy)
        gx, gy = team_to_msl(tx, ty)
        out_robots.append({
            "id": int(r.agent_id),
            "pose": [_r(x), _r(y), _r(r.theta)],
            "targetPose": [_r(gx), _r(gy), _r(r.theta)],
            "velocity": [_r(vx), _r(vy), _r(r.omega)],
            "intention": r.intention,
            "batteryLevel": _r(r.battery_level),
            "ballEngaged": 1 if r.holding else 0,
        })
    out_balls = []
    if ball is not None:
        b, confidence = ball
        if _finite(b.x, b.y, b.vx, b.vy, confidence):
            x, y = team_to_msl(b.x, b.y)
            vx, vy = team_to_msl(b.vx, b.vy)
            out_balls.append({"position": [_r(x), _r(y), 0.0], "velocity": [_r(vx), _r(vy), 0.0],
                              "confidence": _r(confidence)})
    out_obstacles = []
    for o in obstacles:
        if not _finite(o.x, o.y, o.radius, o.confidence, o.vx, o.vy):
            continue
        x, y = team_to_msl(o.x, o.y)
        vx, vy = team_to_msl(o.vx, o.vy)
        out_obstacles.append({"position": [_r(x), _r(y)], "radius": _r(o.radius), "velocity": [_r(vx), _r(vy)],
                              "confidence": _r(o.confidence)})
    age = int(round(age_ms)) if _finite(age_ms) and age_ms > 0 else 0
    return {"type": "worldstate", "teamName": team_name, "intention": intention, "ageMs": age,
            "robots": out_robots, "balls": out_balls, "obstacles": out_obstacles}


# --- the validator the test server (and the tests) use ----------------------------------------------------
WORLDSTATE_KEYS = ("type", "teamName", "intention", "ageMs", "robots", "balls", "obstacles")
ROBOT_KEYS = ("id", "pose", "targetPose", "velocity", "intention", "batteryLevel", "ballEngaged")
BALL_KEYS = ("position", "velocity", "confidence")
OBSTACLE_KEYS = ("position", "radius", "velocity", "confidence")


def _is_number(value: Any) -> bool:
    return not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value)


def _numbers(value: Any, count: int) -> bool:
    return isinstance(value, list) and len(value) == count and all(_is_number(v) for v in value)


def _check_entry(entry: Any, where: str, keys: Sequence[str], checks: Mapping[str, tuple[Any, str]]) -> list[str]:
    if not isinstance(entry, dict):
        return [f"{where} is not an object"]
    problems = [f"{where} lacks \"{key}\"" for key in keys if key not in entry]
    problems += [f"{where}.{key} must be {what}, got {entry[key]!r:.60}"
                 for key, (check, what) in checks.items() if key in entry and not check(entry[key])]
    return problems


def _confidence(value: Any) -> bool:
    return _is_number(value) and 0.0 <= value <= 1.0


_ROBOT_CHECKS = {
    "id": (lambda v: not isinstance(v, bool) and isinstance(v, int), "a whole number"),
    "pose": (lambda v: _numbers(v, 3), "[x, y, theta]"),
    "targetPose": (lambda v: _numbers(v, 3), "[x, y, theta]"),
    "velocity": (lambda v: _numbers(v, 3), "[vx, vy, omega]"),
    "intention": (lambda v: isinstance(v, str), "a string"),
    "batteryLevel": (_is_number, "a number"),
    "ballEngaged": (lambda v: v in (0, 1) and not isinstance(v, float), "0 or 1"),
}
_BALL_CHECKS = {
    "position": (lambda v: _numbers(v, 3), "[x, y, z]"),
    "velocity": (lambda v: _numbers(v, 3), "[vx, vy, vz]"),
    "confidence": (_confidence, "a number in [0, 1]"),
}
_OBSTACLE_CHECKS = {
    "position": (lambda v: _numbers(v, 2), "[x, y]"),
    "radius": (lambda v: _is_number(v) and v >= 0.0, "a non-negative number"),
    "velocity": (lambda v: _numbers(v, 2), "[vx, vy]"),
    "confidence": (_confidence, "a number in [0, 1]"),
}
_TOP_CHECKS = {
    "type": (lambda v: v == "worldstate", "\"worldstate\""),
    "teamName": (lambda v: isinstance(v, str), "a string"),
    "intention": (lambda v: isinstance(v, str), "a string"),
    "ageMs": (lambda v: not isinstance(v, bool) and isinstance(v, int) and v >= 0, "a whole number >= 0"),
    "robots": (lambda v: isinstance(v, list), "a list"),
    "balls": (lambda v: isinstance(v, list), "a list"),
    "obstacles": (lambda v: isinstance(v, list), "a list"),
}


def worldstate_problems(message: Any) -> list[str]:
    """Everything that makes ``message`` fall short of the box's required worldstate keys and types (empty: ok).
    Keys beyond the required ones are allowed, as the box ignores them."""
    problems = _check_entry(message, "worldstate", WORLDSTATE_KEYS, _TOP_CHECKS)
    if not isinstance(message, dict):
        return problems
    for name, keys, checks in (("robots", ROBOT_KEYS, _ROBOT_CHECKS), ("balls", BALL_KEYS, _BALL_CHECKS),
                               ("obstacles", OBSTACLE_KEYS, _OBSTACLE_CHECKS)):
        entries = message.get(name)
        if isinstance(entries, list):
            for i, entry in enumerate(entries):
                problems += _check_entry(entry, f"{name}[{i}]", keys, checks)
    return problems


def check_worldstate(message: Any) -> None:
    """Raise ``RefboxError`` listing every problem unless ``message`` is a worldstate the box accepts."""
    problems = worldstate_problems(message)
    if problems:
        raise RefboxError("invalid worldstate: " + "; ".join(problems))


# --- the connection's bookkeeping -------------------------------------------------------------------------
class Backoff:
    """Delays between connection attempts: ``initial`` [s], doubled after each failure up to ``maximum`` [s]."""

    def __init__(self, initial: float, maximum: float):
        if not 0.0 < initial <= maximum or not math.isfinite(maximum):
            raise RefboxError(f"reconnect delays need 0 < initial <= maximum < inf, got {initial} and {maximum}")
        self.initial, self.maximum = initial, maximum
        self._next = initial

    def next_delay(self) -> float:
        delay = self._next
        self._next = min(self._next * 2.0, self.maximum)
        return delay

    def reset(self) -> None:
        self._next = self.initial


class OutageLog:
    """Says what to log about the connection: one line when an outage begins, one when it ends."""

    def __init__(self, where: str):
        self.where = where
        self.connected = False
        self.outages = 0  # outages seen (the first failure before any connection counts as one)
        self.connections = 0
        self._down_since: float | None = None
        self._attempts = 0

    def failed(self, now: float, reason: str) -> str | None:
        """A connection attempt failed at ``now`` [s]; the line to log, or None within an outage already logged."""
        self._attempts += 1
        if self._down_since is not None:
            return None
        self._down_since = now
        self.outages += 1
        return f"cannot reach the RefBox at {self.where} ({reason}); retrying with back-off, quietly"

    def lost(self, now: float, reason: str) -> str:
        """The connection ended at ``now`` [s]."""
        self.connected = False
        self._down_since, self._attempts = now, 0
        self.outages += 1
        return f"lost the RefBox at {self.where} ({reason}); reconnecting with back-off, quietly"

    def up(self, now: float) -> str:
        """A connection was made at ``now`` [s]."""
        self.connected = True
        self.connections += 1
        if self._down_since is None:
            text = f"connected to the RefBox at {self.where}"
        else:
            text = (f"connected to the RefBox at {self.where} after {now - self._down_since:.1f} s "
                    f"({self._attempts} failed attempt{'s' if self._attempts != 1 else ''})")
        self._down_since, self._attempts = None, 0
        return text


class RateMeter:
    """Events per second over the last ``window`` [s]."""

    def __init__(self, window: float = 2.0):
        if not window > 0.0:
            raise RefboxError(f"window must be positive, got {window}")
        self.window = window
        self.count = 0
        self._times: deque[float] = deque()

    def add(self, now: float) -> None:
        self.count += 1
        self._times.append(now)
        self._drop(now)

    def rate(self, now: float) -> float:
        """[Hz]: the events in the window, over the window (or over the time since the first one, if shorter)."""
        self._drop(now)
        if len(self._times) < 2:
            return 0.0
        span = max(now - self._times[0], self._times[-1] - self._times[0])
        return (len(self._times) - 1) / span if span > 0.0 else 0.0

    def _drop(self, now: float) -> None:
        while self._times and now - self._times[0] > self.window:
            self._times.popleft()


# --- the client node's parameters ----------------------------------------------------------------------------
@dataclass(frozen=True)
class RefboxClientParams:
    """The refbox_client node's parameters (``config/refbox_client.yaml``); SI units."""

    host: str = "127.0.0.1"  # the RefBox's address
    port: int = DEFAULT_PORT
    team: str = "nubot"  # our robots' prefix: /nubot1 ..., /nubot/receive_from_coach
    team_address: str = "224.16.32.53"  # our targetTeam as the box sends it (NuBot's row of the box's team table)
    team_name: str = "NuBot"  # also accepted as our targetTeam; the worldstate's teamName
    other_team: str = ""  # the other team's prefix when it is ours too (gets the mirrored commands); "" otherwise
    team_size: int = 5  # robots <team>1 ... <team><team_size>
    worldstate_rate: float = 20.0  # worldstates to the box [Hz, wall], at least MIN_WORLDSTATE_RATE
    max_age: float = 1.0  # a robot's world model older than this is left out [s, wall]
    battery_level: float = 100.0  # reported for every robot [%] (the robots report no battery)
    obstacle_radius: float = 0.25  # an opponent's radius in the worldstate [m]
    obstacle_merge: float = 0.5  # opponents our robots see this close together are one [m]
    reconnect_initial: float = 0.5  # first delay after a failed connection [s]; doubles up to reconnect_max
    reconnect_max: float = 5.0  # [s]
    connect_timeout: float = 2.0  # a connection attempt, and a send the box does not take, give up after [s]
    max_message: int = MAX_MESSAGE  # a message from the box longer than this is dropped [bytes]
    coach_period: float = 0.03  # without a referee, CoachInfo to the team(s) this often [s] (the coach's 30 ms)
    referee_check_period: float = 1.0  # look for /referee/command this often [s]
    status_period: float = 1.0  # ~status at least this often [s]

    def __post_init__(self) -> None:
        try:
            check_team_prefix(self.team)
            if self.other_team:
                check_team_prefix(self.other_team)
        except NubotCommonError as exc:
            raise ValueError(str(exc)) from None
        if self.other_team == self.team:
            raise ValueError(f"other_team must differ from team {self.team!r}")
        if not self.host.strip():
            raise ValueError("host must name the RefBox's address")
        if not 1 <= self.port <= 65535:
            raise ValueError(f"port must lie in [1, 65535], got {self.port}")
        TeamIdentity(self.team_address, self.team_name)
        if not 1 <= self.team_size <= 9:
            raise ValueError(f"team_size must lie in [1, 9], got {self.team_size}")
        if not MIN_WORLDSTATE_RATE <= self.worldstate_rate <= 200.0:
            raise ValueError(f"worldstate_rate must lie in [{MIN_WORLDSTATE_RATE:g}, 200] Hz (the box requires at "
                             f"least {MIN_WORLDSTATE_RATE:g}), got {self.worldstate_rate}")
        require_positive(self, "max_age", "obstacle_radius", "obstacle_merge", "reconnect_initial", "reconnect_max",
                         "connect_timeout", "coach_period", "referee_check_period", "status_period")
        if self.reconnect_max < self.reconnect_initial:
            raise ValueError(f"reconnect_max {self.reconnect_max} s is shorter than reconnect_initial "
                             f"{self.reconnect_initial} s")
        if not 0.0 <= self.battery_level <= 100.0:
            raise ValueError(f"battery_level must lie in [0, 100] %, got {self.battery_level}")
        if self.max_message < 1024:
            raise ValueError(f"max_message must be at least 1024 bytes, got {self.max_message}")

    @property
    def identity(self) -> TeamIdentity:
        return TeamIdentity(self.team_address, self.team_name)

    @property
    def teams(self) -> tuple[str, ...]:
        return (self.team, self.other_team) if self.other_team else (self.team,)

"""Robot and team names: ``<team prefix><AgentID>``, e.g. ``rival3`` is AgentID 3 of team ``rival``.

Provides: ``RobotName`` (team, agent_id; ``str()`` gives the model name back), ``parse_robot_name``
(raises ``NubotCommonError`` naming the bad name), ``team_of`` (a model name's team, or the
name itself for a model that is no robot, e.g. ``football``), ``is_robot_name``,
``check_team_prefix``, ``RobotSelection`` (``all``, nothing or a list of names) and
``RobotNodeParams`` (``~robot`` and ``~agent_id`` of a per-robot node;
a node with parameters of its own subclasses it) and ``team_colour`` (a team's colour in the page, RViz and the
plots: cyan and magenta as in MSL, then two more). The model name prefixes every topic and service
of its robot in simulation (``/rival3/nubotcontrol/velcmd``); the team prefix names the team's
namespace (``/rival/receive_from_coach``).
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence
from dataclasses import dataclass

from nubot_common import NubotCommonError

_PREFIX = re.compile(r"[A-Za-z_]+")
_ROBOT = re.compile(r"(?P<team>[A-Za-z_]+)(?P<number>[0-9]+)")


def check_team_prefix(prefix: str) -> str:
    """Return ``prefix`` if it can name a team (letters and underscores); else raise ``NubotCommonError``."""
    if not isinstance(prefix, str) or not _PREFIX.fullmatch(prefix):
        raise NubotCommonError(f"a team prefix is letters and underscores (e.g. nubot), got {prefix!r}")
    return prefix


@dataclass(frozen=True, order=True)
class RobotName:
    team: str  # team prefix, e.g. nubot
    agent_id: int  # AgentID within the team, 1 or more

    def __post_init__(self) -> None:
        check_team_prefix(self.team)
        if isinstance(self.agent_id, bool) or not isinstance(self.agent_id, int) or self.agent_id < 1:
            raise NubotCommonError(f"an AgentID is a whole number from 1, got {self.agent_id!r}")

    def __str__(self) -> str:
        return f"{self.team}{self.agent_id}"


def parse_robot_name(name: str) -> RobotName:
    """``rival3`` -> RobotName('rival', 3); a name without a trailing AgentID raises ``NubotCommonError``."""
    match = _ROBOT.fullmatch(name) if isinstance(name, str) else None
    if match is None or int(match["number"]) < 1:
        raise NubotCommonError(f"a robot name is a team prefix and an AgentID from 1 (e.g. nubot2), got {name!r}")
    return RobotName(match["team"], int(match["number"]))


@dataclass(frozen=True)
class RobotNodeParams:
    """Which robot a per-robot node serves, read with ``nubot_common.params.from_mapping``."""

    robot: str = "nubot1"  # model name <team prefix><AgentID>: the prefix of the robot's topics
    agent_id: int = 0  # the robot's AgentID; 0: the one in ``robot``

    def __post_init__(self) -> None:
        try:
            parse_robot_name(self.robot)
        except NubotCommonError as exc:
            raise NubotCommonError(f"robot: {exc}") from None
        if self.agent_id < 0:
            raise NubotCommonError(f"agent_id must be an AgentID from 1 (0: the one in robot), got {self.agent_id}")

    @property
    def name(self) -> RobotName:
        """``robot``, parsed: its team prefix and the AgentID in it."""
        return parse_robot_name(self.robot)

    @property
    def agent(self) -> int:
        """The AgentID the node plays as: ``agent_id``, or the one in ``robot``."""
        return self.agent_id or self.name.agent_id


def is_robot_name(name: str) -> bool:
    match = _ROBOT.fullmatch(name) if isinstance(name, str) else None
    return match is not None and int(match["number"]) >= 1


def team_of(name: str) -> str:
    """The team of a robot's model name (``nubot3`` -> ``nubot``); any other name is returned unchanged."""
    return _team_of(name) if isinstance(name, str) else name


@functools.lru_cache(maxsize=256)
def _team_of(name: str) -> str:  # asked for every robot pair at every referee tick: the names are few
    return parse_robot_name(name).team if is_robot_name(name) else name


@dataclass(frozen=True)
class RobotSelection:
    """Some robots by name, written ``""`` (none), ``all`` or ``nubot1,rival2`` (e.g. the robots that see
    through the simulated camera: ``make match VISION=...``)."""

    names: frozenset[str] = frozenset()
    every: bool = False  # ``all``: every robot, whatever its name

    @classmethod
    def parse(cls, text: str) -> RobotSelection:
        """Read a selection; a word that is no robot name raises ``NubotCommonError`` naming it."""
        if not isinstance(text, str):
            raise NubotCommonError(f"a robot selection is all, nothing or names like nubot1,rival2; got {text!r}")
        words = [w.strip() for w in text.replace(" ", ",").split(",") if w.strip()]
        if words == ["all"]:
            return cls(every=True)
        for word in words:
            if not is_robot_name(word):
                raise NubotCommonError(f"robot selection {text!r}: {word!r} is not a robot name (e.g. nubot2) "
                                       "nor all")
        return cls(frozenset(words))

    def __contains__(self, name: object) -> bool:
        return self.every or name in self.names

    def __str__(self) -> str:
        return "all" if self.every else ",".join(sorted(self.names))


def parse_agent_ids(text: str) -> tuple[int, ...]:
    """AgentIDs written ``2`` or ``2,3``; ``NubotCommonError`` for a word that is no whole number from 1."""
    words = [w.strip() for w in str(text).replace(" ", ",").split(",") if w.strip()]
    if not words or not all(w.isdigit() and int(w) >= 1 for w in words):
        raise NubotCommonError(f"AgentIDs are whole numbers from 1 such as 2 or 2,3; got {text!r}")
    return tuple(sorted({int(w) for w in words}))


TEAM_COLOURS = ("#1ec8e6", "#e83fd1", "#f2c230", "#7ad151")  # cyan, magenta, yellow, green
NO_TEAM_COLOUR = "#cccccc"


def team_colour(team: str, teams: Sequence[str]) -> str:
    """The colour (``#rrggbb``) of ``team`` among ``teams`` (the referee's order, then as seen): the same in the
    live page, RViz and a match's plots; grey for a team not among them."""
    return TEAM_COLOURS[list(teams).index(team) % len(TEAM_COLOURS)] if team in teams else NO_TEAM_COLOUR


def rgb(colour: str) -> tuple[float, float, float]:
    """``#rrggbb`` as red, green and blue in [0, 1]."""
    if not re.fullmatch(r"#[0-9a-fA-F]{6}", colour):
        raise NubotCommonError(f"a colour is #rrggbb, got {colour!r}")
    return tuple(int(colour[i:i + 2], 16) / 255.0 for i in (1, 3, 5))  # type: ignore[return-value]

"""The plain snapshot of the world one robot's strategy reads each cycle (team frame, SI units).

Provides dataclasses only: ``Mate`` (a teammate or the robot itself), ``Ball``, ``TeamState``.
The team frame has the own goal at -x and the opponent goal at +x.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from nubot_common.geometry import Pose2D
from nubot_common.match_mode import MatchMode
from nubot_control.roles import Role


@dataclass(frozen=True)
class Mate:
    agent_id: int
    pose: Pose2D
    vx: float = 0.0  # [m/s], team frame
    vy: float = 0.0
    role: Role = Role.NOROLE
    role_time: float = 0.0  # [s] the role has been kept
    holding: bool = False
    valid: bool = True


@dataclass(frozen=True)
class Ball:
    x: float
    y: float
    vx: float = 0.0  # [m/s]
    vy: float = 0.0
    known: bool = True


@dataclass(frozen=True)
class PassPlan:
    """A pass in force: who kicks, who receives, where it is caught (team frame)."""

    passer: int
    catcher: int
    catch_x: float
    catch_y: float
    kicked: bool = False


@dataclass(frozen=True)
class TeamState:
    time: float  # [s], sim time
    me: Mate
    mates: tuple[Mate, ...]  # valid teammates, without me
    ball: Ball
    opponents: tuple[tuple[float, float], ...]  # obstacle positions labelled opponents [m]
    mode: MatchMode = MatchMode.STOPROBOT
    previous_mode: MatchMode = MatchMode.STOPROBOT
    mode_since: float = 0.0  # [s] sim time the mode started
    pass_plan: PassPlan | None = None
    goalie_id: int = 1
    team_roles: dict[int, Role] = field(default_factory=dict)  # roles teammates announce

    @property
    def team(self) -> tuple[Mate, ...]:
        """All valid robots of the team, me included, by AgentID."""
        return tuple(sorted((self.me, *self.mates), key=lambda m: m.agent_id))

    def obstacles(self) -> list[tuple[float, float]]:
        """Everything to avoid except me: teammates and opponents [m]."""
        return [(m.pose.x, m.pose.y) for m in self.mates] + list(self.opponents)

"""Typed configuration of the referee (read once from ``config/referee.yaml`` and the ``~`` parameters).

Provides frozen, validated dataclasses, all values SI (m, s): ``TeamSpec`` (a team's
robot-name prefix and the goal it attacks), ``RefereeParams`` (the rules' numbers,
used by ``referee.AutomaticReferee``) and ``RefereeNodeParams`` (those plus what the
referee node needs: teams, auto mode, publishing periods, the simulator's names).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from dataclasses import field as dc_field

from nubot_common.field import FieldGeometry
from nubot_common.params import require_non_negative, require_positive

_PREFIX = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


@dataclass(frozen=True)
class TeamSpec:
    """A team: its robots are named ``<prefix>1`` ... ``<prefix>5``; ``attack`` 1 attacks the goal at +x."""

    prefix: str
    attack: int = 1

    def __post_init__(self) -> None:
        if not _PREFIX.fullmatch(self.prefix) or self.prefix[-1].isdigit():
            raise ValueError(f"team prefix must be a name not ending in a digit (e.g. nubot), got {self.prefix!r}")
        if self.attack not in (1, -1):
            raise ValueError(f"team {self.prefix!r}: attack must be 1 or -1, got {self.attack}")


DEFAULT_TEAMS = (TeamSpec("nubot", 1), TeamSpec("rival", -1))


def validate_teams(teams: Sequence[TeamSpec]) -> None:
    """Raise ``ValueError`` unless there are one or two teams with distinct prefixes and opposite attacks."""
    if not 1 <= len(teams) <= 2:
        raise ValueError(f"a match has one or two teams, got {len(teams)}")
    prefixes = [t.prefix for t in teams]
    if len(set(prefixes)) != len(prefixes):
        raise ValueError(f"team prefixes must differ, got {prefixes}")
    if len(teams) == 2 and teams[0].attack == teams[1].attack:
        raise ValueError(f"the two teams must attack opposite goals, both attack {teams[0].attack:+d}")


@dataclass(frozen=True)
class RefereeParams:
    """The numbers of the rules the automatic referee applies (times in sim seconds)."""

    field: FieldGeometry = dc_field(default_factory=FieldGeometry)
    ball_radius: float = 0.11  # [m]; "wholly over a line" means the centre is this far beyond it
    setup_time: float = 4.0  # a restart command, then STARTROBOT this much later [s]
    restart_timeout: float = 12.0  # after STARTROBOT the restart team must play the ball within this [s]
    in_play_distance: float = 0.5  # the ball moved this far from where it was placed: the restart is taken [m]
    stuck_time: float = 5.0  # a ball contested this long without moving is dropped [s]
    stuck_distance: float = 0.3  # "not moving": stays within this distance [m]
    stuck_radius: float = 1.0  # "contested": a robot of each team this close to the ball [m]
    half_duration: float = 300.0  # game clock of one half (runs only while the ball is in play) [s]
    halves: int = 2
    half_time_break: float = 10.0  # STOPROBOT at the end of a half, the next half's kickoff this much later [s]
    switch_ends: bool = True  # the teams change ends at half time
    throw_in_inset: float = 0.1  # throw-in ball centre this far inside the side line [m]
    corner_inset: float = 0.25  # corner-kick ball centre this far inside both lines [m]
    goal_kick_distance: float = 1.0  # goal-kick ball this far in front of the goal-area corner [m]
    restart_margin: float = 1.0  # throw-in x and dropped balls stay this far inside the lines [m]

    def __post_init__(self) -> None:
        require_positive(self, "ball_radius", "setup_time", "restart_timeout", "in_play_distance", "stuck_time",
                  "stuck_distance", "stuck_radius", "half_duration")
        require_non_negative(self, "half_time_break", "throw_in_inset", "corner_inset", "goal_kick_distance",
                      "restart_margin")
        if self.halves < 1:
            raise ValueError(f"halves must be at least 1, got {self.halves}")
        f = self.field
        if 2.0 * self.restart_margin >= min(f.length, f.width):
            raise ValueError(f"restart_margin {self.restart_margin} m leaves no room on a {f.length} x {f.width} m "
                             "field")
        for name in ("throw_in_inset", "corner_inset"):
            if getattr(self, name) >= f.half_width:
                raise ValueError(f"{name} must be smaller than half the field width, got {getattr(self, name)}")
        if f.goal_area_length + self.goal_kick_distance >= f.half_length:
            raise ValueError(f"goal_kick_distance {self.goal_kick_distance} m puts the goal kick past the halfway line")


@dataclass(frozen=True)
class RefereeNodeParams(RefereeParams):
    """Parameters of the referee node: the rules plus the teams and how the node talks to them."""

    teams: tuple[TeamSpec, ...] = DEFAULT_TEAMS
    auto: bool = True  # apply the rules to the simulated world; false: only manual commands
    republish_period: float = 0.03  # CoachInfo to every team this often [s, wall time]
    state_period: float = 1.0  # /referee/state at least this often [s, wall time]
    ball_name: str = "football"  # the ball's model name in the simulator
    sim_namespace: str = "/sim_visual"  # where the simulator's topics and services live

    def __post_init__(self) -> None:
        super().__post_init__()
        validate_teams(self.teams)
        require_positive(self, "republish_period", "state_period")
        if not self.ball_name:
            raise ValueError("ball_name must not be empty")
        if not self.sim_namespace.startswith("/"):
            raise ValueError(f"sim_namespace must be absolute (start with /), got {self.sim_namespace!r}")

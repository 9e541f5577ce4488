"""Typed configuration of the referee (read once from ``config/referee.yaml`` and the ``~`` parameters).

Provides frozen, validated dataclasses, all values SI (m, s): ``TeamSpec`` (a team's
robot-name prefix and the goal it attacks), ``RefereeParams`` (the rules' numbers and the
match's ``WorldDescription``, used by ``referee.AutomaticReferee``) and ``RefereeNodeParams``
(those plus what the referee node needs: teams, auto mode, publishing periods, the
simulator's namespace). The node takes the world from /world, as every node of a match.
``COACH_PERIODS``: the range of periods [s] at which CoachInfo may be sent, by the referee or the coach.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from dataclasses import field as dc_field

from nubot_common import NubotCommonError
from nubot_common.field import FieldGeometry
from nubot_common.naming import check_team_prefix
from nubot_common.params import require_non_negative, require_positive
from nubot_common.world_description import WorldDescription

COACH_PERIODS = (0.005, 10.0)  # CoachInfo at most 200 times a second and at least once in 10 s [s]


@dataclass(frozen=True)
class TeamSpec:
    """A team: its robots are named ``<prefix>1`` ... ``<prefix>5``; ``attack`` 1 attacks the goal at +x; ``goalie``
    is the AgentID of its goalkeeper."""

    prefix: str
    attack: int = 1
    goalie: int = 1

    def __post_init__(self) -> None:
        try:
            check_team_prefix(self.prefix)
        except NubotCommonError as exc:
            raise ValueError(str(exc)) from None
        if self.attack not in (1, -1):
            raise ValueError(f"team {self.prefix!r}: attack must be 1 or -1, got {self.attack}")
        if not 1 <= self.goalie <= 20:
            raise ValueError(f"team {self.prefix!r}: goalie must be an AgentID 1..20, got {self.goalie}")


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

    world: WorldDescription = dc_field(default_factory=WorldDescription)  # the field, the ball
    setup_time: float = 4.0  # a restart command, then STARTROBOT this much later [s]
    set_piece_time: float = 7.0  # after STARTROBOT the restart team has this long to play the ball; then the
    # opponents may go for it (RC-13: no stop, a slow_restart call) [s]
    restart_timeout: float = 20.0  # a restart nobody played this long after STARTROBOT: dropped ball (game stuck) [s]
    in_play_distance: float = 0.5  # the ball moved this far from where it was placed: the restart is taken [m]
    stuck_time: float = 5.0  # a ball contested this long without moving is dropped [s]
    stuck_distance: float = 0.3  # "not moving": stays within this distance [m]
    stuck_radius: float = 1.0  # "contested": a robot of each team this close to the ball [m]
    half_duration: float = 300.0  # game clock of one half (runs only while the ball is in play) [s]
    halves: int = 2
    half_time_break: float = 10.0  # STOPROBOT at the end of a half, the next half's kickoff this much later [s]
    half_limit_factor: float = 3.0  # a half ends at the latest this many half_durations of sim time after its kickoff
    # (plus half_time_break), however little the game clock ran: a match whose play keeps stopping still ends
    switch_ends: bool = True  # the teams change ends at half time
    throw_in_inset: float = 0.1  # throw-in ball centre this far inside the side line [m]
    corner_inset: float = 0.25  # corner-kick ball centre this far inside both lines [m]
    goal_kick_distance: float = 1.0  # goal-kick ball this far in front of the goal-area corner [m]
    restart_margin: float = 1.0  # throw-in x and dropped balls stay this far inside the lines [m]
    # Fouls (coach4sim.fouls, docs/rules.md); fouls: false calls none of them.
    fouls: bool = True
    carry_distance: float = 3.0  # the ball may be kept this far from where it was caught (RC-12.0.1) [m]
    release_distance: float = 0.7  # a release is seen once the ball is this far from the robot's centre [m]
    charge_speed: float = 1.0  # coming into contact with an opponent faster than this is charging (RC-12.3.2) [m/s]
    push_speed: float = 0.2  # in contact, moving towards the opponent faster than this ... [m/s]
    push_time: float = 1.0  # ... this long is pushing [s]
    area_time: float = 10.0  # a robot may stay this long in a penalty area (RC-12.3.4, RC-12.3.5) [s]
    area_robots: int = 1  # this many field robots of a team in its own penalty area, attackers in the other [1]

    def __post_init__(self) -> None:
        require_positive(self, "setup_time", "restart_timeout", "in_play_distance", "stuck_time",
                  "stuck_distance", "stuck_radius", "half_duration", "set_piece_time", "carry_distance",
                  "release_distance", "charge_speed", "push_time", "area_time")
        if self.half_limit_factor < 1.0:
            raise ValueError(f"half_limit_factor must be at least 1, got {self.half_limit_factor}")
        require_non_negative(self, "push_speed")
        if self.area_robots < 1:
            raise ValueError(f"area_robots must be at least 1, got {self.area_robots}")
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

    @property
    def field(self) -> FieldGeometry:
        return self.world.field

    @property
    def ball_radius(self) -> float:
        """[m]; "wholly over a line" means the ball's centre is this far beyond it."""
        return self.world.ball.radius


@dataclass(frozen=True)
class RefereeNodeParams(RefereeParams):
    """Parameters of the referee node: the rules plus the teams and how the node talks to them."""

    teams: tuple[TeamSpec, ...] = DEFAULT_TEAMS
    auto: bool = True  # apply the rules to the simulated world; false: only manual commands
    republish_period: float = 0.03  # CoachInfo to every team this often [s, wall time]
    state_period: float = 1.0  # /referee/state at least this often [s, wall time]
    sim_namespace: str = "/sim_visual"  # where the simulator's topics and services live

    def __post_init__(self) -> None:
        super().__post_init__()
        validate_teams(self.teams)
        require_positive(self, "state_period")
        low, high = COACH_PERIODS
        if not low <= self.republish_period <= high:
            raise ValueError(f"republish_period must lie in [{low:g}, {high:g}] s, got {self.republish_period}")
        if not self.sim_namespace.startswith("/"):
            raise ValueError(f"sim_namespace must be absolute (start with /), got {self.sim_namespace!r}")

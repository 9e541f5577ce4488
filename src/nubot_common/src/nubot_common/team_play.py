"""What teammates agree on: roles, the pass command, and each robot's strategy report.

Provides: ``Role`` (the original code's role enum), ``PassCommand`` (PassCommands: a pass agreed
between two teammates) and ``StrategyReport`` (StrategyInfo, plus the target a robot heads for).
Positions are in the team frame (own goal at -x) [m]; times are sim time [s].
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from enum import IntEnum

from nubot_common.records import fast_init

Point = tuple[float, float]  # [m], team frame


class Role(IntEnum):
    GOALIE = 0
    ACTIVE = 1  # attacker: goes for the ball
    PASSIVE = 2  # defender between the ball and the own goal
    MIDFIELD = 3
    ASSISTANT = 4  # supports the active robot, ready for a pass
    ACIDPASSIVE = 5
    GAZER = 6
    BLOCK = 7
    NOROLE = 8
    CATCHOFPASS = 9
    PASSOFPASS = 10

    @classmethod
    def of(cls, value: int) -> Role:
        """The role numbered ``value``; NOROLE for a number no role has."""
        try:
            return cls(value)
        except ValueError:
            return cls.NOROLE


@dataclass(frozen=True)
class PassCommand:
    """A pass agreed between two teammates (PassCommands)."""

    pass_id: int  # passer's AgentID
    catch_id: int  # catcher's AgentID
    pass_pt: Point = (0.0, 0.0)  # where the passer kicks from [m]
    catch_pt: Point = (0.0, 0.0)  # where the catcher receives [m]
    is_passout: bool = False  # the ball has left the passer
    is_dynamic_pass: bool = False  # a pass in open play
    is_static_pass: bool = False  # a pass at a set play
    is_valid: bool = True  # the command is in force

    def kicked(self) -> PassCommand:
        """The same pass once the ball has left the passer."""
        return replace(self, is_passout=True)


@fast_init
@dataclass(frozen=True)
class StrategyReport:
    """One robot's strategy this cycle, as its teammates and its world model learn it (StrategyInfo)."""

    stamp: float  # [s]
    agent_id: int
    role: Role = Role.NOROLE
    action: int = 0  # behaviour code (nubot_control's Action)
    role_time: float = 0.0  # how long the robot has kept its role [s]
    target_nums: tuple[int, int, int, int] = (0, 0, 0, 0)  # AgentIDs at target positions 1..4
    static_pass: int = 0  # the passer's AgentID of a set-play pass
    static_catch: int = 0  # the catcher's AgentID of a set-play pass
    holding: bool = False  # the robot holds the ball (is_dribble)
    kickoff: bool = False  # the robot takes the kickoff
    pass_cmd: PassCommand | None = None  # the pass it takes part in
    target: Point = (0.0, 0.0)  # where it is heading [m]

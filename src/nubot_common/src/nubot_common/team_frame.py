"""The team frame: each team sees the field with its own goal at -x and the goal it attacks at +x.

Provides: ``TeamFrame(attack)``; ``attack`` is 1 for a team attacking the world's goal at +x (its
frame is the world frame) and -1 for a team attacking the goal at -x (its frame is the world frame
turned half round the centre spot). Points [m], velocities [m/s] and poses ([m], [rad]) go both
ways with ``*_to_team`` and ``*_to_world``; as the turn is a half turn, each is its own inverse,
but the names say which way a value goes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from nubot_common import NubotCommonError
from nubot_common.geometry import Pose2D, wrap_angle
from nubot_common.records import fast_init


@fast_init
@dataclass(frozen=True)
class TeamFrame:
    attack: int = 1  # the world goal the team attacks: 1 at +x, -1 at -x

    def __post_init__(self) -> None:
        if self.attack not in (1, -1) or isinstance(self.attack, bool):
            raise NubotCommonError(f"attack must be 1 (the goal at +x) or -1 (the goal at -x), got {self.attack!r}")

    def _flip(self, x: float, y: float) -> tuple[float, float]:
        return (x, y) if self.attack == 1 else (-x, -y)

    def _turn(self, theta: float) -> float:
        return theta if self.attack == 1 else wrap_angle(theta + math.pi)

    def point_to_team(self, x: float, y: float) -> tuple[float, float]:
        """A world-frame point [m] in the team frame."""
        return self._flip(x, y)

    def point_to_world(self, x: float, y: float) -> tuple[float, float]:
        """A team-frame point [m] in the world frame."""
        return self._flip(x, y)

    def velocity_to_team(self, vx: float, vy: float) -> tuple[float, float]:
        """A world-frame velocity [m/s] in the team frame."""
        return self._flip(vx, vy)

    def velocity_to_world(self, vx: float, vy: float) -> tuple[float, float]:
        return self._flip(vx, vy)

    def heading_to_team(self, theta: float) -> float:
        """A world-frame heading [rad] in the team frame, in (-pi, pi]."""
        return self._turn(theta)

    def heading_to_world(self, theta: float) -> float:
        return self._turn(theta)

    def pose_to_team(self, pose: Pose2D) -> Pose2D:
        x, y = self._flip(pose.x, pose.y)
        return Pose2D(x, y, self._turn(pose.theta))

    def pose_to_world(self, pose: Pose2D) -> Pose2D:
        return self.pose_to_team(pose)

"""The team relay: what RTDB does between real teammates, for one team only (the simulation's relay node
``sim_interface`` and the real robots' ``TeamLink`` keep their teammates' latest messages with it).

Requires: messages tagged with the sender's AgentID and a stamp [s]. Provides: ``TeamRelay``
(keeps the latest message of each member and hands out those younger than ``max_age``).
The node feeds it only topics of its own team's robots, so nothing crosses to the other team.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Generic, TypeVar

from nubot_common.naming import team_of

T = TypeVar("T")


@dataclass
class TeamRelay(Generic[T]):
    team: str
    members: tuple[str, ...]  # model names of the team's robots, e.g. (nubot1, ..., nubot5)
    max_age: float = 1.0  # messages older than this are no longer relayed [s]
    _latest: dict[str, tuple[float, T]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        foreign = [m for m in self.members if team_of(m) != self.team]
        if foreign:
            raise ValueError(f"robots {foreign} are not members of team {self.team!r}")

    def put(self, member: str, stamp: float, message: T) -> None:
        if member not in self.members:
            raise ValueError(f"{member!r} is not a member of team {self.team!r}")
        self._latest[member] = (stamp, message)

    def collect(self, now: float) -> list[T]:
        """The latest message of every member heard from within ``max_age``, by member order."""
        return [self._latest[m][1] for m in self.members
                if m in self._latest and now - self._latest[m][0] <= self.max_age]

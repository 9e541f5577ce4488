"""Typed parameters of the team_link node (read once from its private namespace, ``config/team_link.yaml``).

Provides: ``TeamLinkParams``, frozen and validated (``nubot_common.params.from_mapping`` refuses unknown keys
and values of the wrong type by name; ``__post_init__`` the values out of range).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from nubot_comm.codec import DEFAULT_URL, MAX_AGENT_ID, check_team_name
from nubot_common.naming import RobotNodeParams
from nubot_common.params import require_positive

MAX_RATE = 200.0  # [Hz] far above any sender of the team (control runs at 33 Hz)
_URL = re.compile(r"[a-z]+://.*")


@dataclass(frozen=True)
class TeamLinkParams(RobotNodeParams):
    """``robot`` (and ``agent_id``) name the robot the link speaks for; the coach's side needs only ``team``."""

    team: str = ""  # the team's prefix; "" = the robot's. The coach's side serves this team
    coach: bool = False  # the coach's side: forwards its CoachInfo to the team, sends no team packet
    lcm_url: str = DEFAULT_URL  # LCM provider; udpm://group:port?ttl=1 keeps packets on the robots' LAN
    rate: float = 30.0  # the robot's packet out, teammates and strategies published [Hz]
    max_age: float = 1.0  # a member not heard from for this long is left out [s]
    key_file: str = ""  # the team's shared key (nubot_comm.signing): datagrams signed and only signed ones taken;
    # "" = unsigned, as the original team link
    max_clock_skew: float = 60.0  # packets stamped further from this robot's clock are dropped [s]; the robots'
    # and the coach's clocks must agree within it (run chrony or NTP on each)
    team_size: int = MAX_AGENT_ID  # robots in the team; AgentIDs run 1..team_size
    status_period: float = 1.0  # the link's counters on ~status [s]
    log_period: float = 10.0  # new drops are logged at most this often [s]

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.team:
            check_team_name(self.team)
        if not self.coach and self.team and self.team != self.name.team:
            raise ValueError(f"team {self.team!r} is not the team of robot {self.robot!r} (leave team empty)")
        if not 1 <= self.team_size <= MAX_AGENT_ID:
            raise ValueError(f"team_size must lie in [1, {MAX_AGENT_ID}], got {self.team_size}")
        if not self.coach and self.agent > self.team_size:
            raise ValueError(f"AgentID {self.agent} of {self.robot} is beyond team_size {self.team_size}")
        require_positive(self, "rate", "max_age", "status_period", "log_period", "max_clock_skew")
        if not self.max_clock_skew <= 86400.0:
            raise ValueError(f"max_clock_skew must be at most 86400 s, got {self.max_clock_skew}")
        if not self.rate <= MAX_RATE:
            raise ValueError(f"rate must be at most {MAX_RATE:g} Hz, got {self.rate}")
        if not _URL.fullmatch(self.lcm_url):
            raise ValueError(f"lcm_url must be an LCM URL like {DEFAULT_URL}, got {self.lcm_url!r}")

    @property
    def team_name(self) -> str:
        """The team whose channels the link uses: ``team``, or the robot's."""
        return self.team or self.name.team

    @property
    def link_agent(self) -> int:
        """The AgentID the link sends as; 0 on the coach's side."""
        return 0 if self.coach else self.agent

"""Game commands the coach sends to a team (the chapter's ``MatchMode`` enum).

Provides: ``MatchMode`` (IntEnum, values fixed by the chapter; ``is_ours``, ``is_theirs``,
``restart``, ``mirrored``), ``RestartKind`` (kickoff, throw-in, ... as the rules name them),
``OUR_SET_PLAYS`` / ``THEIR_SET_PLAYS`` and ``parse_match_mode`` (accepts a number, a name or
a ``char`` byte; raises ``NubotCommonError`` naming the bad value otherwise). A team receives
every command in its own view: ``OUR_x`` is its own restart, ``OPP_x`` the other team's.
"""

from __future__ import annotations

from enum import Enum, IntEnum

from nubot_common import NubotCommonError


class MatchMode(IntEnum):
    STOPROBOT = 0
    OUR_KICKOFF = 1
    OPP_KICKOFF = 2
    OUR_THROWIN = 3
    OPP_THROWIN = 4
    OUR_PENALTY = 5
    OPP_PENALTY = 6
    OUR_GOALKICK = 7
    OPP_GOALKICK = 8
    OUR_CORNERKICK = 9
    OPP_CORNERKICK = 10
    OUR_FREEKICK = 11
    OPP_FREEKICK = 12
    DROPBALL = 13
    STARTROBOT = 15
    PARKINGROBOT = 25
    TEST = 27

    @property
    def is_set_play(self) -> bool:
        """True for the restarts that place the team before play resumes (dropped ball included)."""
        return 1 <= self.value <= 13

    @property
    def is_ours(self) -> bool:
        """This team's own restart (OUR_KICKOFF ... OUR_FREEKICK)."""
        return 1 <= self.value <= 12 and self.value % 2 == 1

    @property
    def is_theirs(self) -> bool:
        """The other team's restart (OPP_KICKOFF ... OPP_FREEKICK)."""
        return 1 <= self.value <= 12 and self.value % 2 == 0

    @property
    def restart(self) -> RestartKind | None:
        """Which restart this command sets up (either team's), None for STOP, START, PARK and TEST."""
        if 1 <= self.value <= 12:
            return _RESTARTS[(self.value - 1) // 2]
        return RestartKind.DROPBALL if self == MatchMode.DROPBALL else None

    def mirrored(self) -> MatchMode:
        """The same command as the other team must receive it (OUR_x <-> OPP_x)."""
        if 1 <= self.value <= 12:
            return MatchMode(self.value + 1 if self.value % 2 else self.value - 1)
        return self


class RestartKind(Enum):
    KICKOFF = "kickoff"
    THROWIN = "throw-in"
    PENALTY = "penalty"
    GOALKICK = "goal kick"
    CORNERKICK = "corner kick"
    FREEKICK = "free kick"
    DROPBALL = "dropped ball"

    def ours(self) -> MatchMode:
        """The command giving this restart to the team that receives it (DROPBALL is nobody's)."""
        if self is RestartKind.DROPBALL:
            return MatchMode.DROPBALL
        return MatchMode(2 * _RESTARTS.index(self) + 1)


_RESTARTS = (RestartKind.KICKOFF, RestartKind.THROWIN, RestartKind.PENALTY, RestartKind.GOALKICK,
             RestartKind.CORNERKICK, RestartKind.FREEKICK)
OUR_SET_PLAYS = frozenset(m for m in MatchMode if m.is_ours)
THEIR_SET_PLAYS = frozenset(m for m in MatchMode if m.is_theirs)


def parse_match_mode(value: int | str | bytes) -> MatchMode:
    """Turn an integer, an enum name or a one-byte ``char`` into a ``MatchMode``."""
    if isinstance(value, bytes):
        if len(value) != 1:
            raise NubotCommonError(f"MatchMode must be one byte, got {value!r}")
        value = value[0]
    if isinstance(value, str):
        text = value.strip()
        if text.lstrip("-").isascii() and text.lstrip("-").isdigit():
            value = int(text)
        else:
            try:
                return MatchMode[text.upper()]
            except KeyError:
                names = ", ".join(m.name for m in MatchMode)
                raise NubotCommonError(f"unknown MatchMode name {value!r}; known: {names}") from None
    if isinstance(value, bool) or not isinstance(value, int):
        raise NubotCommonError(f"MatchMode must be an integer, a name or one byte, got {value!r}")
    try:
        return MatchMode(value)
    except ValueError:
        known = ", ".join(f"{m.name}={m.value}" for m in MatchMode)
        raise NubotCommonError(f"unknown MatchMode {value!r}; known: {known}") from None

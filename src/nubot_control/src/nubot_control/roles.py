"""Roles of a NuBot player (values as in the original code's core enum)."""

from enum import IntEnum


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


# The order in which field roles are filled when fewer robots are available.
FIELD_ROLE_PRIORITY = (Role.ACTIVE, Role.PASSIVE, Role.ASSISTANT, Role.MIDFIELD)

"""The colour classes a pixel of the robots' cameras can belong to: what the vision's colour table gives and what
the simulator's cameras label their pixels with (one home for both)."""

from enum import IntEnum


class ColorClass(IntEnum):
    UNKNOWN = 0  # not calibrated, or nothing the vision uses
    GREEN = 1  # the carpet
    WHITE = 2  # field lines (and goal frames)
    BALL = 3  # the ball's colour
    BLACK = 4  # robots (obstacles) and the robot's own body

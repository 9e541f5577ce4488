"""Where the MSL rules let a field robot stand: out of the goal areas, and out of the penalty areas unless it plays the
ball there (team frame, own goal at -x; docs/rules.md RC-12.3.4, RC-12.3.5, RC-12.3.10).

Requires: the field (``FieldGeometry``) and a target point [m]. Provides: ``in_area`` (whether a point lies in a
penalty or goal area, own or the opponents', the line included), ``keep_out`` (the nearest point on the field side
of the areas a robot must stay out of, ``AREA_MARGIN`` beyond their lines), ``no_go`` (those areas as rectangles,
grown by the margin) and ``stay_out`` (a velocity [m/s] without what would take the robot into one of them: the
motion layer's wall, as ``motion.keep_clear`` is its guard against robots; from inside, out by the nearest side).
The goalie stands where it likes; the robot playing the ball (ACTIVE) may enter a penalty area but never a goal
area; every other field robot keeps out of both penalty areas, so that no second defender or attacker is ever in one.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from nubot_common.field import FieldGeometry
from nubot_common.kernels import load_kernels

if TYPE_CHECKING:
    from nubot_control import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("nubot_control")

AREA_MARGIN = 0.35  # kept between a robot's centre and an area's line: noise and overshoot stay outside [m]

Rect = tuple[float, float, float, float]  # x_min, x_max, y_min, y_max [m]


def _area(field: FieldGeometry, own: bool, goal_area: bool) -> tuple[float, float, float]:
    """(sign of the goal line's x, depth [m], half width [m]) of an area."""
    depth = field.goal_area_length if goal_area else field.penalty_area_length
    width = field.goal_area_width if goal_area else field.penalty_area_width
    return (-1.0 if own else 1.0), depth, width / 2.0


def in_area(x: float, y: float, field: FieldGeometry, own: bool, goal_area: bool = False,
            margin: float = 0.0) -> bool:
    """Whether (x, y) lies in the area (its line included), grown by ``margin``."""
    side, depth, half = _area(field, own, goal_area)
    return (x * side >= field.half_length - depth - margin) & (abs(y) <= half + margin)  # numpy arrays too


def _push_out(x: float, y: float, field: FieldGeometry, own: bool, goal_area: bool,
              margin: float) -> tuple[float, float]:
    if not in_area(x, y, field, own, goal_area, margin):
        return x, y
    side, depth, half = _area(field, own, goal_area)
    front = (side * (field.half_length - depth - margin), y)
    beside = (x, (half + margin) * (1.0 if y >= 0.0 else -1.0))
    return min((front, beside), key=lambda p: (p[0] - x) ** 2 + (p[1] - y) ** 2)


def keep_out(x: float, y: float, field: FieldGeometry, penalty_areas: bool, margin: float = AREA_MARGIN
             ) -> tuple[float, float]:
    """(x, y) moved to the nearest point out of both goal areas and, with ``penalty_areas``, out of both penalty
    areas too, ``margin`` beyond their lines."""
    if abs(x) < field.half_length - field.penalty_area_length - margin:  # short of every area (most targets)
        return x, y
    for own in (True, False):
        if penalty_areas:
            x, y = _push_out(x, y, field, own, False, margin)
        x, y = _push_out(x, y, field, own, True, margin)
    return x, y


def no_go(field: FieldGeometry, penalty_areas: bool, margin: float = AREA_MARGIN) -> list[Rect]:
    """The areas a robot must stay out of as rectangles grown by ``margin`` on their field sides (reaching beyond the
    goal lines): both goal areas, and with ``penalty_areas`` both penalty areas (which hold the goal areas)."""
    rects = []
    for own in (True, False):
        side, depth, half = _area(field, own, goal_area=not penalty_areas)
        inner = field.half_length - depth - margin
        outer = field.half_length + field.border + 1.0
        x0, x1 = (-outer, -inner) if side < 0 else (inner, outer)
        rects.append((x0, x1, -half - margin, half + margin))
    return rects


def stay_out(position: tuple[float, float], velocity: tuple[float, float], rects: Sequence[Rect], brake: float,
             latency: float) -> tuple[float, float]:
    """``velocity`` [m/s] without what would take the robot at ``position`` into one of ``rects``: towards each, at
    most the speed from which it stops at its side, braking at ``brake`` [m/s^2] after ``latency`` [s]; along the side
    it keeps its speed. Inside one it leaves by the nearest side at 0.8 m/s at least. Compiled (``cpp/motion.cpp``,
    the motion layer's)."""
    return _kernels.stay_out(position, velocity, rects, float(brake), float(latency))

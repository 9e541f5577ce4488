"""Geometry of an MSL field, in the world frame (origin at the centre spot, x along the length, metres).

Provides: ``FieldGeometry`` (frozen, validated), with the 2015 18 x 12 m field of the
chapter as default and ``FieldGeometry.msl_current()`` for the 22 x 14 m field of the current
rules; goal-post positions, inside/outside tests (``goal_holding``: which goal a ball lies in, i.e. a goal)
and every white marking: ``line_segments``
(touch, goal and halfway lines, penalty and goal areas), ``arcs`` (centre circle, corner arcs)
and ``spots`` (centre spot, penalty marks).
Parameters [m] (letters of the MSL rulebook's field drawing): length A, width B, goal_width
(inner, between posts), goal_height (under the bar), goal_depth, penalty area (length E along x,
width C), goal area (F, D), centre_circle_radius (H / 2), corner_arc_radius G,
penalty_mark_distance I (from the goal line), spot_diameter J, line_width K, border L (the
run-off area outside the lines). The field file of a match is ``world_description``'s YAML.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property


@dataclass(frozen=True)
class Arc:
    """A white arc: centre (x, y) [m], radius [m], from ``start`` to ``end`` counter-clockwise [rad]."""

    x: float
    y: float
    radius: float
    start: float
    end: float


@dataclass(frozen=True)
class FieldGeometry:
    length: float = 18.0
    width: float = 12.0
    goal_width: float = 2.4
    goal_height: float = 1.0
    goal_depth: float = 0.6
    post_radius: float = 0.0625
    penalty_area_length: float = 2.25
    penalty_area_width: float = 6.5
    goal_area_length: float = 0.75
    goal_area_width: float = 3.5
    center_circle_radius: float = 2.0
    corner_arc_radius: float = 0.75
    penalty_mark_distance: float = 3.0
    spot_diameter: float = 0.15
    line_width: float = 0.125
    border: float = 1.0

    def __post_init__(self) -> None:
        for name in ("length", "width", "goal_width", "goal_height", "goal_depth", "post_radius",
                     "penalty_area_length", "penalty_area_width", "goal_area_length", "goal_area_width",
                     "center_circle_radius", "corner_arc_radius", "penalty_mark_distance", "spot_diameter",
                     "line_width", "border"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"{name} must be positive, got {getattr(self, name)}")
        if self.goal_width >= self.width:
            raise ValueError("goal_width must be smaller than the field width")
        for area in ("penalty_area", "goal_area"):
            if getattr(self, f"{area}_width") >= self.width or getattr(self, f"{area}_length") >= self.length / 2:
                raise ValueError(f"the {area.replace('_', ' ')} must fit inside one half of the field")
        if self.goal_area_width > self.penalty_area_width or self.goal_area_length > self.penalty_area_length:
            raise ValueError("the goal area must lie inside the penalty area")
        if self.center_circle_radius >= min(self.half_length, self.half_width):
            raise ValueError("the centre circle must fit inside the field")
        if self.penalty_mark_distance >= self.half_length:
            raise ValueError("the penalty mark must lie in its own half")

    @classmethod
    def msl_current(cls) -> FieldGeometry:
        """The 22 x 14 m field of the current MSL rules."""
        return cls(length=22.0, width=14.0, penalty_area_length=2.25, penalty_area_width=6.9,
                   goal_area_length=0.75, goal_area_width=3.9, penalty_mark_distance=3.6)

    # The halves and the goal's outer width are read thousands of times a second: each is worked out once and kept
    # in the (frozen) instance's __dict__, where it is found like a field.
    @cached_property
    def half_length(self) -> float:
        return self.length / 2.0

    @cached_property
    def half_width(self) -> float:
        return self.width / 2.0

    def goal_posts(self, side: int) -> tuple[tuple[float, float], tuple[float, float]]:
        """Centres of the two posts of the goal at +x (side 1) or -x (side -1)."""
        x = side * (self.half_length + self.post_radius)
        y = self.goal_width / 2.0 + self.post_radius
        return (x, -y), (x, y)

    def goal_frame(self, side: int, spacing: float) -> list[tuple[float, float]]:
        """The goal at +x (side 1) or -x (side -1) as points at most ``spacing`` [m] apart along its footprint:
        the posts, the side nets back to the back net, and the back net (the centres of the posts' circles, and
        lines through them): what a robot cannot drive through."""
        if not spacing > 0.0:
            raise ValueError(f"spacing must be positive, got {spacing}")
        (x0, y0), (_, y1) = self.goal_posts(side)
        back = side * (self.half_length + self.goal_depth + self.post_radius)

        def along(a: tuple[float, float], b: tuple[float, float]) -> list[tuple[float, float]]:
            pieces = max(1, math.ceil(math.dist(a, b) / spacing))
            return [(a[0] + (b[0] - a[0]) * i / pieces, a[1] + (b[1] - a[1]) * i / pieces) for i in range(pieces)]

        corners = [(x0, y0), (back, y0), (back, y1), (x0, y1)]
        return [p for a, b in zip(corners, corners[1:]) for p in along(a, b)] + [corners[-1]]

    def is_inside(self, x: float, y: float, margin: float = 0.0) -> bool:
        """True when (x, y) is within the lines grown by ``margin`` on every side."""
        return abs(x) <= self.half_length + margin and abs(y) <= self.half_width + margin

    def is_in_goal_mouth(self, y: float, z: float, ball_radius: float) -> bool:
        """True when a ball centred at lateral y and height z passes wholly between the posts and under the bar."""
        return abs(y) <= self.goal_width / 2.0 - ball_radius and z <= self.goal_height - ball_radius

    @cached_property
    def goal_outer_half_width(self) -> float:
        """Half the goal's width outside its posts, where its side nets hang [m]."""
        return self.goal_width / 2.0 + 2.0 * self.post_radius

    def in_goal(self, x: float, y: float, margin: float = 0.0) -> bool:
        """True when (x, y) lies on the ground inside a goal: behind its goal line, between its side nets, at most
        ``goal_depth`` + ``margin`` behind the line."""
        behind = abs(x) - self.half_length
        return 0.0 < behind <= self.goal_depth + margin and abs(y) < self.goal_outer_half_width

    def goal_holding(self, x: float, y: float, z: float, ball_radius: float) -> int:
        """The goal that holds a ball centred at (x, y, z): 1 (at +x), -1 (at -x) or 0 (none).

        Held means wholly behind the goal line, before the back net, inside the side nets and under the bar. The
        goal is closed by posts, bar and nets except between the posts under the bar, so a ball that came in from
        the field and is held has crossed the line there: a goal. This is the one test of a goal, judged on any
        one state of the ball, so that the simulator (every physics step) and the referee (the states it is
        sent) agree however far apart their looks are; a ball that enters grazing a post or the bar counts once
        it is inside, as on a real field.
        """
        behind = abs(x) - self.half_length
        if not ball_radius < behind <= self.goal_depth:
            return 0
        if abs(y) >= self.goal_outer_half_width or z >= self.goal_height:
            return 0
        return 1 if x > 0.0 else -1

    def line_segments(self) -> list[tuple[tuple[float, float], tuple[float, float]]]:
        """Straight white lines as ((x0, y0), (x1, y1)) pairs (centre circle excluded)."""
        hl, hw = self.half_length, self.half_width
        segments = [((-hl, -hw), (hl, -hw)), ((-hl, hw), (hl, hw)), ((-hl, -hw), (-hl, hw)),
                    ((hl, -hw), (hl, hw)), ((0.0, -hw), (0.0, hw))]
        for side in (-1, 1):
            for depth, half in ((self.penalty_area_length, self.penalty_area_width / 2),
                                (self.goal_area_length, self.goal_area_width / 2)):
                x0, x1 = side * hl, side * (hl - depth)
                segments += [((x0, -half), (x1, -half)), ((x0, half), (x1, half)), ((x1, -half), (x1, half))]
        return segments

    def arcs(self) -> list[Arc]:
        """The centre circle and the four corner arcs (each a quarter circle inside the field)."""
        hl, hw, r = self.half_length, self.half_width, self.corner_arc_radius
        arcs = [Arc(0.0, 0.0, self.center_circle_radius, -math.pi, math.pi)]
        # Each corner's quarter circle opens towards the field: from the goal line to the touch line.
        for cx, cy, start in ((hl, hw, math.pi), (-hl, hw, -math.pi / 2), (-hl, -hw, 0.0), (hl, -hw, math.pi / 2)):
            arcs.append(Arc(cx, cy, r, start, start + math.pi / 2))
        return arcs

    def spots(self) -> list[tuple[float, float]]:
        """Centres [m] of the centre spot and the two penalty marks (each ``spot_diameter`` wide)."""
        x = self.half_length - self.penalty_mark_distance
        return [(0.0, 0.0), (-x, 0.0), (x, 0.0)]

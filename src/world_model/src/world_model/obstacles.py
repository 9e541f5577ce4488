"""Obstacle fusion and labelling: which of the robots seen are teammates, which opponents.

Requires: this robot's own obstacles and pose, the obstacles its valid teammates
report, the valid teammates' own positions (team frame, [m]). Provides:
``label_obstacles``: own obstacles first, then teammates' obstacles that are no robot
already listed (farther than ``merge_radius`` from each) and not this robot itself
(farther than ``teammate_radius`` from its pose); each obstacle within
``teammate_radius`` of a valid teammate's reported position is that teammate (the
nearest such), every other one an opponent.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from nubot_common.geometry import Pose2D
from nubot_common.team_play import Point
from nubot_common.world_state import LabelledObstacle, ObstacleLabel


def _near(p: Point, points: Sequence[Point], radius: float) -> bool:
    return any(math.hypot(p[0] - q[0], p[1] - q[1]) <= radius for q in points)


def label_obstacles(me: Pose2D, agent_id: int, own: Sequence[Point], reported: Mapping[int, Sequence[Point]],
                    mates: Mapping[int, Point], teammate_radius: float, merge_radius: float
                    ) -> tuple[LabelledObstacle, ...]:
    """Merge and label obstacles; ``reported`` and ``mates`` are keyed by the teammates' AgentIDs."""
    merged: list[tuple[Point, int]] = [(p, agent_id) for p in own]
    for observer in sorted(reported):
        for p in reported[observer]:
            if math.hypot(p[0] - me.x, p[1] - me.y) <= teammate_radius:
                continue  # the teammate sees this robot
            if not _near(p, [q for q, _ in merged], merge_radius):
                merged.append((p, observer))
    labelled = []
    for (x, y), observer in merged:
        distances = {aid: math.hypot(x - mx, y - my) for aid, (mx, my) in mates.items() if aid != agent_id}
        near = [aid for aid, d in distances.items() if d <= teammate_radius]
        mate = min(near, key=lambda aid: (distances[aid], aid)) if near else 0
        label = ObstacleLabel.TEAMMATE if mate else ObstacleLabel.OPPONENT
        labelled.append(LabelledObstacle(x, y, label, mate, observer, me.bearing_to(x, y), me.distance_to(x, y)))
    return tuple(labelled)

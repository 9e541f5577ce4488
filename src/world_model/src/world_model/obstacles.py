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


def label_obstacles(me: Pose2D, agent_id: int, own: Sequence[Point], reported: Mapping[int, Sequence[Point]],
                    mates: Mapping[int, Point], teammate_radius: float, merge_radius: float
                    ) -> tuple[LabelledObstacle, ...]:
    """Merge and label obstacles; ``reported`` and ``mates`` are keyed by the teammates' AgentIDs."""
    # Plain loops that stop at the first match: run every cycle on a few dozen points, where numpy's
    # per-call overhead and generator expressions cost more than the arithmetic.
    hypot = math.hypot
    mx, my = me.x, me.y
    merged: list[tuple[float, float, int]] = [(p[0], p[1], agent_id) for p in own]
    for observer in sorted(reported):
        for p in reported[observer]:
            x, y = p[0], p[1]
            if hypot(x - mx, y - my) <= teammate_radius:
                continue  # the teammate sees this robot
            for qx, qy, _ in merged:
                if hypot(x - qx, y - qy) <= merge_radius:
                    break
            else:
                merged.append((x, y, observer))
    others = sorted((aid, q[0], q[1]) for aid, q in mates.items() if aid != agent_id)
    labelled = []
    for x, y, observer in merged:
        mate, best = 0, math.inf
        for aid, qx, qy in others:  # by AgentID: the lower one wins a tie
            d = hypot(x - qx, y - qy)
            if d <= teammate_radius and d < best:
                mate, best = aid, d
        label = ObstacleLabel.TEAMMATE if mate else ObstacleLabel.OPPONENT
        labelled.append(LabelledObstacle(x, y, label, mate, observer, me.bearing_to(x, y), me.distance_to(x, y)))
    return tuple(labelled)

"""Obstacle tracking, fusion and labelling: where the robots seen are going, which are teammates, which opponents.

Requires: this robot's own obstacles and pose, the obstacles its valid teammates
report, the valid teammates' own positions (team frame, [m]). Provides:
``ObstacleTracker``: own obstacle percepts followed from frame to frame (each percept to the nearest track within a
gate, nearest pairs first), each track an alpha-beta filter (a constant-velocity Kalman filter in its steady state)
that smooths the percepts' noise and estimates the robot's velocity; a track no percept continues is kept for a
short coast, then dropped (compiled: ``world_model._kernels``, from ``cpp/obstacles.cpp``).
``label_obstacles``: own obstacles first, then teammates' obstacles that are no robot
already listed (farther than ``merge_radius`` from each) and not this robot itself
(farther than ``teammate_radius`` from its pose); each obstacle within
``teammate_radius`` of a valid teammate's reported position is that teammate (the
nearest such), every other one an opponent (compiled: ``world_model._kernels``, from ``cpp/labels.cpp``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

from nubot_common.geometry import Pose2D
from nubot_common.kernels import load_kernels
from nubot_common.team_play import Point
from nubot_common.world_state import LabelledObstacle, ObstacleLabel

if TYPE_CHECKING:
    from world_model import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("world_model")


class ObstacleTracker(_kernels.ObstacleTracker):
    """Own obstacle percepts of successive frames, followed as tracks: ``update`` with each frame, ``estimate`` to read.

    A percept continues the nearest track predicted to its frame's time within ``gate`` [m] (the closest pairs
    first); the track moves by ``position_gain`` of the difference and its velocity by ``velocity_gain`` of it per
    frame interval (larger shares while the track is young: its first percepts count as in a straight-line fit, so a
    robot first seen running has its velocity within a few frames); the speed is at most ``max_speed`` [m/s]. A
    percept no track takes starts one at rest. A track no percept continues is kept ``coast`` [s] after its last
    percept (a robot hidden for a frame or two), then dropped. With percepts 0.05 m from the truth (per axis) at 30
    frames a second, the gains 0.4 and 0.1 leave about 0.6 of the percepts' error and a velocity within about
    0.3 m/s; a robot speeding up at 4 m/s^2 is followed about 0.03 m behind.

    ``ObstacleTracker(gate, position_gain, velocity_gain, coast, max_speed)``, the values as ``WorldModelParams``
    (``obstacle_*``) checks them; ``update(stamp, percepts)``: the obstacles of the frame taken at ``stamp`` [s] (a
    frame not newer than the last is ignored); ``estimate(t)``: the tracks of the last ``coast`` [s] before the
    latest frame, moved on to ``t`` [s], as (positions [m], velocities [m/s]) in the same order; ``reset()``."""


def label_obstacles(me: Pose2D, agent_id: int, own: Sequence[Point], reported: Mapping[int, Sequence[Point]],
                    mates: Mapping[int, Point], teammate_radius: float, merge_radius: float,
                    velocities: Sequence[Point] = ()) -> tuple[LabelledObstacle, ...]:
    """Merge and label obstacles; ``reported`` and ``mates`` are keyed by the teammates' AgentIDs; ``velocities``
    are those of ``own`` (at rest where missing; teammates' obstacles come without one). Compiled
    (``world_model._kernels``, from ``cpp/labels.cpp``)."""
    rows = _kernels.label_obstacles(me.x, me.y, me.theta, agent_id, own,
                                    [(observer, p[0], p[1]) for observer, points in reported.items() for p in points],
                                    [(aid, q[0], q[1]) for aid, q in mates.items()], teammate_radius, merge_radius)
    teammate, opponent, still = ObstacleLabel.TEAMMATE, ObstacleLabel.OPPONENT, (0.0, 0.0)
    return tuple(LabelledObstacle(x, y, teammate if mate else opponent, mate, observer, angle, radius,
                                  *(velocities[n] if n < len(velocities) else still))
                 for n, (x, y, observer, mate, angle, radius) in enumerate(rows))

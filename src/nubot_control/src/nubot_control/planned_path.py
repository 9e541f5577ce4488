"""The path the motion layer follows now, as a few points to draw (``nubot_common/PlannedPath``).

Requires: a ``MotionController`` after its last cycle (team frame, m). Provides: ``planned_path(motion)`` ->
points from the robot's position to the goal, at most ``max_points`` [-], or none when there is no plan
(the robot stands still, or the motion layer was reset). With the mpc tracker the points follow what remains
of ``MotionController.trajectory`` from where the robot should be now (``plan_age``), evenly spaced in arc
length and at least ``min_spacing`` [m] apart; with the baseline tracker they are the robot and the
waypoints it still has to reach. A bag records every robot's path at 10 Hz: a few points keep it small.
"""

from __future__ import annotations

import math

import numpy as np

from nubot_control.motion import MotionController

MAX_POINTS = 20  # [-] points of one path, the robot's position included
MIN_SPACING = 0.25  # [m] points of a short path stay at least this far apart along it

Point = tuple[float, float]


def planned_path(motion: MotionController, max_points: int = MAX_POINTS, min_spacing: float = MIN_SPACING
                 ) -> list[Point]:
    """The plan being followed as points from the robot's position to the goal (team frame [m]); [] for none."""
    if max_points < 2 or not min_spacing > 0.0:
        raise ValueError(f"a path needs max_points >= 2 and min_spacing > 0, got {max_points} and {min_spacing}")
    me = motion.position
    if me is None:
        return []
    trajectory = motion.trajectory
    if motion.mpc is not None:
        if trajectory is None:
            return []
        t, s, xy = trajectory.t, trajectory.s, trajectory.xy
        s_now, s_end = float(np.interp(motion.plan_age, t, s)), float(s[-1])
        count = min(max_points - 1, max(2, math.ceil((s_end - s_now) / min_spacing) + 1))
        along = np.linspace(s_now, s_end, count)
        ahead = np.column_stack((np.interp(along, s, xy[:, 0]), np.interp(along, s, xy[:, 1])))
        return [me] + [(float(x), float(y)) for x, y in ahead]
    waypoints = list(motion.waypoints)
    if not waypoints:
        return []
    if len(waypoints) > max_points - 1:  # the next ones and the goal
        waypoints = waypoints[:max_points - 2] + waypoints[-1:]
    return [me] + waypoints

"""Hybrid distributed role allocation: every robot computes the same team assignment from shared data.

Requires: ``TeamState`` (valid teammates with poses and announced roles, the ball) and
``PlayParams``. Provides: ``RoleAllocator.assign`` -> {AgentID: Role} for the whole team.
Steps (chapter 4.3): evaluation (each robot's time to reach the ball; each robot's distance
to each support position), assignment (the fastest robot becomes ACTIVE, the others get
the support roles by minimum total distance, ``scipy.optimize.linear_sum_assignment``),
dynamic reassignment every cycle with hysteresis (the announced ACTIVE keeps its role until
a challenger is ``role_hysteresis`` seconds faster and it has held the role
``min_role_time``). Robots that drop out are simply absent; ties break by AgentID, so
teammates with the same data reach the same answer. With the ball lost, no time to reach it
is known: the announced ACTIVE robot keeps its role (the nearest to where the ball was last seen
takes it if none is announced), and the support spots stay those of its last position.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import linear_sum_assignment

from nubot_common.field import FieldGeometry
from nubot_common.percepts import RobotReport
from nubot_common.team_play import Role
from nubot_common.world_state import FusedBall
from nubot_control.params import MotionParams, PlayParams
from nubot_control.team_state import TeamState

# The order in which field roles are filled when fewer robots are available.
FIELD_ROLE_PRIORITY = (Role.ACTIVE, Role.PASSIVE, Role.ASSISTANT, Role.MIDFIELD)
_TURN_TIME_PER_RAD = 0.25  # [s/rad] cost of facing the ball
_BEHIND_PENALTY = 1.0  # [s] extra for a robot on the wrong side of the ball (between ball and opponent goal)


def time_to_ball(mate: RobotReport, ball: FusedBall, motion: MotionParams) -> float:
    """Estimated time [s] for ``mate`` to reach the ball, facing it."""
    distance = mate.pose.distance_to(ball.x, ball.y)
    turn = abs(mate.pose.bearing_to(ball.x, ball.y))
    behind = _BEHIND_PENALTY if mate.pose.x > ball.x + 0.5 else 0.0
    return distance / motion.max_speed + turn * _TURN_TIME_PER_RAD + behind


def support_positions(ball: FusedBall, field: FieldGeometry) -> dict[Role, tuple[float, float]]:
    """Where the support roles stand, given the ball (team frame, own goal at -x)."""
    own_goal = (-field.half_length, 0.0)
    dx, dy = ball.x - own_goal[0], ball.y - own_goal[1]
    d = max(math.hypot(dx, dy), 1e-6)
    guard = min(max(0.45 * d, 2.5), max(d - 1.5, 1.0))
    passive = (own_goal[0] + dx / d * guard, own_goal[1] + dy / d * guard)
    side = -1.0 if ball.y > 0.5 else 1.0
    assistant = (min(ball.x + 2.5, field.half_length - 2.0), max(-field.half_width + 1.0,
                                                                 min(field.half_width - 1.0, ball.y + side * 3.0)))
    midfield = (max(-field.half_length + 3.0, min(ball.x - 2.5, field.half_length - 4.0)),
                max(-field.half_width + 1.0, min(field.half_width - 1.0, -side * 2.5)))
    return {Role.PASSIVE: passive, Role.ASSISTANT: assistant, Role.MIDFIELD: midfield}


class RoleAllocator:
    def __init__(self, play: PlayParams, motion: MotionParams, field: FieldGeometry):
        self.play, self.motion, self.field = play, motion, field

    def assign(self, state: TeamState) -> dict[int, Role]:
        team = list(state.team)
        roles: dict[int, Role] = {}
        field_players = []
        for mate in team:
            if mate.agent_id == self.play.goalie_id:
                roles[mate.agent_id] = Role.GOALIE
            else:
                field_players.append(mate)
        if not field_players:
            return roles
        active = self._pick_active(field_players, state)
        roles[active.agent_id] = Role.ACTIVE
        rest = [m for m in field_players if m.agent_id != active.agent_id]
        wanted = [r for r in FIELD_ROLE_PRIORITY if r != Role.ACTIVE][: len(rest)]
        if rest:
            spots = support_positions(state.ball, self.field)
            cost = np.array([[m.pose.distance_to(*spots[r]) for r in wanted] for m in rest])
            rows, cols = linear_sum_assignment(cost)
            for i, j in zip(rows, cols):
                roles[rest[i].agent_id] = wanted[j]
        return roles

    def _pick_active(self, players: list[RobotReport], state: TeamState) -> RobotReport:
        times = {m.agent_id: time_to_ball(m, state.ball, self.motion) for m in players}
        for m in players:
            if m.holding:
                return m  # whoever has the ball is the attacker
        best = min(players, key=lambda m: (round(times[m.agent_id], 3), m.agent_id))
        holder = next((m for m in players if m.role == Role.ACTIVE), None)
        if holder is None or holder.agent_id == best.agent_id:
            return best
        if not state.ball.known:
            return holder  # no time to the ball is known: nobody takes the ball over
        if holder.role_time < self.play.min_role_time:
            return holder
        if times[best.agent_id] < times[holder.agent_id] - self.play.role_hysteresis:
            return best
        return holder

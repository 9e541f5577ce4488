"""The single-robot demo behaviour of chapter 5.2 (Fig. 17), as a pure state machine.

Requires: each cycle a ``DemoPerception`` (own pose and ball, team frame, from
OmniVisionInfo; whether the robot holds the ball). Provides: ``DemoBehaviour.step``
returning a ``DemoAction`` (body-frame velocity, an optional BallHandle request,
an optional Shoot request) and the state transitions it made. States:
CHASE_BALL -> DRIBBLE_BALL (MOVE_BALL, ROTATE_BALL) -> KICK_BALL -> RESET -> HOME.
Motion follows trapezoidal speed profiles (``DemoParams``: 3 m/s, 2 m/s^2,
120 deg/s, 120 deg/s^2 by default).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

from nubot_common.geometry import Pose2D, rotate, wrap_angle
from nubot_common.params import require_positive


class DemoState(Enum):
    CHASE_BALL = "CHASE_BALL"
    MOVE_BALL = "DRIBBLE_BALL/MOVE_BALL"
    ROTATE_BALL = "DRIBBLE_BALL/ROTATE_BALL"
    KICK_BALL = "KICK_BALL"
    RESET = "RESET"
    HOME = "HOME"


@dataclass(frozen=True)
class DemoParams:
    max_speed: float = 3.0  # [m/s]
    max_accel: float = 2.0  # [m/s^2]
    max_rot_speed_deg: float = 120.0  # [deg/s]
    max_rot_accel_deg: float = 120.0  # [deg/s^2]
    dribble_speed: float = 1.5  # speed limit while holding the ball [m/s]
    grab_distance: float = 0.45  # ask for the ball when this close (centre to centre) [m]
    shoot_distance: float = 6.0  # dribble to this distance in front of the goal line [m]
    shot: str = "lob"  # "lob" or "ground"
    ground_strength: int = 8  # ground shot speed [m/s]
    aim_tolerance_deg: float = 3.0  # kick when facing the goal this well [deg]
    position_tolerance: float = 0.15  # [m]
    field_half_length: float = 9.0  # [m]
    home: tuple[float, float, float] = (-2.0, 0.0, 0.0)  # x [m], y [m], theta [rad], team frame

    def __post_init__(self) -> None:
        if self.shot not in ("lob", "ground"):
            raise ValueError(f"shot must be 'lob' or 'ground', got {self.shot!r}")
        require_positive(self, "max_speed", "max_accel", "max_rot_speed_deg", "max_rot_accel_deg", "dribble_speed")


@dataclass(frozen=True)
class DemoPerception:
    time: float  # [s]
    pose: Pose2D  # own pose, team frame
    ball: tuple[float, float] | None  # ball position, team frame [m]; None if unseen
    holding: bool


@dataclass(frozen=True)
class DemoAction:
    vx: float = 0.0  # body frame [m/s]
    vy: float = 0.0
    w: float = 0.0  # [rad/s]
    ball_handle: int | None = None  # BallHandle request (1 hold, 0 release) or None
    shoot: tuple[int, int] | None = None  # Shoot request (strength, ShootPos) or None


class DemoBehaviour:
    def __init__(self, params: DemoParams):
        self.params = params
        self.state = DemoState.CHASE_BALL
        self._velocity = (0.0, 0.0)  # last commanded world velocity [m/s]
        self._w = 0.0
        self._last_time: float | None = None
        self.kicks = 0

    def _goto(self, p: DemoPerception, dt: float, target: tuple[float, float], heading: float,
              speed_limit: float) -> tuple[float, float, float]:
        """Trapezoidal move towards ``target`` turning to ``heading``; returns a body-frame command."""
        prm = self.params
        dx, dy = target[0] - p.pose.x, target[1] - p.pose.y
        dist = math.hypot(dx, dy)
        speed = min(speed_limit, math.sqrt(2.0 * prm.max_accel * max(dist - 0.02, 0.0)))
        want = (dx / dist * speed, dy / dist * speed) if dist > 1e-6 else (0.0, 0.0)
        dvx, dvy = want[0] - self._velocity[0], want[1] - self._velocity[1]
        dv = math.hypot(dvx, dvy)
        if dv > prm.max_accel * dt:
            dvx, dvy = dvx / dv * prm.max_accel * dt, dvy / dv * prm.max_accel * dt
        self._velocity = (self._velocity[0] + dvx, self._velocity[1] + dvy)
        err = wrap_angle(heading - p.pose.theta)
        w_max, a_max = math.radians(prm.max_rot_speed_deg), math.radians(prm.max_rot_accel_deg)
        w_want = math.copysign(min(w_max, math.sqrt(2.0 * a_max * abs(err)), 4.0 * abs(err)), err)
        self._w += max(-a_max * dt, min(a_max * dt, w_want - self._w))
        bx, by = rotate(self._velocity[0], self._velocity[1], -p.pose.theta)
        return bx, by, self._w

    def step(self, p: DemoPerception) -> tuple[DemoAction, list[tuple[DemoState, DemoState]]]:
        dt = 0.03 if self._last_time is None else min(max(p.time - self._last_time, 0.0), 0.1)
        self._last_time = p.time
        transitions: list[tuple[DemoState, DemoState]] = []

        def go(state: DemoState) -> None:
            transitions.append((self.state, state))
            self.state = state

        prm = self.params
        goal = (prm.field_half_length, 0.0)
        spot = (prm.field_half_length - prm.shoot_distance, 0.0)
        if self.state in (DemoState.MOVE_BALL, DemoState.ROTATE_BALL) and not p.holding:
            go(DemoState.CHASE_BALL)
        if self.state == DemoState.CHASE_BALL:
            if p.holding:
                go(DemoState.MOVE_BALL)
            elif p.ball is None:
                return DemoAction(w=0.5), transitions  # turn on the spot to look for it
            else:
                heading = math.atan2(p.ball[1] - p.pose.y, p.ball[0] - p.pose.x)
                dist = p.pose.distance_to(*p.ball)
                # Stop short of the ball at the holding distance, facing it.
                reach = max(dist - 0.40, 0.0)
                target = (p.pose.x + math.cos(heading) * reach, p.pose.y + math.sin(heading) * reach)
                vx, vy, w = self._goto(p, dt, target, heading, prm.max_speed)
                near = dist < prm.grab_distance and abs(wrap_angle(heading - p.pose.theta)) < math.radians(12)
                return DemoAction(vx, vy, w, ball_handle=1 if near else None), transitions
        if self.state == DemoState.MOVE_BALL:
            if p.pose.distance_to(*spot) < prm.position_tolerance:
                go(DemoState.ROTATE_BALL)
            else:
                heading = math.atan2(spot[1] - p.pose.y, spot[0] - p.pose.x)
                return DemoAction(*self._goto(p, dt, spot, heading, prm.dribble_speed)), transitions
        if self.state == DemoState.ROTATE_BALL:
            aim = math.atan2(goal[1] - p.pose.y, goal[0] - p.pose.x)
            vx, vy, w = self._goto(p, dt, (p.pose.x, p.pose.y), aim, prm.dribble_speed)
            if abs(wrap_angle(aim - p.pose.theta)) < math.radians(prm.aim_tolerance_deg) and abs(self._w) < 0.2:
                go(DemoState.KICK_BALL)
            else:
                return DemoAction(vx, vy, w), transitions
        if self.state == DemoState.KICK_BALL:
            self.kicks += 1
            go(DemoState.RESET)
            shot = (0, 1) if prm.shot == "lob" else (prm.ground_strength, -1)
            return DemoAction(shoot=shot), transitions
        if self.state == DemoState.RESET:
            home = prm.home
            if p.pose.distance_to(home[0], home[1]) < prm.position_tolerance and \
                    abs(wrap_angle(home[2] - p.pose.theta)) < math.radians(5):
                go(DemoState.HOME)
            else:
                return DemoAction(*self._goto(p, dt, home[:2], home[2], prm.max_speed)), transitions
        self._velocity, self._w = (0.0, 0.0), 0.0
        return DemoAction(), transitions

    def kick_failed(self) -> None:
        """The Shoot service said the ball was not kicked: chase it again."""
        self.state = DemoState.CHASE_BALL

"""The single-robot demo behaviour of chapter 5.2 (Fig. 17), as a pure state machine.

Requires: the field, and each cycle the robot's percepts (``RobotView``: own pose and ball, team
frame, from OmniVisionInfo; ``robot.holding``: whether it holds the ball). Provides:
``DemoBehaviour.step`` returning a ``RobotCommand`` (body-frame velocity, an optional BallHandle
request, an optional kick) and the state transitions it made. States:
CHASE_BALL -> DRIBBLE_BALL (MOVE_BALL, ROTATE_BALL) -> KICK_BALL -> RESET -> HOME.
Motion follows trapezoidal speed profiles (``DemoParams``: 3 m/s, 2 m/s^2,
120 deg/s, 120 deg/s^2 by default).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

from nubot_common.commands import BodyVelocity, KickCommand, KickKind, RobotCommand
from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D, rotate, wrap_angle
from nubot_common.params import require_positive
from nubot_common.percepts import RobotView


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
    home: tuple[float, float, float] = (-2.0, 0.0, 0.0)  # x [m], y [m], theta [rad], team frame

    def __post_init__(self) -> None:
        if self.shot not in ("lob", "ground"):
            raise ValueError(f"shot must be 'lob' or 'ground', got {self.shot!r}")
        require_positive(self, "max_speed", "max_accel", "max_rot_speed_deg", "max_rot_accel_deg", "dribble_speed")


class DemoBehaviour:
    def __init__(self, params: DemoParams, field: FieldGeometry):
        self.params = params
        self.field = field
        self.state = DemoState.CHASE_BALL
        self._velocity = (0.0, 0.0)  # last commanded world velocity [m/s]
        self._w = 0.0
        self._last_time: float | None = None
        self.kicks = 0

    def _goto(self, me: Pose2D, dt: float, target: tuple[float, float], heading: float,
              speed_limit: float) -> BodyVelocity:
        """Trapezoidal move towards ``target`` turning to ``heading``; returns a body-frame command."""
        prm = self.params
        dx, dy = target[0] - me.x, target[1] - me.y
        dist = math.hypot(dx, dy)
        speed = min(speed_limit, math.sqrt(2.0 * prm.max_accel * max(dist - 0.02, 0.0)))
        want = (dx / dist * speed, dy / dist * speed) if dist > 1e-6 else (0.0, 0.0)
        dvx, dvy = want[0] - self._velocity[0], want[1] - self._velocity[1]
        dv = math.hypot(dvx, dvy)
        if dv > prm.max_accel * dt:
            dvx, dvy = dvx / dv * prm.max_accel * dt, dvy / dv * prm.max_accel * dt
        self._velocity = (self._velocity[0] + dvx, self._velocity[1] + dvy)
        err = wrap_angle(heading - me.theta)
        w_max, a_max = math.radians(prm.max_rot_speed_deg), math.radians(prm.max_rot_accel_deg)
        w_want = math.copysign(min(w_max, math.sqrt(2.0 * a_max * abs(err)), 4.0 * abs(err)), err)
        self._w += max(-a_max * dt, min(a_max * dt, w_want - self._w))
        bx, by = rotate(self._velocity[0], self._velocity[1], -me.theta)
        return BodyVelocity(bx, by, self._w)

    def step(self, view: RobotView) -> tuple[RobotCommand, list[tuple[DemoState, DemoState]]]:
        """One cycle on the percepts of ``view`` (taken at ``view.stamp`` [s])."""
        dt = 0.03 if self._last_time is None else min(max(view.stamp - self._last_time, 0.0), 0.1)
        self._last_time = view.stamp
        me, holding = view.robot.pose, view.robot.holding
        ball = view.ball.position if view.ball is not None else None
        transitions: list[tuple[DemoState, DemoState]] = []

        def go(state: DemoState) -> None:
            transitions.append((self.state, state))
            self.state = state

        prm = self.params
        goal = (self.field.half_length, 0.0)
        spot = (self.field.half_length - prm.shoot_distance, 0.0)
        if self.state in (DemoState.MOVE_BALL, DemoState.ROTATE_BALL) and not holding:
            go(DemoState.CHASE_BALL)
        if self.state == DemoState.CHASE_BALL:
            if holding:
                go(DemoState.MOVE_BALL)
            elif ball is None:
                return RobotCommand(BodyVelocity(w=0.5)), transitions  # turn on the spot to look for it
            else:
                heading = math.atan2(ball[1] - me.y, ball[0] - me.x)
                dist = me.distance_to(*ball)
                # Stop short of the ball at the holding distance, facing it.
                reach = max(dist - 0.40, 0.0)
                target = (me.x + math.cos(heading) * reach, me.y + math.sin(heading) * reach)
                # No faster at the ball than the ball handler keeps it (dribble_speed), braking for it in time.
                arrive = math.sqrt(prm.dribble_speed ** 2 + 2.0 * prm.max_accel * max(dist - prm.grab_distance, 0.0))
                velocity = self._goto(me, dt, target, heading, min(prm.max_speed, arrive))
                near = dist < prm.grab_distance and abs(wrap_angle(heading - me.theta)) < math.radians(12)
                return RobotCommand(velocity, dribble=near, ball_handle=1 if near else None), transitions
        if self.state == DemoState.MOVE_BALL:
            if me.distance_to(*spot) < prm.position_tolerance:
                go(DemoState.ROTATE_BALL)
            else:
                heading = math.atan2(spot[1] - me.y, spot[0] - me.x)
                # Turn towards the spot before going there: the ball handler keeps the ball only at a low speed
                # sideways (the simulator's hold_sideways_speed).
                facing = max(0.0, math.cos(wrap_angle(heading - me.theta))) ** 4
                return RobotCommand(self._goto(me, dt, spot, heading, prm.dribble_speed * facing), dribble=True), \
                    transitions
        if self.state == DemoState.ROTATE_BALL:
            aim = math.atan2(goal[1] - me.y, goal[0] - me.x)
            velocity = self._goto(me, dt, (me.x, me.y), aim, prm.dribble_speed)
            if abs(wrap_angle(aim - me.theta)) < math.radians(prm.aim_tolerance_deg) and abs(self._w) < 0.2:
                go(DemoState.KICK_BALL)
            else:
                return RobotCommand(velocity, dribble=True), transitions
        if self.state == DemoState.KICK_BALL:
            self.kicks += 1
            go(DemoState.RESET)
            lob = prm.shot == "lob"
            shot = KickCommand(KickKind.LOB, 0) if lob else KickCommand(KickKind.GROUND, prm.ground_strength)
            return RobotCommand(kick=shot), transitions
        if self.state == DemoState.RESET:
            home = prm.home
            if me.distance_to(home[0], home[1]) < prm.position_tolerance and \
                    abs(wrap_angle(home[2] - me.theta)) < math.radians(5):
                go(DemoState.HOME)
            else:
                return RobotCommand(self._goto(me, dt, home[:2], home[2], prm.max_speed)), transitions
        self._velocity, self._w = (0.0, 0.0), 0.0
        return RobotCommand(), transitions

    def kick_failed(self) -> None:
        """The Shoot service said the ball was not kicked: chase it again."""
        self.state = DemoState.CHASE_BALL

"""The model plugin's rules, as pure functions (chapter 5.2 and Table 3).

Provides: ``clamp_command`` (body-frame velocity limits, NaN/inf rejected), ``limit_drive`` (the
base's acceleration and braking), ``dribble_condition``, ``held_ball_position``, ``held_ball_velocity``,
``grip_holds`` (whether the ball handler keeps the ball at a body velocity; these five compiled, the physics world
uses them every step), ``handler_params``, ``ground_pass_velocity``, ``lob_velocity``
(its flight: ``nubot_common.ball_flight``) and ``spread_kick`` (a kick's scatter). Inputs and outputs are
world-frame, SI units, unless a name says body.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from nubot_common.commands import BodyVelocity
from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D
from nubot_common.kernels import load_kernels
from sim_visual import SimVisualError
from sim_visual.params import PluginParams

if TYPE_CHECKING:
    from sim_visual import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("sim_visual")


def clamp_command(vx: float, vy: float, w: float, params: PluginParams) -> tuple[BodyVelocity, bool]:
    """Limit a command to the robot's speeds; return it and whether it had to be clamped.

    Raises ``SimVisualError`` for NaN or infinite components, which are never applied.
    """
    if not all(math.isfinite(v) for v in (vx, vy, w)):
        raise SimVisualError(f"velocity command must be finite, got Vx={vx} Vy={vy} w={w}")
    clamped = False
    speed = math.hypot(vx, vy)
    if speed > params.max_linear_speed:
        scale = params.max_linear_speed / speed
        vx, vy, clamped = vx * scale, vy * scale, True
    if abs(w) > params.max_angular_speed:
        w, clamped = math.copysign(params.max_angular_speed, w), True
    return BodyVelocity(vx, vy, w), clamped


def limit_drive(current: tuple[float, float, float], wanted: tuple[float, float, float], dt: float,
                params: PluginParams) -> tuple[float, float, float]:
    """The base's velocity (vx, vy [m/s], world frame, w [rad/s]) one step of ``dt`` [s] after ``current`` on its way
    to ``wanted``: the linear change at most ``max_linear_brake * dt`` while the speed falls, else
    ``max_linear_accel * dt``; the turn rate's change at most ``max_angular_accel * dt`` (compiled:
    ``sim_visual/physics.hpp``, which drives every robot's base in a step with it, ``PhysicsWorld.drive_robots``)."""
    return _kernels.limit_drive(current, wanted, dt, *drive_limits(params))


def drive_limits(params: PluginParams) -> tuple[float, float, float]:
    """The base's limits as ``limit_drive`` takes them: linear acceleration and braking, angular acceleration."""
    return params.max_linear_accel, params.max_linear_brake, params.max_angular_accel


def grip_holds(vx: float, vy: float, w: float, params: PluginParams) -> bool:
    """Whether the ball handler keeps the ball while the robot moves at body velocity (vx ahead, vy left [m/s],
    w [rad/s]) (compiled: ``sim_visual/physics.hpp``, which checks the holder's grip every step with it)."""
    return _kernels.grip_holds(vx, vy, w, params.hold_forward_speed, params.hold_backward_speed,
                               params.hold_sideways_speed, params.hold_turn_rate)


def spread_kick(velocity: tuple[float, float, float], params: PluginParams,
                rng: np.random.Generator) -> tuple[float, float, float]:
    """A kick as it leaves the kicker: its horizontal direction turned by a normal draw of ``kick_direction_std_deg``,
    its speed scaled by one of ``kick_speed_std`` (two draws from ``rng``, always, so the generator's sequence does
    not depend on the parameters)."""
    turn = math.radians(params.kick_direction_std_deg) * float(rng.standard_normal())
    scale = max(0.0, 1.0 + params.kick_speed_std * float(rng.standard_normal()))
    vx, vy, vz = velocity
    c, s = math.cos(turn), math.sin(turn)
    return scale * (c * vx - s * vy), scale * (s * vx + c * vy), scale * vz


def dribble_condition(robot: Pose2D, ball_x: float, ball_y: float, ball_z: float,
                      ball_radius: float, params: PluginParams) -> bool:
    """True when the ball is near enough (``dribble_distance``), low enough (its centre at most two radii up) and in
    front enough (within ``dribble_half_angle`` of the robot's front) to be held (compiled, as ``grip_holds``)."""
    return _kernels.dribble_condition(robot.x, robot.y, robot.theta, ball_x, ball_y, ball_z, ball_radius,
                                      params.dribble_distance, params.dribble_half_angle)


def held_ball_position(robot: Pose2D, params: PluginParams) -> tuple[float, float]:
    """Where a held ball sits: ``hold_distance`` ahead of the robot centre (method (a); compiled, as ``grip_holds``)."""
    x, y, _, _ = _kernels.held_ball(robot.x, robot.y, robot.theta, 0.0, 0.0, 0.0, params.hold_distance)
    return x, y


def held_ball_velocity(robot: Pose2D, vx: float, vy: float, w: float, params: PluginParams) -> tuple[float, float]:
    """World velocity of the held ball: the robot's velocity at the holding point (compiled, as ``grip_holds``)."""
    _, _, bvx, bvy = _kernels.held_ball(robot.x, robot.y, robot.theta, vx, vy, w, params.hold_distance)
    return bvx, bvy


def handler_params(params: PluginParams, ball_radius: float) -> tuple[float, ...]:
    """The ball handler's parameters as ``PhysicsWorld.set_ball_handler`` takes them."""
    return (params.dribble_distance, params.dribble_half_angle, params.hold_distance, params.hold_forward_speed,
            params.hold_backward_speed, params.hold_sideways_speed, params.hold_turn_rate, params.hold_slip_time,
            params.kick_recapture_delay, ball_radius)


def ground_pass_velocity(heading: float, strength: float, params: PluginParams) -> tuple[float, float, float]:
    """Initial ball velocity of a ground pass: ``strength`` [m/s] along the heading, in the field plane."""
    if not math.isfinite(strength) or strength <= 0.0:
        raise SimVisualError(f"ground pass strength must be a positive speed in m/s, got {strength}")
    speed = min(float(strength), params.kick_max_speed)
    return speed * math.cos(heading), speed * math.sin(heading), 0.0


def lob_velocity(robot: Pose2D, ball_x: float, ball_y: float, attack: int, field: FieldGeometry,
                 ball_radius: float, gravity: float, params: PluginParams) -> tuple[float, float, float]:
    """Initial ball velocity of a lob shot along the robot heading, aimed to end in the attacked goal.

    The ball flies along the heading to the goal line at ``attack * half_length``
    and crosses it with its top ``lob_bar_margin`` below the bar. A robot that
    does not face that goal line lobs ``lob_default_distance`` ahead, landing
    on the ground.
    """
    g = -gravity
    cx, cy = math.cos(robot.theta), math.sin(robot.theta)
    line_x = attack * field.half_length
    towards = cx * attack > 1e-3
    if towards:
        distance = (line_x - ball_x) / cx
        target_height = field.goal_height - params.lob_bar_margin - ball_radius
    if not towards or distance <= 0.5:
        distance, target_height = params.lob_default_distance, ball_radius
    horizontal = max(params.lob_horizontal_speed, distance / params.lob_max_flight_time)
    flight = distance / horizontal
    vz = (target_height - ball_radius + 0.5 * g * flight * flight) / flight
    speed = math.hypot(horizontal, vz)
    if speed > params.lob_max_speed:
        scale = params.lob_max_speed / speed  # the kicker's limit wins; the lob falls short
        horizontal, vz = horizontal * scale, vz * scale
    return horizontal * cx, horizontal * cy, vz

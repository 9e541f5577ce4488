"""The physics layer: an ODE world with the field, two goals, the ball and robot cylinders.

Requires: the compiled core ``sim_visual._kernels.Physics`` (C++ on Debian's libode), which does the per-step work.
Provides: ``PhysicsWorld`` (add/remove robots, drive them, read and set model states, ``step``) and the plain state
records ``RobotState`` and ``BallState`` (world frame, SI units). Robots are driven
kinematically in the plane (their body velocity is set before every step, as
Gazebo's SetLinearVel/SetAngularVel) but collide dynamically; driving a robot also
sets it back upright on the carpet where the last step's contacts tipped or lifted
it. The ball is a free sphere with rolling resistance. Contact properties come
from one surface table.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from nubot_common.commands import BodyVelocity
from nubot_common.field import FieldGeometry
from nubot_common.kernels import load_kernels
from nubot_common.records import fast_init
from nubot_common.world_description import BallBody, RobotBody
from sim_visual import SimVisualError

if TYPE_CHECKING:  # params imports the sensors, which use this module's states
    from sim_visual import _kernels  # its interface: _kernels.pyi
    from sim_visual.params import PhysicsParams
else:
    _kernels = load_kernels("sim_visual")

_WALL_HEIGHT = 3.0  # arena walls keep lobs inside [m]
_NET_THICKNESS = 0.02  # [m]
_BOUNCE_MIN_SPEED = 0.3  # slower impacts do not bounce [m/s]
_ON_GROUND_TOLERANCE = 0.01  # [m]

# ODE collision categories: ODE offers a pair to the near callback only when one geom's category is in the
# other's collide mask, so the pairs that never make contacts (static geometry with itself, robots gliding above
# the carpet) are dropped inside ODE instead of in a Python callback every step.
_GROUND, _STATIC, _ROBOT, _BALL = 1, 2, 4, 8
_COLLIDES = {"ground": _BALL, "post": _ROBOT | _BALL, "net": _ROBOT | _BALL, "wall": _ROBOT | _BALL,
             "robot": _STATIC | _ROBOT | _BALL, "ball": _GROUND | _STATIC | _ROBOT}
_OTHER, _BALL_ROBOT, _BALL_NET = 0, 1, 2  # contacts the step reports: the ball touched by a robot, in a net
_CATEGORY = {"ground": _GROUND, "post": _STATIC, "net": _STATIC, "wall": _STATIC, "robot": _ROBOT, "ball": _BALL}
_KINDS = tuple(_CATEGORY)  # their numbers in the compiled core (sim_visual/physics.hpp)


def _simulated_ball_mass(ball: BallBody) -> float:
    """The ball's mass in this world [kg]: a sphere of ``ball.mass`` kg per cubic metre, 2.3 g for the MSL ball, as
    it has been since the world was built on pyode, whose ``Mass.setSphereTotal(mass, radius)`` set a density."""
    return (4.0 / 3.0) * math.pi * ball.radius * ball.radius * ball.radius * ball.mass


@fast_init
@dataclass(frozen=True)
class RobotState:
    """A robot in the world frame: position [m], heading [rad], velocity [m/s], [rad/s]."""

    x: float
    y: float
    theta: float
    vx: float
    vy: float
    w: float


@fast_init
@dataclass(frozen=True)
class BallState:
    """The ball centre [m] and velocity [m/s] in the world frame, spin [rad/s]."""

    x: float
    y: float
    z: float
    vx: float
    vy: float
    vz: float
    wx: float = 0.0
    wy: float = 0.0
    wz: float = 0.0


class PhysicsWorld:
    """ODE world of one MSL field. Not thread-safe: one caller steps and edits it. Drive every robot
    (``drive_robot``) before each ``step``. The field and its surfaces are described here; the per-step work (driving,
    contacts, the step, the net and the rolling ball) is the compiled core's (``sim_visual._kernels.Physics``)."""

    def __init__(self, field: FieldGeometry, physics: PhysicsParams, robot: RobotBody, ball: BallBody):
        self.field = field
        self.physics = physics
        self.robot_body = robot
        self.ball_body = ball
        self._core = _kernels.Physics(physics.gravity, 0.2, 1e-5, _simulated_ball_mass(ball), ball.radius,
                                      ball.rolling_friction * -physics.gravity, ball.net_restitution,
                                      _BOUNCE_MIN_SPEED, _ON_GROUND_TOLERANCE)
        self._core.set_goal_line(field.half_length)  # advance tells when the ball may lie in a goal
        self.drive_params: tuple[float, tuple[float, float, float], tuple[int, float, float, float]] | None = None
        self._robots: dict[str, int] = {}  # name: the core's handle
        self._names: dict[int, str] = {}
        # States read since the last change, by robot name: a step, an observation of every robot and the
        # controllers ask for the same states many times between two changes.
        self._robot_states: dict[str, RobotState] = {}
        self._ball_state: BallState | None = None
        self._build_field()
        for (a, b), (mu, bounce, pair) in self._surface_table().items():
            self._core.set_surface(_KINDS.index(a), _KINDS.index(b), _kernels.Surface(mu, bounce, pair))
        self._core.add_ball(_CATEGORY["ball"], _COLLIDES["ball"])
        self.set_ball_state(BallState(0.0, 0.0, ball.radius, 0.0, 0.0, 0.0))

    # --- construction -------------------------------------------------------------
    def _bits(self, kind: str) -> tuple[int, int, int]:
        return _KINDS.index(kind), _CATEGORY[kind], _COLLIDES[kind]

    def _static_box(self, kind: str, size: tuple[float, float, float], centre: tuple[float, float, float]) -> None:
        self._core.add_box(*self._bits(kind), size, centre)

    def _build_field(self) -> None:
        f = self.field
        self._core.add_plane(*self._bits("ground"))
        for side in (-1, 1):
            for px, py in f.goal_posts(side):
                self._core.add_cylinder(*self._bits("post"), f.post_radius, f.goal_height,
                                        (px, py, f.goal_height / 2.0))
            outer_y = f.goal_outer_half_width
            bar_x = side * (f.half_length + f.post_radius)
            self._static_box("post", (2 * f.post_radius, 2 * outer_y, 2 * f.post_radius),
                             (bar_x, 0.0, f.goal_height + f.post_radius))
            back_x = side * (f.half_length + f.goal_depth + _NET_THICKNESS / 2.0)
            self._static_box("net", (_NET_THICKNESS, 2 * outer_y, f.goal_height), (back_x, 0.0, f.goal_height / 2.0))
            mid_x = side * (f.half_length + f.goal_depth / 2.0)
            for sy in (-1, 1):
                self._static_box("net", (f.goal_depth, _NET_THICKNESS, f.goal_height),
                                 (mid_x, sy * (outer_y + _NET_THICKNESS / 2.0), f.goal_height / 2.0))
            self._static_box("net", (f.goal_depth, 2 * outer_y, _NET_THICKNESS),
                             (mid_x, 0.0, f.goal_height + _NET_THICKNESS / 2.0))
        ax, ay = f.half_length + f.border, f.half_width + f.border
        for sx in (-1, 1):
            self._static_box("wall", (0.2, 2 * ay + 0.4, _WALL_HEIGHT), (sx * (ax + 0.1), 0.0, _WALL_HEIGHT / 2))
        for sy in (-1, 1):
            self._static_box("wall", (2 * ax + 0.4, 0.2, _WALL_HEIGHT), (0.0, sy * (ay + 0.1), _WALL_HEIGHT / 2))
        # Where a goal's back net stands short of the wall by less than a robot's width, the gap is filled (net, as
        # what is behind a net to a ball that meets it): a robot driven in wedged between the nets' corner and the wall.
        back = f.half_length + f.goal_depth + _NET_THICKNESS
        gap = ax - back
        if 0.0 < gap < 2.0 * self.robot_body.radius:
            for side in (-1, 1):
                self._static_box("net", (gap, 2 * (f.goal_outer_half_width + _NET_THICKNESS), f.goal_height),
                                 (side * (back + gap / 2.0), 0.0, f.goal_height / 2.0))

    # --- robots ---------------------------------------------------------------------
    @property
    def robot_names(self) -> list[str]:
        return list(self._robots)

    def add_robot(self, name: str, x: float, y: float, theta: float) -> None:
        if name in self._robots:
            raise SimVisualError(f"a model named {name!r} already exists")
        rb = self.robot_body
        handle = self._core.add_robot(rb.mass, rb.inertia_zz, rb.radius, rb.height, _CATEGORY["robot"],
                                      _COLLIDES["robot"])
        self._robots[name] = handle
        self._names[handle] = name
        self.set_robot_state(name, RobotState(x, y, theta, 0.0, 0.0, 0.0))

    def remove_robot(self, name: str) -> None:
        handle = self._robot(name)
        self._core.remove_robot(handle)
        del self._robots[name], self._names[handle]
        self._robot_states.pop(name, None)

    def _robot(self, name: str) -> int:
        try:
            return self._robots[name]
        except KeyError:
            raise SimVisualError(f"no robot named {name!r}; robots: {', '.join(self._robots) or 'none'}") from None

    def robot_state(self, name: str) -> RobotState:
        state = self._robot_states.get(name)
        if state is None:
            state = RobotState(*self._core.robot_state(self._robot(name)))
            self._robot_states[name] = state
        return state

    def robot_states(self) -> list[RobotState]:
        """Every robot's state now, in the order of ``robot_names`` (read in one call)."""
        cache, names = self._robot_states, self._names
        if len(cache) != len(self._robots):
            for handle, row in self._core.robot_states():
                name = names[handle]
                if name not in cache:
                    cache[name] = RobotState(*row)
        return [cache[name] for name in self._robots]

    def set_robot_state(self, name: str, state: RobotState) -> None:
        handle = self._robot(name)
        self._robot_states.pop(name, None)
        self._core.set_robot_state(handle, (state.x, state.y, state.theta, state.vx, state.vy, state.w))

    def heading(self, name: str) -> float:
        """A robot's heading now [rad] (read from ODE, not cached)."""
        return self._core.heading(self._robot(name))

    def drive_robot(self, name: str, vx: float, vy: float, w: float, world_frame: bool = False) -> None:
        """Drive a robot for the next step with a velocity in its own frame [m/s] (x ahead; with ``world_frame``,
        in the world's) and yaw rate [rad/s], as its wheels do (turned into the world frame by its heading now),
        upright on the carpet: a robot a contact tipped or lifted is set back upright on it."""
        handle = self._robot(name)
        self._robot_states.pop(name, None)
        self._core.drive(handle, vx, vy, w, world_frame)

    # --- the robots' bases ---------------------------------------------------------------
    def set_command(self, name: str, command: BodyVelocity, time: float) -> None:
        """Robot ``name``'s base velocity command (body frame), given at ``time`` [s]."""
        self._core.set_command(self._robot(name), command.vx, command.vy, command.w, time)

    def command(self, name: str) -> BodyVelocity:
        """Robot ``name``'s last base velocity command (body frame); at rest until it gets one."""
        return BodyVelocity(*self._core.command(self._robot(name)))

    def set_driven_by_wheels(self, name: str) -> None:
        """From now on robot ``name``'s wheels drive its base: a drive model of their own gives their dynamics, so
        its commands reach the base without the base's limits."""
        self._core.set_by_wheels(self._robot(name), True)

    def base_drive(self, name: str) -> tuple[float, float, float]:
        """What robot ``name``'s base gives now: vx, vy [m/s] (world frame), w [rad/s]."""
        vx, vy, w = self._core.drive_of(self._robot(name))
        return vx, vy, w

    def set_base_drive(self, name: str, vx: float, vy: float, w: float) -> None:
        self._core.set_drive(self._robot(name), (vx, vy, w))

    def stuck(self, name: str) -> bool:
        """Whether robot ``name`` has moved at less than half its command for the stuck time (``drive_robots``)."""
        return self._core.stuck(self._robot(name))

    def reset_base(self, name: str) -> None:
        """Robot ``name``'s base as a new one: no command, at rest, not driven by wheels, not stuck."""
        self._core.reset_base(self._robot(name))

    # --- the ball handler -------------------------------------------------------------
    def set_ball_handler(self, params: tuple[float, ...]) -> None:
        """The ball handler's parameters (``rules.handler_params``) for the calls below."""
        self._core.set_handler(*params)

    def set_dribbling(self, name: str, on: bool) -> None:
        self._core.set_dribbling(self._robot(name), on)

    def dribbling(self, name: str) -> bool:
        return self._core.dribbling(self._robot(name))

    def set_no_capture_until(self, name: str, time: float) -> None:
        """Robot ``name`` cannot take the ball before ``time`` [s] (after a kick or a slip)."""
        self._core.set_no_capture_until(self._robot(name), time)

    def grip_slips(self, holder: str, dt: float, time: float) -> bool:
        """The holder one step of ``dt`` [s] on at ``time`` [s]: whether its grip lost the ball (its base moved
        faster than ``rules.grip_holds`` keeps it for ``hold_slip_time``); then it cannot take the ball again for
        ``kick_recapture_delay``."""
        return self._core.grip_slips(self._robot(holder), dt, time)

    def can_capture(self, name: str, time: float) -> bool:
        """Whether robot ``name`` can take the ball now: its recapture delay over, the ball in reach
        (``rules.dribble_condition``)."""
        return self._core.can_capture(self._robot(name), time)

    def first_capture(self, time: float) -> str | None:
        """The first robot (in the order they were added) whose ball handler is on and can take the ball now."""
        handle = self._core.first_capture(time)
        return None if handle < 0 else self._names[handle]

    def carry_ball(self, holder: str) -> None:
        """The ball where ``holder`` holds it (``rules.held_ball_position``), moving with it, on the carpet."""
        self._ball_state = None
        self._core.carry_ball(self._robot(holder))

    def drive_robots(self, dt: float, time: float, steps: int, timeout: float, limits: tuple[float, float, float],
                     stuck: tuple[int, float, float, float]) -> None:
        """Every robot's base one step of ``dt`` [s] on at ``time`` [s] (``steps`` steps made before), in one
        compiled call: its command (a stop once older than ``timeout`` [s]; 0: never), the stuck detection every
        ``stuck[0]`` steps (a command of at least ``stuck[1]`` m/s, the ground velocity low-passed over ``stuck[2]``
        s, slow for ``stuck[3]`` s), the command turned into the world frame by the heading now and reached from
        what the base gives within ``limits`` (linear acceleration and braking [m/s^2], angular acceleration
        [rad/s^2]; ``rules.limit_drive``) unless the wheels drive it, then driven (``drive_robot``)."""
        self._robot_states.clear()
        self._core.drive_robots(dt, time, steps, timeout, *stuck, *limits)

    # --- ball -------------------------------------------------------------------------
    def ball_state(self) -> BallState:
        if self._ball_state is None:
            self._ball_state = BallState(*self._core.ball_state())
        return self._ball_state

    def set_ball_state(self, state: BallState) -> None:
        """Put the ball there (no lower than resting on the carpet), level."""
        self._ball_state = None
        self._core.set_ball_state((state.x, state.y, state.z, state.vx, state.vy, state.vz, state.wx, state.wy,
                                   state.wz))

    def ball_x(self) -> float:
        """The ball centre's x [m] (without making its whole state)."""
        state = self._ball_state
        return state.x if state is not None else self._core.ball_x()

    def ball_on_ground(self) -> bool:
        return self._core.ball_on_ground()

    def set_ball_collides_with(self, name: str | None) -> None:
        """Ignore ball contacts with the robot ``name`` (the one holding it), or none."""
        self._core.set_ball_holder(-1 if name is None else self._robot(name))

    def bodies(self) -> dict[str | None, tuple[float, ...]]:
        """Every body as ODE holds it, by robot name (the ball: None): position [m], orientation (w, x, y, z), linear
        [m/s] and angular [rad/s] velocity, 13 numbers."""
        out: dict[str | None, tuple[float, ...]] = {name: tuple(self._core.body(h)) for name, h in self._robots.items()}
        out[None] = tuple(self._core.body(-1))
        return out

    def set_bodies(self, bodies: dict[str | None, tuple[float, ...]]) -> None:
        """Put bodies back exactly as ``bodies`` gave them (orientation and height included)."""
        for name, row in bodies.items():
            self._core.set_body(-1 if name is None else self._robot(name), row)
        self._robot_states.clear()
        self._ball_state = None

    def pairs_offered(self) -> dict[frozenset[str], int]:
        """How often each pair of kinds of geometry reached the contact callback since the world was made."""
        counts: dict[frozenset[str], int] = {}
        for a, row in enumerate(self._core.pairs_offered()):
            for b, n in enumerate(row):
                if n:
                    key = frozenset((_KINDS[a], _KINDS[b]))
                    counts[key] = counts.get(key, 0) + n
        return counts

    # --- stepping -----------------------------------------------------------------------
    def step(self, dt: float) -> set[str]:
        """Advance the world by ``dt`` seconds; return the robots that touched the ball."""
        self._robot_states.clear()
        self._ball_state = None
        return {self._names[h] for h in self._core.step(dt)}

    def set_drive_params(self, timeout: float, limits: tuple[float, float, float],
                         stuck: tuple[int, float, float, float]) -> None:
        """How ``advance`` drives the bases (``drive_robots``' ``timeout``, ``limits`` and ``stuck``)."""
        self._core.set_base_params(timeout, *stuck, *limits)
        self.drive_params = (timeout, limits, stuck)

    def advance(self, dt: float, time: float, steps: int,
                holder: str | None) -> tuple[set[str], bool, str | None] | None:
        """One step of the simulator's world in one compiled call, ``steps`` steps after the start at ``time`` [s]:
        ``drive_robots`` (with ``set_drive_params``' parameters), the holder's ``grip_slips`` (the ball let go when it
        slips), its ball contacts ignored, ``step``, then with no holder the ``first_capture`` at the time after the
        step, and the holder's ``carry_ball``. Returns the robots that touched the ball in the step, whether the
        holder's grip lost it, and the robot that took it (None: none); or None alone when none did and the ball
        lies short of both goal lines (|x| below the field's half length): the usual step."""
        self._robot_states.clear()
        self._ball_state = None
        happened = self._core.advance(dt, time, steps, -1 if holder is None else self._robot(holder))
        if happened is None:
            return None
        touched, slipped, captured = happened
        names = self._names
        return {names[h] for h in touched}, slipped, None if captured < 0 else names[captured]

    @property
    def step_seconds(self) -> float:
        """The wall time [s] ODE's own part of the steps took since the world was made (``step``, also inside
        ``advance``)."""
        return self._core.step_seconds()

    @property
    def solver_errors(self) -> int:
        """How often ODE's solver reported "LCP internal error" in this world's steps since it was made (it could not
        solve a step's contacts exactly; the message goes to stderr as ODE prints it, and the step goes on)."""
        return self._core.solver_errors()

    def _surface_table(self) -> dict[tuple[str, str], tuple[float, float, int]]:
        """By the kinds of two geometries (both orders): the friction coefficient and restitution of their
        contacts (0: ODE's 0.1 at any speed), and whether they are the ball and a robot or the ball and a net. The
        pairs that never make contacts are left out: static geometry with itself, robots gliding above the carpet
        (the collision categories drop them inside ODE already). A ball in a net keeps ``net_restitution`` of its
        horizontal motion per step of contact (the net gives way and swallows a shot; the ball drops down it); a ball
        on the carpet slows by ``rolling_friction`` g."""
        ball, robot = self.ball_body, self.robot_body
        table = {}
        for a in _CATEGORY:
            for b in _CATEGORY:
                pair = {a, b}
                if "ground" in pair and "robot" in pair or "ball" not in pair and "robot" not in pair:
                    continue
                if pair == {"ball", "ground"}:
                    table[a, b] = ball.ground_friction, ball.restitution, _OTHER
                elif pair == {"ball", "net"}:
                    table[a, b] = 1.0, 0.0, _BALL_NET
                elif "ball" in pair:  # robots, posts, walls
                    table[a, b] = robot.friction, ball.body_restitution, _BALL_ROBOT if "robot" in pair else _OTHER
                else:  # robot against robot, post, net or wall
                    table[a, b] = robot.friction, 0.0, _OTHER
        return table



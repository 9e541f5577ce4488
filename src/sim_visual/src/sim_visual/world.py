"""The physics layer: an ODE world with the field, two goals, the ball and robot cylinders.

Requires: ``python3-pyode``. Provides: ``PhysicsWorld`` (add/remove robots, drive
them, read and set model states, ``step``) and the plain state records
``RobotState`` and ``BallState`` (world frame, SI units). Robots are driven
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

import ode

from nubot_common.field import FieldGeometry
from nubot_common.geometry import quaternion_to_yaw, yaw_to_quaternion
from nubot_common.world_description import BallBody, RobotBody
from sim_visual import SimVisualError

if TYPE_CHECKING:  # params imports the sensors, which use this module's states
    from sim_visual.params import PhysicsParams

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


@dataclass(frozen=True)
class RobotState:
    """A robot in the world frame: position [m], heading [rad], velocity [m/s], [rad/s]."""

    x: float
    y: float
    theta: float
    vx: float
    vy: float
    w: float


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
    (``drive_robot``) before each ``step``."""

    def __init__(self, field: FieldGeometry, physics: PhysicsParams, robot: RobotBody, ball: BallBody):
        self.field = field
        self.physics = physics
        self.robot_body = robot
        self.ball_body = ball
        self._world = ode.World()
        self._world.setGravity((0.0, 0.0, physics.gravity))
        self._world.setERP(0.2)
        self._world.setCFM(1e-5)
        self._space = ode.HashSpace()
        self._contacts = ode.JointGroup()
        self._kind: dict[ode.GeomObject, str] = {}
        self._robots: dict[str, tuple[ode.Body, ode.GeomObject]] = {}
        self._robot_of_geom: dict[ode.GeomObject, str] = {}
        self._touched: set[str] = set()
        self._ball_holder: str | None = None
        self._ball_in_net = False
        self._static: list[ode.GeomObject] = []
        self._surfaces = self._surface_table()
        # States read since the last change, by robot name: a step, an observation of every robot and the
        # controllers ask for the same states many times between two changes.
        self._robot_states: dict[str, RobotState] = {}
        self._ball_state: BallState | None = None
        self._build_field()
        self._ball = ode.Body(self._world)
        mass = ode.Mass()
        mass.setSphereTotal(ball.mass, ball.radius)
        self._ball.setMass(mass)
        self._ball_geom = ode.GeomSphere(self._space, ball.radius)
        self._ball_geom.setBody(self._ball)
        self._classify(self._ball_geom, "ball")
        self.set_ball_state(BallState(0.0, 0.0, ball.radius, 0.0, 0.0, 0.0))

    # --- construction -------------------------------------------------------------
    def _classify(self, geom: ode.GeomObject, kind: str) -> None:
        self._kind[geom] = kind
        geom.setCategoryBits(_CATEGORY[kind])
        geom.setCollideBits(_COLLIDES[kind])

    def _static_box(self, kind: str, size: tuple[float, float, float], centre: tuple[float, float, float]) -> None:
        geom = ode.GeomBox(self._space, size)
        geom.setPosition(centre)
        self._classify(geom, kind)
        self._static.append(geom)

    def _build_field(self) -> None:
        f = self.field
        ground = ode.GeomPlane(self._space, (0.0, 0.0, 1.0), 0.0)
        self._classify(ground, "ground")
        self._static.append(ground)
        for side in (-1, 1):
            for px, py in f.goal_posts(side):
                post = ode.GeomCylinder(self._space, f.post_radius, f.goal_height)
                post.setPosition((px, py, f.goal_height / 2.0))
                self._classify(post, "post")
                self._static.append(post)
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

    # --- robots ---------------------------------------------------------------------
    @property
    def robot_names(self) -> list[str]:
        return list(self._robots)

    def add_robot(self, name: str, x: float, y: float, theta: float) -> None:
        if name in self._robots:
            raise SimVisualError(f"a model named {name!r} already exists")
        rb = self.robot_body
        body = ode.Body(self._world)
        mass = ode.Mass()
        # Roll and pitch are set back every step (drive_robot); only I_zz matters (Table 1).
        mass.setParameters(rb.mass, 0.0, 0.0, 0.0, rb.inertia_zz, rb.inertia_zz, rb.inertia_zz, 0.0, 0.0, 0.0)
        body.setMass(mass)
        body.setGravityMode(False)
        holder = ode.GeomTransform(self._space)
        cylinder = ode.GeomCylinder(None, rb.radius, rb.height)
        holder.setGeom(cylinder)
        cylinder.setPosition((0.0, 0.0, rb.height / 2.0))
        holder.setBody(body)
        self._classify(holder, "robot")
        self._robot_of_geom[holder] = name
        self._robots[name] = (body, holder)
        self.set_robot_state(name, RobotState(x, y, theta, 0.0, 0.0, 0.0))

    def remove_robot(self, name: str) -> None:
        body, holder = self._robot(name)
        self._space.remove(holder)
        del self._kind[holder], self._robot_of_geom[holder], self._robots[name]
        self._robot_states.pop(name, None)
        body.disable()

    def _robot(self, name: str) -> tuple[ode.Body, ode.GeomObject]:
        try:
            return self._robots[name]
        except KeyError:
            raise SimVisualError(f"no robot named {name!r}; robots: {', '.join(self._robots) or 'none'}") from None

    def robot_state(self, name: str) -> RobotState:
        state = self._robot_states.get(name)
        if state is None:
            body, _ = self._robot(name)
            x, y, _z = body.getPosition()
            vx, vy, _vz = body.getLinearVel()
            state = RobotState(x, y, _yaw(body), vx, vy, body.getAngularVel()[2])
            self._robot_states[name] = state
        return state

    def set_robot_state(self, name: str, state: RobotState) -> None:
        body, _ = self._robot(name)
        self._robot_states.pop(name, None)
        body.setPosition((state.x, state.y, 0.0))
        body.setQuaternion(_wxyz(yaw_to_quaternion(state.theta)))
        body.setLinearVel((state.vx, state.vy, 0.0))
        body.setAngularVel((0.0, 0.0, state.w))

    def heading(self, name: str) -> float:
        """A robot's heading now [rad] (read from ODE, not cached)."""
        qw, qx, qy, qz = self._robot(name)[0].getQuaternion()
        return math.atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))

    def drive_robot(self, name: str, vx: float, vy: float, w: float, world_frame: bool = False) -> None:
        """Drive a robot for the next step with a velocity in its own frame [m/s] (x ahead; with ``world_frame``,
        in the world's) and yaw rate [rad/s], as its wheels do (turned into the world frame by its heading now),
        upright on the carpet."""
        body, _ = self._robot(name)
        self._robot_states.pop(name, None)
        # Every robot, every step: _yaw and rotate written out (ODE's quaternion order w, x, y, z).
        qw, qx, qy, qz = body.getQuaternion()
        yaw = math.atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
        c, s = math.cos(yaw), math.sin(yaw)
        if qx != 0.0 or qy != 0.0:  # a contact tipped it: set it upright
            body.setQuaternion((math.cos(yaw / 2.0), 0.0, 0.0, math.sin(yaw / 2.0)))
        x, y, z = body.getPosition()
        if z != 0.0:  # a contact lifted it: back on the carpet
            body.setPosition((x, y, 0.0))
        if world_frame:
            body.setLinearVel((vx, vy, 0.0))
        else:
            body.setLinearVel((c * vx - s * vy, s * vx + c * vy, 0.0))
        body.setAngularVel((0.0, 0.0, w))

    # --- ball -------------------------------------------------------------------------
    def ball_state(self) -> BallState:
        if self._ball_state is None:
            x, y, z = self._ball.getPosition()
            vx, vy, vz = self._ball.getLinearVel()
            wx, wy, wz = self._ball.getAngularVel()
            self._ball_state = BallState(x, y, z, vx, vy, vz, wx, wy, wz)
        return self._ball_state

    def set_ball_state(self, state: BallState) -> None:
        self._ball_state = None
        self._ball.setPosition((state.x, state.y, max(state.z, self.ball_body.radius)))
        self._ball.setLinearVel((state.vx, state.vy, state.vz))
        self._ball.setAngularVel((state.wx, state.wy, state.wz))
        self._ball.setQuaternion((1.0, 0.0, 0.0, 0.0))

    def ball_on_ground(self) -> bool:
        low = self._ball.getPosition()[2] <= self.ball_body.radius + _ON_GROUND_TOLERANCE
        return low and abs(self._ball.getLinearVel()[2]) < _BOUNCE_MIN_SPEED

    def set_ball_collides_with(self, name: str | None) -> None:
        """Ignore ball contacts with the robot ``name`` (the one holding it), or none."""
        self._ball_holder = name

    # --- stepping -----------------------------------------------------------------------
    def step(self, dt: float) -> set[str]:
        """Advance the world by ``dt`` seconds; return the robots that touched the ball."""
        self._touched = set()
        self._ball_in_net = False
        self._robot_states.clear()
        self._ball_state = None
        self._space.collide(None, self._near)
        self._world.step(dt)  # the exact solver: quickStep reorders constraints with a process-global RNG
        self._contacts.empty()
        if self._ball_in_net:
            self._absorb_in_net()
        self._apply_rolling_resistance(dt)
        self._ball_state = None
        return self._touched

    def _near(self, _args: object, geom_a: ode.GeomObject, geom_b: ode.GeomObject) -> None:
        kind_a, kind_b = self._kind.get(geom_a, ""), self._kind.get(geom_b, "")
        surface = self._surfaces.get((kind_a, kind_b))
        if surface is None:
            return
        mu, bounce, pair = surface
        robot = None
        if pair == _BALL_ROBOT:
            robot = self._robot_of_geom[geom_a if kind_a == "robot" else geom_b]
            if robot == self._ball_holder:
                return
        contacts = ode.collide(geom_a, geom_b)
        if not contacts:
            return
        for contact in contacts:
            contact.setMu(mu)
            if bounce > 0.0:
                contact.setBounce(bounce)
                contact.setBounceVel(_BOUNCE_MIN_SPEED)
            joint = ode.ContactJoint(self._world, self._contacts, contact)
            joint.attach(geom_a.getBody(), geom_b.getBody())
        if robot is not None:
            self._touched.add(robot)
        elif pair == _BALL_NET:
            self._ball_in_net = True

    def _surface_table(self) -> dict[tuple[str, str], tuple[float, float, int]]:
        """By the kinds of two geometries (both orders): the friction coefficient and restitution of their
        contacts, and whether they are the ball and a robot or the ball and a net. The pairs that never make
        contacts are left out: static geometry with itself, robots gliding above the carpet (the collision
        categories drop them inside ODE already)."""
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

    def _absorb_in_net(self) -> None:
        """A net gives way and swallows a shot: each step of contact keeps net_restitution of the horizontal motion.

        The vertical motion is left alone so that the ball drops down the net instead of clinging to it.
        """
        keep = self.ball_body.net_restitution
        vx, vy, vz = self._ball.getLinearVel()
        wx, wy, wz = self._ball.getAngularVel()
        self._ball.setLinearVel((vx * keep, vy * keep, vz))
        self._ball.setAngularVel((wx * keep, wy * keep, wz * keep))

    def _apply_rolling_resistance(self, dt: float) -> None:
        if not self.ball_on_ground():
            return
        vx, vy, vz = self._ball.getLinearVel()
        speed = math.hypot(vx, vy)
        decel = self.ball_body.rolling_friction * -self.physics.gravity
        if speed <= decel * dt:
            self._ball.setLinearVel((0.0, 0.0, vz))
            self._ball.setAngularVel((0.0, 0.0, 0.0))
            return
        scale = (speed - decel * dt) / speed
        wx, wy, wz = self._ball.getAngularVel()
        self._ball.setLinearVel((vx * scale, vy * scale, vz))
        self._ball.setAngularVel((wx * scale, wy * scale, wz * scale))


def _yaw(body: ode.Body) -> float:
    """A body's heading [rad] (ODE's quaternion order is w, x, y, z)."""
    w, x, y, z = body.getQuaternion()
    return quaternion_to_yaw(x, y, z, w)


def _wxyz(q_xyzw: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    x, y, z, w = q_xyzw
    return w, x, y, z

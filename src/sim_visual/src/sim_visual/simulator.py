"""The simulator: physics world plus one model plugin per robot, stepped at a fixed rate.

Requires: ``SimConfig``. Provides: ``Simulator`` with the robot interface of the
chapter (``command_velocity``, ``ball_handle``, ``shoot``), Gazebo-like world
services (``model_states``, ``set_model_state``, ``reset``, ``spawn_robot``,
``delete_robot``), ``switch_ends`` (half time), ``observe`` (noisy omni-vision frame of one robot; of many at
once: ``observe_all``; its noise-free truth: ``observe_truth``; a goalie's RGB-D ball: ``observe_ball3d``), the
robot's own sensors for omni_vision
(``camera_frame``, ``odometry``, ``inertial_heading``), for front_vision (``front_camera_frame``) and for
kinect_ball (``rgbd_frames``), and ``step`` which returns the events of that step (goals, kicks, touches,
captures, releases, the holder changing). All
randomness comes from ``SimConfig.seed``: the percepts' noise from one ``numpy.random.Generator``, the
sensors' from one of their own derived from the same seed.
Every state from outside is checked before it reaches ODE (finite, inside the arena, speeds within
the limits of ``sim_visual.params``); a refusal raises ``SimVisualError`` and changes nothing.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import astuple, dataclass, replace
from typing import TYPE_CHECKING, Protocol, TypeVar

import numpy as np

from nubot_common.commands import BodyVelocity, KickKind, RobotCommand
from nubot_common.geometry import Pose2D, rotate
from nubot_common.naming import parse_robot_name
from nubot_common.percepts import Ball3dPercept, RobotView
from nubot_common.team_frame import TeamFrame
from sim_visual import SimVisualError
from sim_visual.odometry import ImuReading, OdometryReading
from sim_visual.params import (
    MAX_BALL_HEIGHT,
    MAX_BALL_SPEED,
    MAX_ROBOTS,
    NoiseParams,
    PluginParams,
    RobotSpawn,
    SimConfig,
    require_in_arena,
)
from sim_visual.rules import (
    clamp_command,
    drive_limits,
    ground_pass_velocity,
    handler_params,
    lob_velocity,
    spread_kick,
)
from sim_visual.sensing import RobotFlags, observe, observe_all, observe_ball3d
from sim_visual.sensors import RobotSensors
from sim_visual.world import BallState, PhysicsWorld, RobotState

if TYPE_CHECKING:
    from sim_visual.omni_camera import RenderedFrame
    from sim_visual.rgbd_camera import RgbdFrame

T = TypeVar("T")
BALL3D_STREAM = 2  # the RGB-D percepts' generator: SeedSequence([seed, BALL3D_STREAM]) (the sensors' is 1)
_NO_NOISE = NoiseParams(position_std=0.0, velocity_std=0.0, self_position_std=0.0, heading_std=0.0)
_KICK_FLAG_TIME = 0.2  # RobotInfo.iskick stays true this long after a kick [s]
_STUCK_MIN_COMMAND = 0.3  # commands slower than this never count as stuck [m/s]
_STUCK_FILTER_TIME = 0.2  # time constant of the ground-speed estimate [s]
_STUCK_EVERY = 4  # physics steps between two updates of the ground-speed estimate (20 ms at 5 ms steps)
_LOB_LIFT = 0.01  # a lobbed ball starts this far above the carpet [m]


class WheelBase(Protocol):
    """A wheel layout (``nubot_common.kinematics.WheelLayout``): body velocity to rim speeds and back."""

    def wheel_speeds(self, vx: float, vy: float, w: float) -> np.ndarray: ...

    def body_velocity(self, rim_speeds: np.ndarray) -> tuple[float, float, float]: ...


@dataclass(frozen=True)
class GoalScored:
    time: float
    side: int  # +1 goal at +x, -1 goal at -x (world frame)
    ball: BallState
    last_touch: str


@dataclass(frozen=True)
class BallKicked:
    time: float
    robot: str
    kind: KickKind
    velocity: tuple[float, float, float]  # world frame [m/s]
    position: tuple[float, float, float]  # ball centre at the kick, world frame [m]


@dataclass(frozen=True)
class BallCaptured:
    time: float
    robot: str


@dataclass(frozen=True)
class BallReleased:
    time: float
    robot: str


@dataclass(frozen=True)
class BallTouched:
    """The robot that touched the ball last changed (contact, capture or kick)."""

    time: float
    robot: str
    ball: BallState


@dataclass(frozen=True)
class HolderChanged:
    """The robot whose ball handler holds the ball changed (a capture, a kick, a release, a slip)."""

    time: float
    robot: str  # "" nobody
    ball: BallState


SimEvent = GoalScored | BallKicked | BallCaptured | BallReleased | BallTouched | HolderChanged


@dataclass
class RobotPlugin:
    """Per-robot state of the model plugin; its base's (the command, what the base gives, the stuck detection) and
    its ball handler's (on or off, the recapture delay, the grip slipping) are the physics world's
    (``PhysicsWorld.drive_robots``, ``grip_slips``, ``first_capture``)."""

    spawn: RobotSpawn
    agent_id: int
    kicked_at: float = -math.inf


class Simulator:
    def __init__(self, config: SimConfig):
        self.config = config
        self.noise: NoiseParams = config.noise
        self.rng = np.random.default_rng(config.seed)
        self.ball3d_rng = np.random.default_rng(np.random.SeedSequence([config.seed, BALL3D_STREAM]))
        self.sensors = RobotSensors(config.world, config.sensors, config.seed)
        self.time = 0.0
        self.steps = 0
        self.world = PhysicsWorld(config.field, config.physics, config.robot, config.ball)
        self.plugin_params = config.plugin
        self.plugins: dict[str, RobotPlugin] = {}
        self.holder: str | None = None
        self.last_touch = ""
        self._reported_touch = ""
        self._reported_holder = ""
        self._goal_open = True  # False after a goal or a placement behind a goal line, until the ball is back in play
        for spawn in config.robots:
            self.spawn_robot(spawn)
        self._place_ball_start()

    # --- models ---------------------------------------------------------------------
    @property
    def plugin_params(self) -> PluginParams:
        return self._plugin_params

    @plugin_params.setter
    def plugin_params(self, params: PluginParams) -> None:
        self._plugin_params = params
        self.world.set_ball_handler(handler_params(params, self.config.ball.radius))
        # What stepping the bases takes (PhysicsWorld.advance): the command timeout, the limits, the stuck detection.
        self.world.set_drive_params(params.command_timeout, drive_limits(params),
                                    (_STUCK_EVERY, _STUCK_MIN_COMMAND, _STUCK_FILTER_TIME, params.stuck_time))

    @property
    def model_names(self) -> list[str]:
        return [*self.plugins, self.config.ball_name]

    def spawn_robot(self, spawn: RobotSpawn) -> None:
        if spawn.name in self.plugins or spawn.name == self.config.ball_name:
            raise SimVisualError(f"a model named {spawn.name!r} already exists")
        if len(self.plugins) >= MAX_ROBOTS:
            raise SimVisualError(f"cannot spawn {spawn.name!r}: the simulator holds at most {MAX_ROBOTS} robots")
        require_in_arena(spawn.name, spawn.x, spawn.y, self.config.field)
        self.world.add_robot(spawn.name, spawn.x, spawn.y, spawn.theta)
        self.plugins[spawn.name] = RobotPlugin(spawn, parse_robot_name(spawn.name).agent_id)

    def delete_robot(self, name: str) -> None:
        self._plugin(name)
        if self.holder == name:
            self._release()
        self.world.remove_robot(name)
        del self.plugins[name]
        self.sensors.forget(name)

    def _plugin(self, name: str) -> RobotPlugin:
        try:
            return self.plugins[name]
        except KeyError:
            raise SimVisualError(f"no robot named {name!r}; robots: {', '.join(self.plugins) or 'none'}") from None

    def _place_ball_start(self) -> None:
        bx, by = self.config.ball_start
        self._put_ball(BallState(bx, by, self.config.ball.radius, 0.0, 0.0, 0.0))

    def _put_ball(self, state: BallState) -> None:
        """Place the ball from outside play: a ball put beyond a goal line has not crossed it."""
        self.world.set_ball_state(state)
        self._goal_open = abs(state.x) <= self.config.field.half_length + self.config.ball.radius

    def reset(self) -> None:
        """Put every robot and the ball back where they started, at rest; time keeps running."""
        self._release()
        for name, plugin in self.plugins.items():
            s = plugin.spawn
            self.world.set_robot_state(name, RobotState(s.x, s.y, s.theta, 0.0, 0.0, 0.0))
            self.world.reset_base(name)
            self.plugins[name] = RobotPlugin(s, plugin.agent_id)
        self._place_ball_start()
        self.last_touch = self._reported_touch = ""
        self.sensors.reset()

    def switch_ends(self) -> None:
        """Half time: every robot attacks the other goal and is turned half round the centre spot, at rest.

        Each robot keeps its pose in its team frame, so its own software sees no jump; the ball is
        mirrored too and stops; start poses (``reset``) follow the new ends.
        """
        self._release()
        turn = TeamFrame(-1)  # the half turn round the centre spot that takes one team's frame to the other's
        for name, plugin in self.plugins.items():
            s = self.world.robot_state(name)
            now = turn.pose_to_world(Pose2D(s.x, s.y, s.theta))
            self.world.set_robot_state(name, RobotState(now.x, now.y, now.theta, 0.0, 0.0, 0.0))
            start = turn.pose_to_world(Pose2D(plugin.spawn.x, plugin.spawn.y, plugin.spawn.theta))
            spawn = replace(plugin.spawn, x=start.x, y=start.y, theta=start.theta, attack=-plugin.spawn.attack)
            dribbling = self.world.dribbling(name)
            self.world.reset_base(name)
            self.world.set_dribbling(name, dribbling)
            self.plugins[name] = RobotPlugin(spawn, plugin.agent_id)
        b = self.world.ball_state()
        bx, by = turn.point_to_world(b.x, b.y)
        self._put_ball(BallState(bx, by, max(b.z, self.config.ball.radius), 0.0, 0.0, 0.0))

    def model_states(self) -> list[tuple[str, RobotState | BallState]]:
        states: list[tuple[str, RobotState | BallState]] = list(zip(self.plugins, self.world.robot_states()))
        states.append((self.config.ball_name, self.world.ball_state()))
        return states

    def set_model_state(self, name: str, state: RobotState | BallState) -> None:
        """Put a model in ``state``; raise ``SimVisualError`` naming the bad value, changing nothing."""
        if name == self.config.ball_name:
            if not isinstance(state, BallState):
                raise SimVisualError("the ball needs a BallState")
            self._check_ball_state(state)
            self._release()
            self._put_ball(state)
            return
        self._plugin(name)
        if not isinstance(state, RobotState):
            raise SimVisualError(f"robot {name!r} needs a RobotState")
        self._check_robot_state(name, state)
        self.world.set_robot_state(name, state)
        self.world.set_base_drive(name, state.vx, state.vy, state.w)

    def _check_robot_state(self, name: str, s: RobotState) -> None:
        _require_finite(name, s)
        require_in_arena(name, s.x, s.y, self.config.field)
        p = self.plugin_params
        speed = math.hypot(s.vx, s.vy)
        if speed > p.max_linear_speed:
            raise SimVisualError(f"{name}'s speed {speed:g} m/s exceeds max_linear_speed {p.max_linear_speed:g} m/s")
        if abs(s.w) > p.max_angular_speed:
            raise SimVisualError(f"{name}'s turn rate {s.w:g} rad/s exceeds max_angular_speed "
                                 f"{p.max_angular_speed:g} rad/s")

    def _check_ball_state(self, s: BallState) -> None:
        name, field = self.config.ball_name, self.config.field
        _require_finite(name, s)
        if not field.goal_holding(s.x, s.y, s.z, 0.0):
            require_in_arena(name, s.x, s.y, field)
        if not 0.0 <= s.z <= MAX_BALL_HEIGHT:
            raise SimVisualError(f"{name}'s height z={s.z:g} m must lie in [0, {MAX_BALL_HEIGHT:g}] m")
        speed = math.hypot(s.vx, s.vy, s.vz)
        if speed > MAX_BALL_SPEED:
            raise SimVisualError(f"{name}'s speed {speed:g} m/s exceeds {MAX_BALL_SPEED:g} m/s")
        spin, max_spin = math.hypot(s.wx, s.wy, s.wz), MAX_BALL_SPEED / self.config.ball.radius
        if spin > max_spin:
            raise SimVisualError(f"{name}'s spin {spin:g} rad/s exceeds {max_spin:g} rad/s "
                                 f"(rolling at {MAX_BALL_SPEED:g} m/s)")

    # --- the robot interface (Table 3) ------------------------------------------------------
    def command_velocity(self, name: str, vx: float, vy: float, w: float) -> tuple[BodyVelocity, bool]:
        """Set a robot's body-frame velocity command; returns it (clamped) and whether it was clamped."""
        self._plugin(name)
        command, clamped = clamp_command(vx, vy, w, self.plugin_params)
        self.world.set_command(name, command, self.time)
        return command, clamped

    def command_wheels(self, name: str, base: WheelBase, rim_speeds: np.ndarray) -> tuple[BodyVelocity, bool]:
        """Drive a robot by its wheels: the body velocity their rim speeds [m/s] give (least squares over the
        wheels), clamped as a velocity command; returns it and whether it was clamped. The wheels' dynamics are the
        caller's (a drive model such as ``nubot_hwcontrol.sim_drive``): the base's acceleration limits no longer
        apply to this robot."""
        speeds = np.asarray(rim_speeds, dtype=float)
        if not np.all(np.isfinite(speeds)):
            raise SimVisualError(f"wheel speeds must be finite, got {speeds.tolist()}")
        command = self.command_velocity(name, *base.body_velocity(speeds))
        self.world.set_driven_by_wheels(name)
        return command

    def wheel_ground_speeds(self, name: str, base: WheelBase) -> np.ndarray:
        """The rim speed robot ``name``'s actual motion gives each of its wheels [m/s]."""
        self._plugin(name)
        state = self.world.robot_state(name)
        vx, vy = rotate(state.vx, state.vy, -state.theta)
        return base.wheel_speeds(vx, vy, state.w)

    def ball_handle(self, name: str, enable: int) -> bool:
        """Enable (non-zero) or disable dribbling; return whether the robot now holds the ball."""
        self._plugin(name)
        self.world.set_dribbling(name, enable != 0)
        if enable == 0:
            if self.holder == name:
                self._release()
            return False
        self._try_capture(name)
        return self.holder == name

    def shoot(self, name: str, strength: float, shoot_pos: int) -> tuple[bool, BallKicked | None]:
        """Kick the held ball: -1 ground pass at ``strength`` m/s, 1 lob at the attacked goal."""
        plugin = self._plugin(name)
        if shoot_pos not in (KickKind.GROUND, KickKind.LOB):
            raise SimVisualError(f"ShootPos must be -1 (ground pass) or 1 (lob), got {shoot_pos}")
        kind = KickKind(shoot_pos)
        if self.holder != name:
            return False, None
        robot = self.world.robot_state(name)
        pose = Pose2D(robot.x, robot.y, robot.theta)
        ball = self.world.ball_state()
        if kind is KickKind.GROUND:
            velocity = ground_pass_velocity(robot.theta, strength, self.plugin_params)
        else:
            velocity = lob_velocity(pose, ball.x, ball.y, plugin.spawn.attack, self.config.field,
                                    self.config.ball.radius, self.config.physics.gravity, self.plugin_params)
        velocity = spread_kick(velocity, self.plugin_params, self.rng)
        self._release()
        self.world.set_dribbling(name, False)
        self.world.set_no_capture_until(name, self.time + self.plugin_params.kick_recapture_delay)
        plugin.kicked_at = self.time
        vx, vy, vz = velocity
        r = self.config.ball.radius
        if kind is KickKind.GROUND:  # rolling from the start: no skid on the carpet
            kicked = replace(ball, vx=vx, vy=vy, vz=vz, wx=-vy / r, wy=vx / r, wz=0.0)
        else:  # leaves the carpet at once, so ground friction takes nothing from it
            kicked = replace(ball, z=r + _LOB_LIFT, vx=vx, vy=vy, vz=vz, wx=0.0, wy=0.0, wz=0.0)
        self.world.set_ball_state(kicked)
        self.last_touch = name
        return True, BallKicked(self.time, name, kind, velocity, (kicked.x, kicked.y, kicked.z))

    def execute(self, name: str, command: RobotCommand,
                refused: Callable[[str, str], None] | None = None) -> tuple[bool, BallKicked | None]:
        """One control cycle's calls of the robot interface, as a control node makes them: the velocity
        (VelCmd), a BallHandle request if there is one, a Shoot if there is one. Return whether the shot was
        done ((True, None) without one) and the kick it made. With ``refused``, each call the interface refuses
        (a NaN velocity, a bad strength) is reported to it as (call, reason) and the others go on, as the
        simulator node refuses one message and takes the next (a refused velocity leaves the last good one in
        force, a refused Shoot is not done); without it, the first refusal raises ``SimVisualError``."""
        def call(part: str, action: Callable[[], T]) -> T | None:
            if refused is None:
                return action()
            try:
                return action()
            except SimVisualError as exc:
                refused(part, str(exc))
                return None

        v = command.velocity
        call("velocity", lambda: self.command_velocity(name, v.vx, v.vy, v.w))
        if command.ball_handle is not None:
            enable = command.ball_handle
            call("BallHandle", lambda: self.ball_handle(name, enable))
        if command.kick is None:
            return True, None
        kick = command.kick
        shot = call("Shoot", lambda: self.shoot(name, float(kick.strength), int(kick.kind)))
        return shot if shot is not None else (False, None)

    def update_params(self, plugin: PluginParams | None = None, noise: NoiseParams | None = None) -> None:
        if plugin is not None:
            self.plugin_params = plugin
        if noise is not None:
            self.noise = noise

    # --- perception -------------------------------------------------------------------------
    def observe(self, name: str) -> RobotView:
        """What robot ``name``'s omni vision gives now: its percepts, in its team frame, with noise."""
        return self._observe(name, self.noise, self.rng)

    def observe_all(self, names: Iterable[str]) -> list[RobotView]:
        """What the omni vision of each robot of ``names`` gives now, in that order: the frames ``observe`` would give
        one after the other (the same noise), made together."""
        names = list(names)
        for name in names:
            self._plugin(name)
        robots = list(self.plugins)
        index = {n: i for i, n in enumerate(robots)}
        return observe_all(self.time, self.world.robot_states(), [index[n] for n in names],
                           [TeamFrame(self.plugins[n].spawn.attack) for n in names],
                           [self.plugins[n].agent_id for n in names], [self._flags(n) for n in names],
                           self.world.ball_state(), self.noise, self.rng)

    def observe_ball3d(self, name: str) -> Ball3dPercept | None:
        """The ball in 3-D as robot ``name``'s RGB-D cameras give it now (a goalie's; team frame, with noise);
        None out of their view. Its noise comes from a generator of its own: asking changes no other percept."""
        plugin = self._plugin(name)
        return observe_ball3d(self.time, self.world.robot_state(name), TeamFrame(plugin.spawn.attack),
                              self.world.ball_state(), self.ball3d_rng)

    def observe_truth(self, name: str) -> RobotView:
        """Robot ``name``'s percepts without noise or range limit (the truth a vision is measured against);
        draws nothing from the simulator's generator."""
        return self._observe(name, _NO_NOISE, np.random.default_rng(0))

    def _flags(self, name: str) -> RobotFlags:
        plugin, me = self.plugins[name], self.world.robot_state(name)
        return RobotFlags(self.config.field.is_inside(me.x, me.y, self.config.field.border), self.world.stuck(name),
                          self.holder == name, self.time - plugin.kicked_at < _KICK_FLAG_TIME)

    def _observe(self, name: str, noise: NoiseParams, rng: np.random.Generator) -> RobotView:
        plugin = self._plugin(name)
        others = [self.world.robot_state(n) for n in self.plugins if n != name]
        return observe(self.time, self.world.robot_state(name), TeamFrame(plugin.spawn.attack), plugin.agent_id,
                       self._flags(name), self.world.ball_state(), others, noise, rng)

    def camera_frame(self, name: str, labels: bool = False) -> RenderedFrame:
        """Robot ``name``'s omni camera image now (and each pixel's colour class with ``labels``)."""
        self._plugin(name)
        others = [self.world.robot_state(n) for n in self.plugins if n != name]
        return self.sensors.camera(self.time, self.world.robot_state(name), self.world.ball_state(), others, labels)

    def front_camera_frame(self, name: str) -> np.ndarray:
        """Robot ``name``'s front camera image now (RGB, the camera's size; a regular robot's, front_vision)."""
        self._plugin(name)
        others = [self.world.robot_state(n) for n in self.plugins if n != name]
        return self.sensors.front_camera(self.time, self.world.robot_state(name), self.world.ball_state(), others)

    def rgbd_frames(self, name: str) -> tuple[RgbdFrame, RgbdFrame]:
        """Robot ``name``'s two RGB-D cameras' point clouds now (left, right; the goalie's, kinect_ball)."""
        self._plugin(name)
        others = [self.world.robot_state(n) for n in self.plugins if n != name]
        return self.sensors.rgbd(self.time, self.world.robot_state(name), self.world.ball_state(), others)

    def odometry(self, name: str, dt: float) -> OdometryReading:
        """Robot ``name``'s wheel odometry now, ``dt`` [s] after its previous reading."""
        self._plugin(name)
        return self.sensors.odometry(name, self.world.robot_state(name), dt, self.world.stuck(name))

    def inertial_heading(self, name: str, dt: float) -> ImuReading:
        """Robot ``name``'s inertial heading now (team frame: 0 faces the goal it attacks), ``dt`` [s] after
        its previous reading."""
        plugin = self._plugin(name)
        state = self.world.robot_state(name)
        heading = TeamFrame(plugin.spawn.attack).heading_to_team(state.theta)
        return self.sensors.inertial_heading(name, heading, state.w, dt)

    # --- stepping -------------------------------------------------------------------------
    def step(self) -> list[SimEvent]:
        """Advance one physics step and return what happened in it."""
        dt = self.config.physics.step_size
        # The bases, the holder's grip, the step, a capture and the carried ball: one compiled call.
        holder = self.holder
        time = self.time
        happened = self.world.advance(dt, time, self.steps, holder)
        self.time = (self.steps + 1) * dt
        self.steps += 1
        if happened is None and self.last_touch == self._reported_touch and (holder or "") == self._reported_holder:
            self._goal_open = True  # the ball is short of both goal lines: back in play
            return []  # the usual step: nothing to report
        events: list[SimEvent] = []
        touched, slipped, captured = happened if happened is not None else ((), False, None)
        if slipped and holder is not None:  # it moved faster than its handler holds for hold_slip_time: it rolls on
            events.append(BallReleased(time, holder))
            self.holder = None
        if touched:
            self.last_touch = sorted(touched)[0] if self.last_touch not in touched else self.last_touch
        if captured is not None:
            self.holder = self.last_touch = captured
            events.append(BallCaptured(self.time, captured))
        if self.last_touch != self._reported_touch:  # also catches captures made by a BallHandle call
            self._reported_touch = self.last_touch
            if self.last_touch:
                events.append(BallTouched(self.time, self.last_touch, self.world.ball_state()))
        if (self.holder or "") != self._reported_holder:  # captures, kicks, releases and slips, however made
            self._reported_holder = self.holder or ""
            events.append(HolderChanged(self.time, self._reported_holder, self.world.ball_state()))
        goal = self._detect_goal()
        if goal is not None:
            events.append(goal)
        return events

    def _try_capture(self, name: str) -> bool:
        if self.holder is not None:
            return self.holder == name
        if not self.world.can_capture(name, self.time):
            return False
        self._capture(name)
        return True

    def _capture(self, name: str) -> None:
        self.holder = name
        self.last_touch = name
        self.world.carry_ball(name)

    def _release(self) -> None:
        self.holder = None
        self.world.set_ball_collides_with(None)

    def _detect_goal(self) -> GoalScored | None:
        """A goal: a ball that came from the field lies in a goal (``FieldGeometry.goal_holding``);
        counted once, until the ball is back in play."""
        field = self.config.field
        if abs(self.world.ball_x()) < field.half_length:  # most steps: no ball record made
            self._goal_open = True
            return None
        ball = self.world.ball_state()
        side = field.goal_holding(ball.x, ball.y, ball.z, self.config.ball.radius)
        if not side or not self._goal_open:
            return None
        self._goal_open = False
        return GoalScored(self.time, side, ball, self.last_touch)


def _require_finite(name: str, state: RobotState | BallState) -> None:
    if not all(math.isfinite(v) for v in astuple(state)):
        raise SimVisualError(f"state for {name!r} must be finite, got {state}")

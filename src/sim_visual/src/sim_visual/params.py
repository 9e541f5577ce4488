"""Typed configuration of the simulator (read once from ``config/sim_visual.yaml``).

Provides frozen, validated dataclasses; all values SI (m, kg, s, rad unless a
name says ``_deg``). ``SimConfig`` is the whole configuration; ``PluginParams``
and ``NoiseParams`` are the run-time reconfigurable part. The field, the goals and
the bodies are the match's ``WorldDescription`` (``SimConfig.world``): the node
reads it from /world, as every other node does. ``SimInterfaceParams`` configures
the team relay node.

Also the one home of the simulator's limits: ``PLUGIN_UPPER_BOUNDS``, ``NOISE_UPPER_BOUNDS``
and ``REAL_TIME_FACTOR_MAX`` (checked here and used as the dynamic_reconfigure ranges),
``MAX_ROBOTS``, ``MAX_BALL_SPEED``, ``MAX_BALL_HEIGHT``, ``MAX_RELAY_RATE`` and
``require_in_arena`` (where a body may be put: inside the lines plus the border, up to the
walls' inner faces).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from dataclasses import field as dc_field
from types import MappingProxyType

from nubot_common import NubotCommonError
from nubot_common.field import FieldGeometry
from nubot_common.naming import RobotSelection, check_team_prefix, parse_robot_name
from nubot_common.params import require_non_negative, require_positive
from nubot_common.world_description import BallBody, RobotBody, WorldDescription
from sim_visual import SimVisualError
from sim_visual.sensors import SensorParams

MAX_STEP_SIZE = 0.007  # [s], chapter Table 2
MAX_GRAVITY = 50.0  # [m/s^2], about 5 g: stronger gravity is no soccer field

# Upper bounds of the reconfigurable parameters; with 0 below (refused by those that must be
# positive) they are the ranges dynamic_reconfigure offers.
# Speeds: a robot or ball must move less per ODE step than the 0.2 m walls are thick, or it can
# pass through them; at the largest step (0.007 s) 10 m/s is 7 cm and 15 m/s is 10.5 cm.
PLUGIN_UPPER_BOUNDS: Mapping[str, float] = MappingProxyType({
    "dribble_distance": 1.0,  # [m]; robot and ball touch at 0.37 m, no grabber reaches 1 m
    "dribble_angle_deg": 180.0,  # [deg]; the whole front half
    "hold_distance": 1.0,  # [m]; farther, a held ball would pass through other robots
    "max_linear_speed": 10.0,  # [m/s]; twice the fastest MSL robots (about 5 m/s, chapter 1)
    "max_angular_speed": 30.0,  # [rad/s]; about 5 turns a second
    "max_linear_accel": 50.0,  # [m/s^2]; about 5 g, far beyond what wheels on a carpet give
    "max_linear_brake": 50.0,  # [m/s^2]
    "max_angular_accel": 200.0,  # [rad/s^2]
    "hold_forward_speed": 10.0,  # [m/s]; max_linear_speed's bound
    "hold_backward_speed": 10.0,  # [m/s]
    "hold_sideways_speed": 10.0,  # [m/s]
    "hold_turn_rate": 30.0,  # [rad/s]; max_angular_speed's bound
    "hold_slip_time": 5.0,  # [s]
    "command_timeout": 10.0,  # [s]
    "kick_max_speed": 15.0,  # [m/s]; above the hardest MSL kicks (about 12 m/s)
    "kick_recapture_delay": 5.0,  # [s]
    "kick_direction_std_deg": 20.0,  # [deg]; a kicker that bad could not aim at a goal from 7 m
    "kick_speed_std": 0.5,  # share of the speed
    "lob_max_speed": 15.0,  # [m/s]; kick_max_speed's bound
    "lob_horizontal_speed": 15.0,  # [m/s]; a lob is a kick: kick_max_speed's bound
    "lob_max_flight_time": 5.0,  # [s]
    "lob_bar_margin": 1.0,  # [m]; the bar is 1 m high
    "lob_default_distance": 30.0,  # [m]; longer than the 22 m field
    "stuck_time": 10.0,  # [s]
})
NOISE_UPPER_BOUNDS: Mapping[str, float] = MappingProxyType({
    "position_std": 5.0,  # [m]
    "velocity_std": 5.0,  # [m/s]
    "self_position_std": 5.0,  # [m]
    "heading_std": math.pi,  # [rad]
    "vision_range": 100.0,  # [m]; the 22 x 14 m field's diagonal is 26 m
})
REAL_TIME_FACTOR_MAX = 100.0  # sim seconds per wall second (0, as fast as possible, also allowed)

MAX_ROBOTS = 20  # two teams of ten (five players and five more for tests or substitutes)
# A ball set from outside (set_model_state) may move at most twice as fast as the hardest kick
# allowed: 0.21 m per 0.007 s step, less than its diameter plus a net's 2 cm, so it cannot pass
# through a net. Its spin is bounded by rolling at that speed (MAX_BALL_SPEED / radius).
MAX_BALL_SPEED = 2.0 * PLUGIN_UPPER_BOUNDS["kick_max_speed"]  # [m/s]
MAX_BALL_HEIGHT = 20.0  # [m]; a kick at 15 m/s straight up peaks at 11.5 m
MAX_RELAY_RATE = 1000.0  # sim_interface's rate [Hz]; far faster than any sender (control: 33 Hz)


def _require_at_most(obj: object, bounds: Mapping[str, float]) -> None:
    for name, high in bounds.items():
        if not getattr(obj, name) <= high:
            raise ValueError(f"{name} must be at most {high:g}, got {getattr(obj, name)}")


def require_in_arena(what: str, x: float, y: float, field: FieldGeometry) -> None:
    """Raise ``SimVisualError`` naming ``what`` unless (x, y) [m] is finite and inside the arena's walls."""
    if not (math.isfinite(x) and math.isfinite(y)):
        raise SimVisualError(f"{what} must be at a finite position, got ({x}, {y})")
    if not field.is_inside(x, y, field.border):
        raise SimVisualError(
            f"{what} at ({x:g}, {y:g}) is outside the arena: |x| <= {field.half_length + field.border:g} m "
            f"and |y| <= {field.half_width + field.border:g} m (the lines plus the {field.border:g} m border)")


@dataclass(frozen=True)
class PhysicsParams:
    step_size: float = 0.005  # [s], at most 0.007 (chapter Table 2)
    gravity: float = -9.8  # [m/s^2] along z

    def __post_init__(self) -> None:
        if not 0.0 < self.step_size <= MAX_STEP_SIZE:
            raise ValueError(f"step_size must lie in (0, {MAX_STEP_SIZE}] s, got {self.step_size}")
        if not -MAX_GRAVITY <= self.gravity < 0.0:
            raise ValueError(f"gravity must be negative (down) and at least -{MAX_GRAVITY:g}, got {self.gravity}")


@dataclass(frozen=True)
class PluginParams:
    """The model plugin's rules (reconfigurable at run time)."""

    dribble_distance: float = 0.50  # robot centre to ball centre, in the plane [m]
    dribble_angle_deg: float = 30.0  # full width of the cone in front of the robot [deg]
    hold_distance: float = 0.43  # held ball centre ahead of the robot centre [m]
    max_linear_speed: float = 5.0  # commands faster than this are clamped [m/s]
    max_angular_speed: float = 12.0  # [rad/s]
    # The base follows its command within these (world frame; docs/physical_figures.md): speeding up or turning
    # aside at max_linear_accel, slowing down at max_linear_brake.
    max_linear_accel: float = 3.5  # [m/s^2]
    max_linear_brake: float = 5.0  # [m/s^2]
    max_angular_accel: float = 10.0  # [rad/s^2]
    # What a robot holding the ball can do (body frame; the ball handler's grip): moving faster than these for
    # hold_slip_time loses the ball, which rolls on with the velocity it had.
    hold_forward_speed: float = 2.2  # [m/s]
    hold_backward_speed: float = 0.75  # [m/s]
    hold_sideways_speed: float = 0.75  # [m/s]
    hold_turn_rate: float = 4.0  # [rad/s]
    hold_slip_time: float = 0.1  # [s]
    command_timeout: float = 0.5  # a robot with no command for this long stops [s]; 0 never
    kick_max_speed: float = 10.0  # ball speed limit of a flat kick [m/s]
    kick_recapture_delay: float = 0.3  # the kicker cannot hold the ball again this soon [s]
    # A kick's spread (standard deviations, one draw each from the simulator's generator): its direction, and its
    # speed as a share of the speed asked for.
    kick_direction_std_deg: float = 1.5  # [deg]
    kick_speed_std: float = 0.05
    lob_max_speed: float = 8.6  # ball speed limit of a lob (about 45 degrees up) [m/s]
    lob_horizontal_speed: float = 6.0  # preferred horizontal speed of a lob [m/s]
    lob_max_flight_time: float = 1.6  # longer lobs get a faster horizontal speed [s]
    lob_bar_margin: float = 0.15  # ball top passes this far under the bar [m]
    lob_default_distance: float = 6.0  # lob length when the robot does not face the goal [m]
    stuck_time: float = 1.0  # slower than half the command this long means stuck [s]

    def __post_init__(self) -> None:
        require_positive(self, "dribble_distance", "hold_distance", "max_linear_speed", "max_angular_speed",
                  "kick_max_speed", "lob_horizontal_speed", "lob_max_flight_time", "lob_default_distance",
                  "stuck_time", "max_linear_accel", "max_linear_brake", "max_angular_accel", "hold_forward_speed",
                  "hold_backward_speed", "hold_sideways_speed", "hold_turn_rate", "lob_max_speed")
        require_non_negative(self, "command_timeout", "kick_recapture_delay", "lob_bar_margin", "hold_slip_time",
                             "kick_direction_std_deg", "kick_speed_std")
        require_positive(self, "dribble_angle_deg")
        _require_at_most(self, PLUGIN_UPPER_BOUNDS)

    @property
    def dribble_half_angle(self) -> float:
        """Largest bearing [rad] from the robot front at which the ball can be held."""
        return math.radians(self.dribble_angle_deg) / 2.0


@dataclass(frozen=True)
class NoiseParams:
    """Gaussian noise (standard deviations) on what each robot perceives; 0 disables."""

    position_std: float = 0.05  # ball and obstacle positions [m]
    velocity_std: float = 0.10  # ball and robot velocities [m/s]
    self_position_std: float = 0.02  # own position (self-localization) [m]
    heading_std: float = 0.01  # own heading [rad]
    vision_range: float = 0.0  # objects farther than this are not seen [m]; 0 unlimited

    def __post_init__(self) -> None:
        require_non_negative(self, "position_std", "velocity_std", "self_position_std", "heading_std",
                      "vision_range")
        _require_at_most(self, NOISE_UPPER_BOUNDS)


@dataclass(frozen=True)
class RobotSpawn:
    """Where a robot starts; ``attack`` is +1 for a team attacking the goal at +x, -1 otherwise."""

    name: str
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    attack: int = 1

    def __post_init__(self) -> None:
        try:
            parse_robot_name(self.name)
        except NubotCommonError as exc:
            raise ValueError(str(exc)) from None
        if self.attack not in (1, -1):
            raise ValueError(f"attack must be 1 or -1, got {self.attack}")
        if not math.isfinite(self.theta):
            raise ValueError(f"{self.name}'s heading theta must be finite, got {self.theta}")


@dataclass(frozen=True)
class SimConfig:
    world: WorldDescription = dc_field(default_factory=WorldDescription)
    physics: PhysicsParams = dc_field(default_factory=PhysicsParams)
    plugin: PluginParams = dc_field(default_factory=PluginParams)
    noise: NoiseParams = dc_field(default_factory=NoiseParams)
    robots: tuple[RobotSpawn, ...] = ()
    ball_start: tuple[float, float] = (0.0, 0.0)  # [m]
    seed: int = 0
    sensors: SensorParams = dc_field(default_factory=SensorParams)  # camera, odometry, inertial heading

    def __post_init__(self) -> None:
        names = [r.name for r in self.robots]
        if len(set(names)) != len(names):
            raise ValueError(f"robot names must be unique, got {names}")
        if len(self.robots) > MAX_ROBOTS:
            raise ValueError(f"at most {MAX_ROBOTS} robots, got {len(self.robots)}")
        for robot in self.robots:
            require_in_arena(f"{robot.name}'s start", robot.x, robot.y, self.field)
        require_in_arena("ball_start", *self.ball_start, self.field)
        if self.seed < 0:
            raise ValueError(f"seed must not be negative, got {self.seed}")

    @property
    def field(self) -> FieldGeometry:
        return self.world.field

    @property
    def ball(self) -> BallBody:
        return self.world.ball

    @property
    def robot(self) -> RobotBody:
        return self.world.robot

    @property
    def ball_name(self) -> str:
        return self.world.ball_name


@dataclass(frozen=True)
class SimNodeParams:
    """Parameters of the simulator node: the world plus how it runs and publishes."""

    sim: SimConfig = dc_field(default_factory=SimConfig)
    real_time_factor: float = 1.0  # sim seconds per wall second; 0 runs as fast as possible
    model_states_rate: float = 100.0  # /sim_visual/model_states [Hz, sim time]
    vision_rate: float = 30.0  # /<robot>/omnivision/OmniVisionInfo, or camera image [Hz, sim time]
    vision: str = ""  # robots seeing through the camera (RobotSelection: all, or names such as nubot1,rival2)
    goalie_id: int = 1  # AgentID of the goalie of a team ``goalies`` does not name (nubot_control's play/goalie_id);
    # 0: none. A goalie of ``vision`` also gets its two RGB-D cameras' clouds (kinect_ball)
    goalies: str = ""  # each team's goalie by name, at most one a team (e.g. nubot1,rival3: the match runner's, from
    # the team YAMLs); overrides goalie_id for the teams it names
    odometry_rate: float = 50.0  # their /<robot>/nubotdriver/odoinfo [Hz, sim time]
    imu_rate: float = 50.0  # their /<robot>/imu/data [Hz, sim time]
    camera_labels: bool = False  # also publish each image's colour classes (/<robot>/camera/labels)
    clock_rate: float = 1000.0  # /clock this often [Hz, sim time], on the first step at or after each due time (at
    # most once a step: 1000 Hz on 5 ms steps is every step)
    gui: bool = False  # no viewer exists yet: true only warns and runs headless
    cpu_nice: int = 5  # the node's claim on the CPU against the other nodes' (nubot_common.node_io.yield_cpu), 0 to
    # 19: on a machine too busy for the whole match, sim time slows instead of the robots missing control cycles

    def __post_init__(self) -> None:
        require_non_negative(self, "real_time_factor")
        if not self.real_time_factor <= REAL_TIME_FACTOR_MAX:
            raise ValueError(f"real_time_factor must be at most {REAL_TIME_FACTOR_MAX:g}, got {self.real_time_factor}")
        require_positive(self, "model_states_rate", "vision_rate", "clock_rate", "odometry_rate", "imu_rate")
        if not 0 <= self.cpu_nice <= 19:
            raise ValueError(f"cpu_nice must lie in [0, 19] (0: the default priority), got {self.cpu_nice}")
        if not 0 <= self.goalie_id <= MAX_ROBOTS:
            raise ValueError(f"goalie_id must lie in [0, {MAX_ROBOTS}] (0: no goalie), got {self.goalie_id}")
        try:
            RobotSelection.parse(self.vision)
        except NubotCommonError as exc:
            raise ValueError(f"vision: {exc}") from None
        try:
            goalies = RobotSelection.parse(self.goalies)
        except NubotCommonError as exc:
            raise ValueError(f"goalies: {exc}") from None
        if goalies.every:
            raise ValueError("goalies names one robot a team (e.g. nubot1,rival3), not all")
        teams = [parse_robot_name(name).team for name in goalies.names]
        if len(set(teams)) < len(teams):
            raise ValueError(f"goalies names two robots of one team: {self.goalies!r}")

    @property
    def vision_robots(self) -> RobotSelection:
        return RobotSelection.parse(self.vision)

    def is_goalie(self, name: str) -> bool:
        """Whether robot ``name`` is its team's goalie: the one ``goalies`` names for its team, else AgentID
        ``goalie_id``."""
        robot = parse_robot_name(name)
        named = RobotSelection.parse(self.goalies).names
        if any(parse_robot_name(goalie).team == robot.team for goalie in named):
            return name in named
        return robot.agent_id == self.goalie_id


@dataclass(frozen=True)
class SimInterfaceParams:
    """Parameters of the team relay node (sim_interface)."""

    team: str = "nubot"  # the team's prefix; its members are <team>1 .. <team><team_size>
    team_size: int = 5  # number of members, 1 .. MAX_ROBOTS
    max_age: float = 1.0  # messages older than this are no longer relayed [s]
    rate: float = 30.0  # relayed messages out [Hz, sim time]

    def __post_init__(self) -> None:
        check_team_prefix(self.team)
        if not 1 <= self.team_size <= MAX_ROBOTS:
            raise ValueError(f"team_size must lie in [1, {MAX_ROBOTS}], got {self.team_size}")
        require_positive(self, "max_age", "rate")
        if not self.rate <= MAX_RELAY_RATE:
            raise ValueError(f"rate must be at most {MAX_RELAY_RATE:g} Hz, got {self.rate}")

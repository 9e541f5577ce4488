"""Typed configuration of the simulator (read once from ``config/sim_visual.yaml``).

Provides frozen, validated dataclasses; all values SI (m, kg, s, rad unless a
name says ``_deg``). ``SimConfig`` is the whole configuration; ``PluginParams``
and ``NoiseParams`` are the run-time reconfigurable part. The field, the goals and
the bodies are the match's ``WorldDescription`` (``SimConfig.world``): the node
reads it from /world, as every other node does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import field as dc_field

from nubot_common import NubotCommonError
from nubot_common.field import FieldGeometry
from nubot_common.naming import parse_robot_name
from nubot_common.params import require_non_negative, require_positive
from nubot_common.world_description import BallBody, RobotBody, WorldDescription

MAX_STEP_SIZE = 0.007  # [s], chapter Table 2


@dataclass(frozen=True)
class PhysicsParams:
    step_size: float = 0.005  # [s], at most 0.007 (chapter Table 2)
    gravity: float = -9.8  # [m/s^2] along z

    def __post_init__(self) -> None:
        if not 0.0 < self.step_size <= MAX_STEP_SIZE:
            raise ValueError(f"step_size must lie in (0, {MAX_STEP_SIZE}] s, got {self.step_size}")
        if not self.gravity < 0.0:
            raise ValueError(f"gravity must be negative (down), got {self.gravity}")


@dataclass(frozen=True)
class PluginParams:
    """The model plugin's rules (reconfigurable at run time)."""

    dribble_distance: float = 0.50  # robot centre to ball centre, in the plane [m]
    dribble_angle_deg: float = 30.0  # full width of the cone in front of the robot [deg]
    hold_distance: float = 0.43  # held ball centre ahead of the robot centre [m]
    max_linear_speed: float = 5.0  # commands faster than this are clamped [m/s]
    max_angular_speed: float = 12.0  # [rad/s]
    command_timeout: float = 0.5  # a robot with no command for this long stops [s]; 0 never
    kick_max_speed: float = 12.0  # ball speed limit of a kick [m/s]
    kick_recapture_delay: float = 0.3  # the kicker cannot hold the ball again this soon [s]
    lob_horizontal_speed: float = 6.0  # preferred horizontal speed of a lob [m/s]
    lob_max_flight_time: float = 1.6  # longer lobs get a faster horizontal speed [s]
    lob_bar_margin: float = 0.15  # ball top passes this far under the bar [m]
    lob_default_distance: float = 6.0  # lob length when the robot does not face the goal [m]
    stuck_time: float = 1.0  # slower than half the command this long means stuck [s]

    def __post_init__(self) -> None:
        require_positive(self, "dribble_distance", "hold_distance", "max_linear_speed", "max_angular_speed",
                  "kick_max_speed", "lob_horizontal_speed", "lob_max_flight_time", "lob_default_distance",
                  "stuck_time")
        require_non_negative(self, "command_timeout", "kick_recapture_delay", "lob_bar_margin")
        if not 0.0 < self.dribble_angle_deg <= 180.0:
            raise ValueError(f"dribble_angle_deg must lie in (0, 180], got {self.dribble_angle_deg}")

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


@dataclass(frozen=True)
class SimConfig:
    world: WorldDescription = dc_field(default_factory=WorldDescription)
    physics: PhysicsParams = dc_field(default_factory=PhysicsParams)
    plugin: PluginParams = dc_field(default_factory=PluginParams)
    noise: NoiseParams = dc_field(default_factory=NoiseParams)
    robots: tuple[RobotSpawn, ...] = ()
    ball_start: tuple[float, float] = (0.0, 0.0)  # [m]
    seed: int = 0

    def __post_init__(self) -> None:
        names = [r.name for r in self.robots]
        if len(set(names)) != len(names):
            raise ValueError(f"robot names must be unique, got {names}")

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
    vision_rate: float = 30.0  # /<robot>/omnivision/OmniVisionInfo [Hz, sim time]
    clock_rate: float = 1000.0  # /clock at most this often [Hz, sim time]; at least once a step
    gui: bool = False  # no viewer exists yet: true only warns and runs headless

    def __post_init__(self) -> None:
        require_non_negative(self, "real_time_factor")
        require_positive(self, "model_states_rate", "vision_rate", "clock_rate")

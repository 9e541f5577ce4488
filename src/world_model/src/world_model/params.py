"""Typed configuration of the world model (read once from ``config/world_model.yaml``).

Provides: ``WorldModelParams``, frozen and validated; times in seconds of sim time,
distances in metres. The node reads it from its private namespace with
``nubot_common.params.from_mapping`` (unknown keys and bad values are refused by name).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class WorldModelParams:
    team_size: int = 5  # robots per team; AgentIDs run 1..team_size
    teammate_timeout: float = 0.3  # a robot whose state is older than this is invalid [s] (NuBot: 300 ms)
    strategy_timeout: float = 1.0  # a teammate whose strategy is older than this no longer plays [s]
    ball_timeout: float = 0.3  # own perception (ball, obstacles) older than this is not used [s]
    velocity_window: float = 0.5  # ball positions this recent enter the velocity fit [s]
    min_fit_samples: int = 3  # fewer positions in the window: ball velocity unknown
    teammate_radius: float = 0.5  # an obstacle this close to a valid teammate is that teammate [m]
    obstacle_merge_radius: float = 0.5  # a teammate's obstacle this close to a known one is the same robot [m]
    # Own obstacles are tracked from frame to frame (world_model.obstacles.ObstacleTracker):
    obstacle_gate: float = 0.5  # a percept this close to a track's prediction may continue it [m]
    obstacle_position_gain: float = 0.4  # share of a percept's difference from the prediction taken, in (0, 1]
    obstacle_velocity_gain: float = 0.1  # share of it that goes into the velocity per frame, below the position's
    obstacle_coast: float = 0.1  # a track no percept continues is kept this long [s]
    obstacle_max_speed: float = 5.0  # an obstacle's estimated speed is at most this [m/s]
    ball_agreement_radius: float = 1.0  # a robot whose ball is this close to the fused ball sees the same ball [m]
    sighting_confidence: float = 0.7  # confidence in a fresh ball seen by one robot, in (0, 1)
    sensor_timeout: float = 0.15  # an own sensor whose ball is this recent takes its place in the order of trust [s]
    air_margin: float = 0.1  # a 3-D ball whose centre is this much above a ball at rest flies [m]

    def __post_init__(self) -> None:
        if not 1 <= self.team_size <= 99:
            raise ValueError(f"team_size must lie in [1, 99], got {self.team_size}")
        for name in ("teammate_timeout", "strategy_timeout", "ball_timeout", "velocity_window", "teammate_radius",
                     "obstacle_merge_radius", "obstacle_gate", "obstacle_coast", "obstacle_max_speed",
                     "ball_agreement_radius", "sensor_timeout", "air_margin"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"{name} must be positive, got {getattr(self, name)}")
        if self.min_fit_samples < 2:
            raise ValueError(f"min_fit_samples must be at least 2 (a line needs 2 points), got {self.min_fit_samples}")
        if not 0.0 < self.sighting_confidence < 1.0:
            raise ValueError(f"sighting_confidence must lie in (0, 1), got {self.sighting_confidence}")
        if not 0.0 <= self.obstacle_velocity_gain < self.obstacle_position_gain <= 1.0:
            raise ValueError("the obstacle gains must satisfy 0 <= obstacle_velocity_gain < obstacle_position_gain "
                             f"<= 1, got {self.obstacle_velocity_gain} and {self.obstacle_position_gain}")

"""The world of a match: the field with its markings and goals, the ball, the robot bodies (one YAML).

Provides: ``BallBody``, ``RobotBody`` and ``WorldDescription`` (frozen, validated; SI units), the
shipped descriptions ``FIELDS`` (``18x12``: the chapter's 2015 field; ``22x14``: the current MSL
field), ``world_file(name)`` (the YAML of a shipped field, or any path), ``load_world(name or path)``
and ``WORLD_NAMESPACE``: every launch file loads the match's YAML into this ROS parameter
namespace, and every node that needs the field, the goals or the bodies (simulator, world model,
control, referee, spawner) reads it from there. The simulator also publishes it, latched, so a
bag carries the world its match was played in.
"""

from __future__ import annotations

from dataclasses import dataclass
from dataclasses import field as dc_field
from pathlib import Path

from nubot_common import NubotCommonError
from nubot_common.field import FieldGeometry
from nubot_common.params import from_mapping, load_yaml, require_non_negative, require_positive

WORLD_NAMESPACE = "/world"
CONFIG_DIR = Path(__file__).resolve().parents[2] / "config"
FIELDS = ("18x12", "22x14")  # shipped descriptions: config/world_<name>.yaml


@dataclass(frozen=True)
class RobotBody:
    """The robot model of chapter Table 1: a simplified cylinder, no joints."""

    mass: float = 31.0  # [kg]
    inertia_zz: float = 2.86  # [kg m^2]
    friction: float = 0.1  # contact friction coefficient against ball and robots
    radius: float = 0.26  # collision cylinder radius [m] (52 cm footprint, MSL maximum)
    height: float = 0.75  # collision cylinder height [m]

    def __post_init__(self) -> None:
        require_positive(self, "mass", "inertia_zz", "radius", "height")
        require_non_negative(self, "friction")


@dataclass(frozen=True)
class BallBody:
    """A FIFA size 5 ball."""

    mass: float = 0.41  # [kg]
    radius: float = 0.11  # [m]
    rolling_friction: float = 0.08  # rolling deceleration = rolling_friction * g (0.78 m/s^2 on artificial turf)
    ground_friction: float = 0.4  # sliding friction against the carpet
    restitution: float = 0.6  # bounce off the ground (FIFA's turf rebound test)
    net_restitution: float = 0.3  # share of the ball's motion a goal net keeps per step of contact
    body_restitution: float = 0.7  # bounce off robots, posts and walls

    def __post_init__(self) -> None:
        require_positive(self, "mass", "radius")
        require_non_negative(self, "rolling_friction", "ground_friction")
        for name in ("restitution", "net_restitution", "body_restitution"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"{name} must lie in [0, 1], got {getattr(self, name)}")


@dataclass(frozen=True)
class WorldDescription:
    field: FieldGeometry = dc_field(default_factory=FieldGeometry)
    ball: BallBody = dc_field(default_factory=BallBody)
    robot: RobotBody = dc_field(default_factory=RobotBody)
    ball_name: str = "football"  # the ball's model name in the simulator, its model states and bags

    def __post_init__(self) -> None:
        if not self.ball_name or not self.ball_name.replace("_", "").isalnum() or self.ball_name[-1].isdigit():
            raise ValueError(f"ball_name must be a name not ending in a digit, got {self.ball_name!r}")
        if self.ball.radius >= self.field.goal_height / 2 or 2 * self.ball.radius >= self.field.goal_width:
            raise ValueError("the ball must fit into the goal")

    @property
    def name(self) -> str:
        """The field's size in words, e.g. ``18 x 12 m``."""
        return f"{self.field.length:g} x {self.field.width:g} m"


def world_file(name: str | Path) -> Path:
    """The YAML of a shipped field (``18x12``, ``22x14``) or the path given; raise if there is none."""
    text = str(name)
    path = CONFIG_DIR / f"world_{text}.yaml" if text in FIELDS else Path(text)
    if not path.is_file():
        raise NubotCommonError(f"no world description {text!r}: give one of {', '.join(FIELDS)} or a YAML file")
    return path


def load_world(name: str | Path = "18x12") -> WorldDescription:
    """Read a world description (a shipped field's name or a YAML path); errors name the bad key or value."""
    return load_yaml(WorldDescription, world_file(name))


def world_from_params(value: object) -> WorldDescription:
    """The world description a node finds under ``WORLD_NAMESPACE`` on the parameter server (None: absent)."""
    if value is None:
        raise NubotCommonError(
            f"no world description under {WORLD_NAMESPACE}: start the node from a launch file of the workspace, "
            f"or load one first: rosparam load $(rospack find nubot_common)/config/world_18x12.yaml {WORLD_NAMESPACE}")
    if not isinstance(value, dict):
        raise NubotCommonError(f"{WORLD_NAMESPACE}: expected a mapping (field, ball, robot), got {value!r}")
    return from_mapping(WorldDescription, value, WORLD_NAMESPACE)

"""Factories for the world model's unit tests: robots, teammates' views, a fresh WorldModel."""

import pytest

from nubot_common.geometry import Pose2D
from nubot_common.percepts import BallPercept, RobotReport, RobotView
from world_model.params import WorldModelParams
from world_model.world_model import WorldModel


@pytest.fixture
def make_model():
    """A WorldModel for AgentID ``agent_id`` with ``WorldModelParams`` overrides."""
    def build(agent_id: int = 1, **overrides) -> WorldModel:
        return WorldModel(WorldModelParams(**overrides), agent_id)
    return build


@pytest.fixture
def robot():
    """A RobotReport of robot ``agent_id`` at (x, y, theta)."""
    def build(agent_id: int, x: float, y: float, theta: float = 0.0, **fields) -> RobotReport:
        return RobotReport(agent_id, Pose2D(x, y, theta), **fields)
    return build


@pytest.fixture
def mate_view(robot):
    """A teammate's message stamped ``t``: its pose, optionally the ball it sees and its obstacles."""
    def build(t: float, agent_id: int, x: float, y: float, ball: tuple[float, float] | None = None,
              obstacles: tuple = (), **fields) -> RobotView:
        seen = BallPercept(t, *ball) if ball is not None else None
        return RobotView(t, robot(agent_id, x, y, **fields), seen, tuple(obstacles))
    return build


@pytest.fixture
def see(robot):
    """Feed ``model`` one own vision frame at ``t``: own pose, the ball (or None), obstacles."""
    def feed(model: WorldModel, t: float, pose=(-2.0, 0.0, 0.0), ball=(1.0, 2.0), obstacles=(), **fields) -> None:
        seen = BallPercept(t, *ball) if ball is not None else None
        model.on_vision(RobotView(t, robot(model.agent_id, *pose, **fields), seen, tuple(obstacles)))
    return feed

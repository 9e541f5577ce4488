"""NuBot/ScoreAgainstGoalie-v0: one learning attacker against the built-in goalie (Gymnasium).

Requires: two team YAMLs (default ``nubot_match/config/score_attacker.yaml``: nubot1, the learner, and
``score_goalie.yaml``: rival1, the other team's goalie, playing the built-in strategy), the field.
Provides: ``ScoreAgainstGoalieEnv``. Each episode starts with the ball in play at once, the learner and the
ball at rest at random places of the attacking half (``self.np_random``: x in [0, L-3] m, |y| <= W-1 m,
any heading for the robot; x in [1, L-2.5] m, |y| <= W-1.5 m, at least 1 m from the robot for the ball; L,
W the half length and half width) unless ``options`` give them. One step is one control period of the
engine (1/33 s; in effect 35 ms, the physics step being 5 ms). The episode terminates on a goal (either
goal) or the ball going out, and is truncated after ``max_steps`` steps or when the referee drops the ball
(a still ball contested for 5 s).

Observation (``Box`` float32, the learner's team frame: its own goal at -x, the goal it attacks at +x; SI
units; true state; clipped to the bounds): indices 0-11 ``observations.own_block`` (x, y [m], cos_theta,
sin_theta, vx, vy [m/s], w [rad/s], ball_dx, ball_dy [m] relative to the robot, ball_vx, ball_vy [m/s],
holding 0/1), 12-13 goalie_x, goalie_y [m] (the opponents' goalie, absolute), 14 time_left (1 at reset,
0 at ``max_steps``). Action: ``actions.action_space`` ([vx, vy, w] body frame, dribble, kick).
Reward: ``reward_fn(prev_obs, obs, info)``, default ``rewards.ScoreReward()``. Info: goal (+1 scored, -1
own goal, 0), ball_progress [m] (how much closer the ball came to the attacked goal's centre; the whole
remaining distance on a goal, 0 when the referee moved the ball), ball_to_goal [m], holding, end ("" or
"goal", "out", "dropped ball", "time"), time [s, sim time], engine_seed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np

from nubot_common.geometry import Pose2D
from nubot_common.naming import parse_robot_name
from nubot_common.packages import package_path
from nubot_common.team_frame import TeamFrame
from nubot_match import NubotMatchError
from nubot_match.config import match_config
from nubot_match.engine import LockstepMatch
from nubot_match.envs import match_adapter as adapter
from nubot_match.envs.actions import action_space, to_command
from nubot_match.envs.observations import OWN_NAMES, Layout, own_block
from nubot_match.envs.rewards import RewardFn, ScoreReward
from sim_visual.simulator import GoalScored, Simulator

CONFIG = package_path("nubot_match") / "config"
LONGEST_HALF = 4 * 3600.0  # the game clock never ends an episode [s]
ENGINE_SEEDS = 2**31 - 1  # engine seeds are drawn from [0, this)
ROBOT_BACK, BALL_FRONT, BALL_BACK = 3.0, 1.0, 2.5  # start area: x in [0, L-3] robot, [1, L-2.5] ball [m]
ROBOT_SIDE, BALL_SIDE = 1.0, 1.5  # ... |y| <= W minus this [m]
MIN_BALL_DISTANCE = 1.0  # the ball starts at least this far from the robot centre [m]


class ScoreAgainstGoalieEnv(gymnasium.Env):  # Env[np.ndarray, np.ndarray]: Debian's mypy 1.0 misreads the parameters
    metadata: dict[str, Any] = {"render_modes": [], "render_fps": 33}

    def __init__(self, render_mode: str | None = None, *, max_steps: int = 300, reward_fn: RewardFn | None = None,
                 attack: int = 1, learner: str = "nubot1", home: str | Path = CONFIG / "score_attacker.yaml",
                 away: str | Path = CONFIG / "score_goalie.yaml", field: str | Path = "18x12", tracker: str = ""):
        """``attack``: the world goal the learner's team attacks (1 at +x, -1 at -x: the ends swapped)."""
        if render_mode is not None:
            raise NubotMatchError(f"render_mode must be None (no viewer yet), got {render_mode!r}")
        if max_steps < 1:
            raise NubotMatchError(f"max_steps must be at least 1, got {max_steps}")
        if attack not in (1, -1):
            raise NubotMatchError(f"attack must be 1 (the goal at +x) or -1 (the goal at -x), got {attack!r}")
        config = match_config(home, away, field, tracker, half_seconds=LONGEST_HALF, halves=1)
        if learner not in config.robot_names:
            raise NubotMatchError(f"learner {learner!r} does not play in this match ({', '.join(config.robot_names)})")
        self.team = parse_robot_name(learner).team
        if next(t.config.attack for t in config.teams if t.config.prefix == self.team) != attack:
            config = config.swapped()
        other = next(t.config for t in config.teams if t.config.prefix != self.team)
        self.learner, self.goalie = learner, f"{other.prefix}{other.goalie}"
        self.frame = TeamFrame(attack)
        self.field = config.world.field
        self.plugin = config.sim.sim.plugin
        self.max_steps = max_steps
        self.reward_fn: RewardFn = ScoreReward()
        if reward_fn is not None:
            self.reward_fn = reward_fn
        self.render_mode = render_mode
        self.match = LockstepMatch(config, external=[learner])
        self.layout = Layout((*OWN_NAMES, "goalie_x", "goalie_y", "time_left"), self.field, self.plugin)
        self.observation_space = self.layout.space
        self._actions = action_space(self.plugin)
        self.action_space = self._actions
        self._steps = 0
        self._obs: np.ndarray | None = None
        self._over = True
        self._engine_seed = 0

    # --- the episode ------------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None,
              options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict[str, Any]]:
        """Options: ``robot`` (x, y, theta) and ``ball`` (x, y), team frame [m], [rad], instead of random ones."""
        super().reset(seed=seed)
        options = dict(options or {})
        robot, ball = self._start(options.pop("robot", None), options.pop("ball", None))
        if options:
            raise NubotMatchError(f"unknown reset options {sorted(options)}; known: robot, ball")
        self._engine_seed = int(self.np_random.integers(ENGINE_SEEDS))
        self.match.reset(self._engine_seed)
        adapter.start_play_now(self.match)
        pose = self.frame.pose_to_world(Pose2D(*robot))
        adapter.place_robot(self.match, self.learner, pose.x, pose.y, pose.theta)
        adapter.place_ball(self.match, *self.frame.point_to_world(*ball))
        self._steps, self._over = 0, False
        self._obs = self._observe()
        return self._obs, self._info(0, 0.0, "")

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        if self._obs is None or self._over:
            raise NubotMatchError("the episode is over (or never began): call reset() first")
        command = to_command(action, self._actions, self.plugin, self.learner)
        before = self._ball_to_goal()
        out = self.match.step({self.learner: command})
        self._steps += 1
        goals = [e.side for e in out.events if isinstance(e, GoalScored)]
        end = "goal" if goals else adapter.interruption(out.decisions)
        if not end and (self._steps >= self.max_steps or out.done):
            end = "time"
        goal = sum(1 if side == self.frame.attack else -1 for side in goals)
        # The referee may already have put the ball back: only a step that play went on through is measured.
        progress = before if end == "goal" else 0.0 if end else before - self._ball_to_goal()
        prev, self._obs = self._obs, self._observe()
        info = self._info(goal, progress, end)
        self._over = bool(end)
        terminated = end in ("goal", "out")
        return self._obs, float(self.reward_fn(prev, self._obs, info)), terminated, self._over and not terminated, \
            info

    def render(self) -> None:
        return None

    def close(self) -> None:
        self.match.close()

    # --- helpers ------------------------------------------------------------------------------------
    def _start(self, robot: Sequence[float] | None,
               ball: Sequence[float] | None) -> tuple[tuple[float, float, float], tuple[float, float]]:
        hl, hw, rng = self.field.half_length, self.field.half_width, self.np_random
        if (robot is not None and len(robot) != 3) or (ball is not None and len(ball) != 2):
            raise NubotMatchError(f"reset options: robot is (x, y, theta), ball (x, y); got {robot!r}, {ball!r}")
        if robot is None:
            robot = (rng.uniform(0.0, hl - ROBOT_BACK), rng.uniform(-(hw - ROBOT_SIDE), hw - ROBOT_SIDE),
                     rng.uniform(-math.pi, math.pi))
        while ball is None:  # rejection sampling: most of the area lies far enough from the robot
            drawn = (rng.uniform(BALL_FRONT, hl - BALL_BACK), rng.uniform(-(hw - BALL_SIDE), hw - BALL_SIDE))
            ball = drawn if math.dist(drawn, robot[:2]) >= MIN_BALL_DISTANCE else None
        for what, x, y in (("robot", robot[0], robot[1]), ("ball", ball[0], ball[1])):
            if not self.field.is_inside(float(x), float(y)):
                raise NubotMatchError(f"the {what} start ({x:g}, {y:g}) m is off the field")
        return (float(robot[0]), float(robot[1]), float(robot[2])), (float(ball[0]), float(ball[1]))

    def _ball_to_goal(self) -> float:
        ball = self._sim().world.ball_state()
        x, y = self.frame.point_to_team(ball.x, ball.y)
        return math.hypot(self.field.half_length - x, y)

    def _sim(self) -> Simulator:
        assert self.match.sim is not None, "reset() builds the simulator"
        return self.match.sim

    def _observe(self) -> np.ndarray:
        sim = self._sim()
        world = sim.world
        own = own_block(self.frame, world.robot_state(self.learner), world.ball_state(), sim.holder == self.learner)
        goalie = world.robot_state(self.goalie)
        gx, gy = self.frame.point_to_team(goalie.x, goalie.y)
        return self.layout.vector([*own, gx, gy, 1.0 - self._steps / self.max_steps])

    def _info(self, goal: int, progress: float, end: str) -> dict[str, Any]:
        sim = self._sim()
        return {"goal": goal, "ball_progress": progress, "ball_to_goal": self._ball_to_goal(),
                "holding": sim.holder == self.learner, "end": end, "time": sim.time,
                "engine_seed": self._engine_seed}

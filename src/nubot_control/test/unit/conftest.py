"""An in-process match: the simulator core and one Strategy per robot, no ROS (fast behaviour tests)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import pytest

from nubot_common.geometry import Pose2D, wrap_angle
from nubot_common.match_mode import MatchMode
from nubot_control.params import ControlParams, PlayParams
from nubot_control.roles import Role
from nubot_control.strategy import ControlOutput, Strategy
from nubot_control.team_state import Ball, Mate, PassPlan, TeamState
from sim_visual.params import NoiseParams, RobotSpawn, SimConfig
from sim_visual.sensing import to_team_frame
from sim_visual.simulator import GoalScored, Simulator, agent_id_of


@dataclass
class InProcessMatch:
    sim: Simulator
    strategies: dict[str, Strategy]
    mode: dict[str, MatchMode]
    previous: dict[str, MatchMode]
    mode_since: float = 0.0
    outputs: dict[str, ControlOutput] = field(default_factory=dict)
    goals: list[GoalScored] = field(default_factory=list)
    roles: dict[str, Role] = field(default_factory=dict)
    role_time: dict[str, float] = field(default_factory=dict)
    pass_plans: dict[str, PassPlan | None] = field(default_factory=dict)

    def team_of(self, name: str) -> str:
        return name.rstrip("0123456789")

    def command(self, team: str, mode: MatchMode) -> None:
        for t in self.mode:
            m = mode if t == team else mode.mirrored()
            self.previous[t], self.mode[t] = self.mode[t], m
        self.mode_since = self.sim.time

    def state_for(self, name: str) -> TeamState:
        sim = self.sim
        attack = sim.plugins[name].spawn.attack
        team = self.team_of(name)

        def mate(n: str) -> Mate:
            s = sim.world.robot_state(n)
            x, y = to_team_frame(s.x, s.y, attack)
            vx, vy = to_team_frame(s.vx, s.vy, attack)
            theta = s.theta if attack == 1 else wrap_angle(s.theta + math.pi)
            return Mate(agent_id_of(n), Pose2D(x, y, theta), vx, vy, self.roles.get(n, Role.NOROLE),
                        sim.time - self.role_time.get(n, 0.0), sim.holder == n)

        b = sim.world.ball_state()
        bx, by = to_team_frame(b.x, b.y, attack)
        bvx, bvy = to_team_frame(b.vx, b.vy, attack)
        mates = tuple(mate(n) for n in sim.plugins if n != name and self.team_of(n) == team)
        opponents = tuple(to_team_frame(sim.world.robot_state(n).x, sim.world.robot_state(n).y, attack)
                          for n in sim.plugins if self.team_of(n) != team)
        plan = next((p for n, p in self.pass_plans.items() if p is not None and self.team_of(n) == team), None)
        return TeamState(sim.time, mate(name), mates, Ball(bx, by, bvx, bvy), opponents, self.mode[team],
                         self.previous[team], self.mode_since, plan)

    def run(self, seconds: float) -> None:
        end = self.sim.time + seconds
        next_control = self.sim.time
        while self.sim.time < end:
            if self.sim.time >= next_control - 1e-9:
                next_control += 1.0 / 33.0
                for name, strategy in self.strategies.items():
                    out = strategy.step(self.state_for(name))
                    self.outputs[name] = out
                    if out.role != self.roles.get(name):
                        self.roles[name], self.role_time[name] = out.role, self.sim.time
                    self.pass_plans[name] = out.pass_plan
                    self.sim.command_velocity(name, out.vx, out.vy, out.w)
                    self.sim.ball_handle(name, 1 if out.dribble else 0)
                    if out.kick is not None:
                        self.sim.shoot(name, *out.kick)
            self.goals += [e for e in self.sim.step() if isinstance(e, GoalScored)]


@pytest.fixture
def make_match():
    """Build an in-process match: ``robots`` as (name, x, y, theta) world poses; nubot attacks +x."""
    def build(robots, ball=(0.0, 0.0), mode=MatchMode.STARTROBOT, goalie_id=1, seed=0):
        spawns = tuple(RobotSpawn(n, x, y, th, 1 if n.startswith("nubot") else -1) for n, x, y, th in robots)
        sim = Simulator(SimConfig(robots=spawns, ball_start=ball, seed=seed, noise=NoiseParams(0, 0, 0, 0)))
        params = ControlParams(play=PlayParams(goalie_id=goalie_id))
        strategies = {s.name: Strategy(params, agent_id_of(s.name)) for s in spawns}
        teams = {n.rstrip("0123456789") for n, *_ in robots}
        return InProcessMatch(sim, strategies, {t: mode for t in teams}, {t: MatchMode.STOPROBOT for t in teams})
    return build

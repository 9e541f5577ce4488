"""An in-process match: the simulator core and one RobotAgent per robot, no ROS (fast behaviour tests).

Each robot runs the whole pipeline of a ROS match: its simulated vision at 30 Hz, its world model
fusing that with its teammates' packets and strategies (delivered one control cycle late, as the
team link does) and the coach's commands, and its controller at 33 Hz, whose commands go to the
simulator through the robot interface (velocity, BallHandle requests, Shoot).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import pytest

from nubot_common.match_mode import MatchMode
from nubot_common.naming import parse_robot_name, team_of
from nubot_common.percepts import RobotView
from nubot_common.schedule import Periodic
from nubot_common.team_play import StrategyReport
from nubot_common.world_description import WorldDescription
from nubot_control.agent import AgentStep, RobotAgent
from nubot_control.params import ControlParams, PlayParams
from sim_visual.host import SensorSchedule
from sim_visual.params import NoiseParams, RobotSpawn, SimConfig, SimNodeParams
from sim_visual.simulator import GoalScored, Simulator

CONTROL_PERIOD = 1.0 / ControlParams().rate  # [s] the robots' control cycle


_team_of = functools.cache(team_of)  # parsed once per name: the team link asks for every pair of robots every cycle


@dataclass
class InProcessMatch:
    sim: Simulator
    agents: dict[str, RobotAgent]
    mode: dict[str, MatchMode]
    outputs: dict[str, StrategyReport] = field(default_factory=dict)  # each robot's latest strategy report
    steps: dict[str, AgentStep] = field(default_factory=dict)
    goals: list[GoalScored] = field(default_factory=list)
    _packets: dict[str, tuple[RobotView | None, StrategyReport]] = field(default_factory=dict)
    _sensors: SensorSchedule = field(default_factory=lambda: SensorSchedule(SimNodeParams()))  # the sim node's
    _control: Periodic = field(default_factory=lambda: Periodic(CONTROL_PERIOD))

    def team_of(self, name: str) -> str:
        return _team_of(name)

    def command(self, team: str, mode: MatchMode) -> None:
        """The coach's command to ``team``; the other team gets the mirrored one (as the referee sends them)."""
        for t in self.mode:
            m = mode if t == team else mode.mirrored()
            previous, self.mode[t] = self.mode[t], m
            for name, agent in self.agents.items():
                if self.team_of(name) == t:
                    agent.on_coach(self.sim.time, int(m), int(previous))

    def _deliver(self) -> None:
        """The team link: every robot's last packet and strategy to its teammates."""
        t = self.sim.time
        for sender, (packet, report) in self._packets.items():
            for name, agent in self.agents.items():
                if name != sender and self.team_of(name) == self.team_of(sender):
                    if packet is not None:
                        agent.on_teammate(t, packet)
                    agent.on_teammate_strategy(t, report)

    def run(self, seconds: float) -> None:
        end = self.sim.time + seconds
        while self.sim.time < end:
            t = self.sim.time
            if self._sensors.vision.due(t):
                for name, agent in self.agents.items():
                    agent.on_vision(self.sim.observe(name))
            if self._control.due(t):
                self._deliver()
                for name, agent in self.agents.items():
                    step = agent.step(t)
                    self.steps[name], self.outputs[name] = step, step.report
                    self._packets[name] = (step.packet, step.report)
                    self.sim.execute(name, step.command)
            self.goals += [e for e in self.sim.step() if isinstance(e, GoalScored)]


@pytest.fixture
def make_match():
    """Build an in-process match: ``robots`` as (name, x, y, theta) world poses; nubot attacks +x."""
    def build(robots, ball=(0.0, 0.0), mode=MatchMode.STARTROBOT, goalie_id=1, seed=0,
              world: WorldDescription | None = None):
        world = world or WorldDescription()
        spawns = tuple(RobotSpawn(n, x, y, th, 1 if n.startswith("nubot") else -1) for n, x, y, th in robots)
        sim = Simulator(SimConfig(world=world, robots=spawns, ball_start=ball, seed=seed,
                                  noise=NoiseParams(0, 0, 0, 0)))
        control = ControlParams(play=PlayParams(goalie_id=goalie_id))
        agents = {s.name: RobotAgent(parse_robot_name(s.name), world, control=control) for s in spawns}
        teams = {parse_robot_name(n).team for n, *_ in robots}
        match = InProcessMatch(sim, agents, dict.fromkeys(teams, MatchMode.STOPROBOT))
        match.command(sorted(teams)[0], mode)
        return match
    return build

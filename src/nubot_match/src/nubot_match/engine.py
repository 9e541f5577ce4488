"""The lockstep engine: a whole refereed match in one process, without ROS, from the nodes' own cores.

Requires: a ``MatchConfig`` (``nubot_match.config``) and a seed. Provides: ``LockstepMatch``:
``reset(seed)`` builds the match (the ``Simulator`` with both teams at their start poses, one
``RobotAgent`` per robot with its team's ``ControlParams`` and strategy, a ``TeamRelay`` per team, the
``AutomaticReferee``); ``step()`` runs one control period; ``run()`` plays to the end. Every physics
step (``sim.physics.step_size`` <= 7 ms) the schedule runs, in sim time, what the ROS match runs:

- every robot's omni vision at ``vision_rate`` (30 Hz), into its world model, and each team's goalie
  (AgentID ``play.goalie_id``) also its RGB-D cameras' ball in 3-D (``Simulator.observe_ball3d``);
- every robot's control cycle at its ``ControlParams.rate`` (33 Hz): teammates' packets and strategies
  from the relay (what the last cycle shared, as the relay node hands them on), ``RobotAgent.step``, and
  its commands through the robot interface (velocity, BallHandle, Shoot);
- the referee every ``referee_period`` (30 ms) on the latest model states and the robot holding the ball, its
  decisions applied as the referee node applies them (ball placed, ends switched, commands to every robot's world
  model, its calls (fouls, disallowed goals) to the listeners);
- the listeners (``nubot_match.record``): model states and /clock at ``model_states_rate`` (100 Hz),
  every simulator event, the referee's state on change and every second, coach commands on change.

``external`` robots are not driven by their agent: their command comes with ``step(actions)`` (the
Gymnasium/PettingZoo environments); their world model still runs, so their teammates still hear them.
All randomness is the simulator's one generator, seeded by ``reset(seed)``: a seed gives one match.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, replace

from coach4sim.game import GameController, GameStateData
from coach4sim.params import TeamSpec
from coach4sim.referee import AutomaticReferee, Phase, RefereeDecision, RefereeInputs
from nubot_comm.relay import TeamRelay
from nubot_common.commands import RobotCommand
from nubot_common.match_mode import MatchMode
from nubot_common.naming import parse_robot_name
from nubot_common.percepts import RobotView
from nubot_common.schedule import EPS, Periodic
from nubot_common.team_play import StrategyReport
from nubot_control.agent import AgentStep, RobotAgent
from nubot_match import NubotMatchError
from nubot_match.config import MatchConfig
from nubot_match.record import MatchListener
from sim_visual.host import SensorSchedule
from sim_visual.params import RobotSpawn, SimConfig
from sim_visual.simulator import BallKicked, BallTouched, GoalScored, SimEvent, Simulator
from sim_visual.world import BallState

STATE_PERIOD = 1.0  # the referee's state is recorded at least this often [s] (referee.yaml state_period)


@dataclass
class MatchStep:
    """What one ``step()`` did."""

    time: float  # sim time at its end [s]
    events: list[SimEvent] = field(default_factory=list)  # goals, kicks, touches, captures, releases
    decisions: list[RefereeDecision] = field(default_factory=list)
    refused: list[tuple[str, str, str]] = field(default_factory=list)  # (robot, call, reason): commands the robot
    # interface refused (a NaN velocity, a bad strength), as the simulator node refuses them; the match plays on
    done: bool = False  # the match is over (full time)


class LockstepMatch:
    def __init__(self, config: MatchConfig, listeners: Iterable[MatchListener] = (),
                 external: Iterable[str] = ()):
        self.config = config
        self.listeners = list(listeners)
        self.external = set(external)
        unknown = self.external - set(config.robot_names)
        if unknown:
            raise NubotMatchError(f"external robots {sorted(unknown)} do not play in this match "
                                  f"({', '.join(config.robot_names)})")
        self.sim: Simulator | None = None
        self.agents: dict[str, RobotAgent] = {}
        self.steps: dict[str, AgentStep] = {}  # each robot's latest control cycle
        self.refused_commands = 0  # calls of the robot interface refused since reset (MatchStep.refused: which)
        self.goalies: frozenset[str] = frozenset()  # each team's goalie: it also sees the ball in 3-D
        self.seed: int | None = None

    # --- set-up ----------------------------------------------------------------------------------
    def reset(self, seed: int = 0) -> GameStateData:
        """Build the match anew from ``seed`` (kick-off of the first half comes with the first step)."""
        cfg = self.config.with_seed(seed)
        self.seed = seed
        spawns = tuple(RobotSpawn(name, x, y, yaw, t.config.attack)
                       for t in cfg.teams for name, x, y, yaw in t.config.world_poses())
        s = cfg.sim.sim
        self.sim = Simulator(SimConfig(world=cfg.world, physics=s.physics, plugin=s.plugin, noise=s.noise,
                                       robots=spawns, ball_start=s.ball_start, seed=s.seed))
        self.agents = {}
        self.control_period: dict[str, float] = {}
        for team in cfg.teams:
            for name in team.config.robot_names():
                robot = parse_robot_name(name)
                self.agents[name] = RobotAgent(robot, cfg.world, cfg.world_model, team.control_of(robot.agent_id))
                self.control_period[name] = 1.0 / team.control.rate
        self.team_of = {name: parse_robot_name(name).team for name in self.agents}
        self.goalies = frozenset(name for team in cfg.teams for name in team.config.robot_names()
                                 if parse_robot_name(name).agent_id == team.control.play.goalie_id)
        self.members = {t.config.prefix: tuple(t.config.robot_names()) for t in cfg.teams}
        self.packets = {team: TeamRelay[RobotView](team, names, cfg.relay_max_age)
                        for team, names in self.members.items()}
        self.strategies = {team: TeamRelay[StrategyReport](team, names, cfg.relay_max_age)
                           for team, names in self.members.items()}
        self.game = GameController([TeamSpec(t.config.prefix, t.config.attack, t.config.goalie) for t in cfg.teams])
        self.referee = AutomaticReferee(cfg.referee, self.game)
        self.steps = {}
        self.refused_commands = 0  # calls of the robot interface refused since reset (MatchStep.refused: which)
        self._sensors = SensorSchedule(cfg.sim)  # the simulator node's: its percept and model-state clocks
        self._control = {period: Periodic(period) for period in set(self.control_period.values())}
        self._judge = Periodic(cfg.referee_period)
        self._state_out = Periodic(STATE_PERIOD)
        self._sent: dict[str, tuple[MatchMode, MatchMode]] = {}
        self._published: GameStateData | None = None
        self._inputs = RefereeInputs()  # what the steps' events told since the last referee tick
        for listener in self.listeners:
            listener.start(cfg.world, 0.0)
        return self.game.state()

    def _require_sim(self) -> Simulator:
        if self.sim is None:
            raise NubotMatchError("call reset(seed) before stepping the match")
        return self.sim

    # --- state ----------------------------------------------------------------------------------
    @property
    def time(self) -> float:
        return self._require_sim().time

    @property
    def done(self) -> bool:
        return self.sim is not None and self.referee.phase is Phase.FINISHED

    def state(self) -> GameStateData:
        return self.game.state()

    # --- commands ----------------------------------------------------------------------------------
    def command(self, team: str, mode: MatchMode | int | str) -> str:
        """A coach command by hand (``/referee/command``); raises ``NubotCommonError`` if it is invalid."""
        text = self.referee.manual_command(team, mode, self.time)
        self._coach_all()
        return text

    # --- stepping -----------------------------------------------------------------------------------
    def step(self, actions: Mapping[str, RobotCommand] | None = None,
             seconds: float | None = None) -> MatchStep:
        """Advance to just before the next control cycle (``seconds`` [s] of sim time if given): one call holds
        exactly one control cycle of the fastest robots; ``actions`` drive the external robots in it."""
        sim = self._require_sim()
        if actions:
            stray = set(actions) - self.external
            if stray:
                raise NubotMatchError(f"actions for robots that are not external: {sorted(stray)}")
        if seconds is not None and not seconds > 0.0:
            raise NubotMatchError(f"seconds must be positive, got {seconds}")
        end = sim.time + seconds if seconds is not None else math.inf
        out = MatchStep(sim.time)
        while True:
            self._physics_step(actions or {}, out)
            if self.done or sim.time + EPS >= end:
                break
            if seconds is None and min(s.next for s in self._control.values()) <= sim.time + EPS:
                break
        out.time, out.done = sim.time, self.done
        return out

    def run(self, until: float | None = None, progress: Callable[[LockstepMatch], None] | None = None,
            progress_period: float = 10.0) -> GameStateData:
        """Play to full time (or to sim time ``until`` [s]); call ``progress`` every ``progress_period`` [s]."""
        sim = self._require_sim()
        ticker = Periodic(progress_period, sim.time)
        out = MatchStep(sim.time)
        while not self.done and (until is None or sim.time + EPS < until):
            self._physics_step({}, out)
            out.events.clear()
            out.decisions.clear()
            out.refused.clear()
            if progress is not None and ticker.due(sim.time):
                progress(self)
        return self.game.state()

    def close(self) -> None:
        """Close every listener (a bag is complete only then); also on leaving a ``with`` block."""
        for listener in self.listeners:
            listener.close()

    def __enter__(self) -> LockstepMatch:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def _physics_step(self, actions: Mapping[str, RobotCommand], out: MatchStep) -> None:
        sim = self._require_sim()
        t = sim.time
        if self._judge.due(t):
            self._referee_tick(t, out)
        if self._sensors.vision.due(t):
            for (name, agent), view in zip(self.agents.items(), sim.observe_all(self.agents)):
                agent.on_vision(view)
                if name in self.goalies:  # its own generator: draws nothing from the one above
                    agent.on_ball3d(sim.observe_ball3d(name))
                for listener in self.listeners:
                    listener.vision(name, view)
        due = [p for p, schedule in self._control.items() if schedule.due(t)]
        if due:
            self._control_cycle(t, set(due), actions, out)
        events = sim.step()
        self._note_events(events, out)
        if self._sensors.states.due(sim.time):
            states = sim.model_states()
            for listener in self.listeners:
                listener.clock(sim.time)
                listener.model_states(sim.time, states)

    def _control_cycle(self, t: float, due: set[float], actions: Mapping[str, RobotCommand],
                       out: MatchStep) -> None:
        names = [n for n in self.agents if self.control_period[n] in due]
        heard: dict[str, tuple[list[RobotView], list[StrategyReport]]] = {}  # each team's, the same for all its robots
        for name in names:  # the team link: what every teammate shared up to the previous cycle (own: ignored)
            team, agent = self.team_of[name], self.agents[name]
            if team not in heard:
                heard[team] = self.packets[team].collect(t), self.strategies[team].collect(t)
            packets, reports = heard[team]
            for packet in packets:
                agent.on_teammate(t, packet)
            for report in reports:
                agent.on_teammate_strategy(t, report)
        for name in names:
            step = self.agents[name].step(t)
            self.steps[name] = step
            team = self.team_of[name]
            if step.packet is not None:
                self.packets[team].put(name, t, step.packet)
            self.strategies[team].put(name, t, step.report)
            if name in self.external:  # what the robot did is the action, not its agent's wish
                command = actions.get(name) or RobotCommand()
                step = replace(step, command=command)
            self._apply(name, step.command, out)
            for listener in self.listeners:
                listener.robot_step(t, name, step)

    def _apply(self, name: str, command: RobotCommand, out: MatchStep) -> None:
        def refused(call: str, reason: str) -> None:
            self.refused_commands += 1
            out.refused.append((name, call, reason))

        _done, event = self._require_sim().execute(name, command, refused)
        if event is not None:
            self._note_events([event], out)

    def _note_events(self, events: list[SimEvent], out: MatchStep) -> None:
        for event in events:
            out.events.append(event)
            if isinstance(event, GoalScored):
                self._inputs.goal(event.side, event.last_touch)
            elif isinstance(event, BallKicked):
                self._inputs.kick(event.robot)
            elif isinstance(event, BallTouched):
                self._inputs.touch(event.robot)
            for listener in self.listeners:
                listener.sim_event(event)

    # --- the referee ---------------------------------------------------------------------------------
    def _referee_tick(self, t: float, out: MatchStep) -> None:
        sim = self._require_sim()
        ball = sim.world.ball_state()
        robots = {n: (s.x, s.y) for n, s in ((n, sim.world.robot_state(n)) for n in self.agents)}
        self._inputs.last_touch, self._inputs.holder = sim.last_touch, sim.holder or ""  # the simulator knows them
        snapshot = self._inputs.snapshot(t, (ball.x, ball.y, ball.z), robots)
        decision = self.referee.update(snapshot)
        if decision is not None:
            out.decisions.append(decision)
            for call in decision.calls:
                for listener in self.listeners:
                    listener.referee_call(call)
            if decision.switch_ends:
                sim.switch_ends()
            if decision.ball is not None:
                r = self.config.world.ball.radius
                sim.set_model_state(self.config.world.ball_name, BallState(*decision.ball, r, 0.0, 0.0, 0.0))
        self._coach_all()
        state = self.game.state()
        changed = self._published is None or state.without_clock() != self._published.without_clock()
        if self._state_out.due(t) or changed:
            self._published = state
            for listener in self.listeners:
                listener.game_state(t, state)

    def _coach_all(self) -> None:
        """Each team's command to its robots' world models when it changed (CoachInfo, MatchType = previous)."""
        t = self._require_sim().time
        for status in self.game.teams:
            team = status.spec.prefix
            now = (status.mode, status.previous)
            if self._sent.get(team) == now:
                continue
            self._sent[team] = now
            for name in self.members[team]:
                self.agents[name].on_coach(t, int(status.mode), int(status.previous))
            for listener in self.listeners:
                listener.coach(t, team, status.mode, status.previous)

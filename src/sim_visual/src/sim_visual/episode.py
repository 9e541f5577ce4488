"""In-process runs of the simulator without ROS (tests, benchmarks, batch experiments).

Provides: ``run_demo_episode`` which steps a ``Simulator`` and drives one robot with
``DemoBehaviour`` through the same interface the ROS nodes use (omni-vision frames
at 30 Hz, commands at 33 Hz, ball-handle and shoot requests), and returns an
``EpisodeLog`` (robot and ball trajectories, transitions, events).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from sim_visual.demo import DemoBehaviour, DemoParams, DemoState
from sim_visual.simulator import GoalScored, SimEvent, Simulator

VISION_PERIOD = 1.0 / 30.0  # [s]
CONTROL_PERIOD = 1.0 / 33.0  # [s]


@dataclass
class EpisodeLog:
    times: list[float] = field(default_factory=list)
    robot: list[tuple[float, float, float]] = field(default_factory=list)  # x, y, theta (world)
    ball: list[tuple[float, float, float]] = field(default_factory=list)  # x, y, z (world)
    transitions: list[tuple[float, str, str]] = field(default_factory=list)
    events: list[SimEvent] = field(default_factory=list)

    @property
    def goals(self) -> list[GoalScored]:
        return [e for e in self.events if isinstance(e, GoalScored)]


def run_demo_episode(sim: Simulator, robot: str, params: DemoParams, duration: float,
                     stop_at_home: bool = True) -> EpisodeLog:
    """Run the demo behaviour on ``robot`` for up to ``duration`` seconds of sim time."""
    demo = DemoBehaviour(params, sim.config.field)
    log = EpisodeLog()
    frame = sim.observe(robot)
    next_vision, next_control = 0.0, 0.0
    while sim.time < duration:
        if sim.time >= next_vision:
            frame = sim.observe(robot)
            next_vision += VISION_PERIOD
        if sim.time >= next_control:
            next_control += CONTROL_PERIOD
            now = replace(frame, stamp=sim.time, robot=replace(frame.robot, holding=sim.holder == robot))
            command, transitions = demo.step(now)
            log.transitions += [(sim.time, a.value, b.value) for a, b in transitions]
            done, event = sim.execute(robot, command)
            if event is not None:
                log.events.append(event)
            if not done:
                demo.kick_failed()
            if stop_at_home and demo.state == DemoState.HOME:
                break
        log.events += sim.step()
        state, ball_state = sim.world.robot_state(robot), sim.world.ball_state()
        log.times.append(sim.time)
        log.robot.append((state.x, state.y, state.theta))
        log.ball.append((ball_state.x, ball_state.y, ball_state.z))
    return log

import pytest

from nubot_hwcontrol.controller import HardwareController, HwControlParams
from nubot_hwcontrol.sim_drive import SimulatedDrive
from nubot_hwcontrol.sim_world import SimulatorWorld
from sim_visual.params import RobotSpawn, SimConfig
from sim_visual.simulator import Simulator


class Rig:
    """A robot of a real simulator, driven through the simulated drive by the hardware controller at 50 Hz."""

    def __init__(self, start=(-3.0, 0.0, 0.0), ball=(3.0, 3.0), goalie=False, seed=0, params=None):
        params = params or HwControlParams()
        self.sim = Simulator(SimConfig(robots=(RobotSpawn("nubot1", *start),), ball_start=ball, seed=seed))
        self.drive = SimulatedDrive(SimulatorWorld(self.sim, "nubot1"), params.layout(goalie), seed=seed)
        self.ctl = HardwareController(params, self.drive, goalie)
        self.period = 1.0 / params.rate
        self._next = 0.0

    def run(self, seconds, command=None, each=None):
        """Step for ``seconds``; before each control cycle ``command(t)`` gives (vx, vy, w) and ``each(t, report)``
        sees its report."""
        end = self.sim.time + seconds
        while self.sim.time < end - 1e-9:
            if self.sim.time >= self._next - 1e-9:
                t = self.sim.time
                if command is not None:
                    self.ctl.command_velocity(t, *command(t))
                report = self.ctl.cycle(t)
                if each is not None:
                    each(t, report)
                self._next += self.period
            self.sim.step()

    @property
    def truth(self):
        return self.sim.world.robot_state("nubot1")


@pytest.fixture
def rig():
    return Rig

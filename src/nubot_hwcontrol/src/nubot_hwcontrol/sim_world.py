"""The simulated drive's world in this process: a robot of a ``sim_visual`` simulator, driven by its wheels.

Over ROS the hardware node does the same through the simulator node's topics and services (``WheelSpeeds``,
``DriveFeedback``, ``BallHandle``, ``Shoot``). The simulator is typed structurally, so this core does not
import ``sim_visual``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from nubot_common.commands import KickKind
from nubot_common.kinematics import WheelLayout


class SimulatorWorld:
    def __init__(self, sim: Any, name: str):
        self.sim, self.name = sim, name

    def drive(self, layout: WheelLayout, rim_speeds: np.ndarray) -> None:
        self.sim.command_wheels(self.name, layout, rim_speeds)

    def ground_speeds(self, layout: WheelLayout) -> np.ndarray:
        return np.asarray(self.sim.wheel_ground_speeds(self.name, layout))

    def ball_in_handler(self) -> bool:
        return bool(self.sim.holder == self.name)

    def set_dribbling(self, on: bool) -> None:
        self.sim.ball_handle(self.name, int(on))

    def kick(self, speed: float, lob: bool) -> bool:
        done, _ = self.sim.shoot(self.name, speed, KickKind.LOB if lob else KickKind.GROUND)
        return bool(done)

"""The hardware node's parameters (``config/nubot_hwcontrol.yaml`` under the node's private namespace)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from nubot_common import NubotCommonError
from nubot_common.naming import parse_robot_name
from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.backend import BACKENDS
from nubot_hwcontrol.controller import HwControlParams
from nubot_hwcontrol.ethercat import EtherCATParams
from nubot_hwcontrol.sim_drive import SimDriveParams


@dataclass(frozen=True)
class HwNodeParams:
    backend: str = "sim"  # sim: the simulated drive moves robot sim_robot of sim_visual; ethercat: the robot
    goalie: bool = False  # the goalie's wheel layout
    sim_robot: str = ""  # backend sim: the simulator's robot this drive moves, e.g. nubot1
    seed: int = 0  # backend sim: the drive's noise
    status_rate: float = 1.0  # HardwareStatus [Hz]
    control: HwControlParams = field(default_factory=HwControlParams)
    sim_drive: SimDriveParams = field(default_factory=SimDriveParams)
    ethercat: EtherCATParams = field(default_factory=EtherCATParams)

    def __post_init__(self) -> None:
        if self.backend not in BACKENDS:
            raise HardwareError(f"backend must be one of {', '.join(BACKENDS)}, got {self.backend!r}")
        if self.backend == "sim":
            try:
                parse_robot_name(self.sim_robot)
            except (NubotCommonError, ValueError) as exc:
                raise HardwareError(f"backend sim needs sim_robot, the simulator's robot to drive "
                                    f"(e.g. nubot1): {exc}") from exc
        if self.seed < 0:
            raise HardwareError(f"seed must not be negative, got {self.seed}")
        if not (math.isfinite(self.status_rate) and self.status_rate > 0.0):
            raise HardwareError(f"status_rate must be positive, got {self.status_rate}")
        if self.control.odometry.counts_per_revolution != self.sim_drive.counts_per_revolution \
                and self.backend == "sim":
            raise HardwareError("the simulated drive's encoders must have the odometry's counts_per_revolution")

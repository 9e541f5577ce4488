"""The hardware boundary: what the controller reads from and writes to the robot each cycle.

``HardwareBackend`` is implemented by ``sim_drive.SimulatedDrive`` (motor dynamics, encoders, wheel slip, arm
potentiometers; it moves a robot of the simulator by its wheel speeds) and by ``ethercat.EtherCATBackend``
(the Elmo drives and the I/O and AD modules on EtherCAT). ``make_backend`` picks one by name.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any

import numpy as np

from nubot_hwcontrol import HardwareError


@dataclass(frozen=True)
class HardwareState:
    """One cycle's inputs."""

    stamp: float  # when they were read [s]
    encoder_counts: tuple[int, ...]  # each drive's motor shaft counter (32 bit, wrapping)
    arms: tuple[float, float]  # the ball handler's potentiometers, 0 (down) to 1 (up)
    power_on: bool  # the motors have power (the emergency stop is released)


class HardwareBackend(ABC):
    name = "abstract"

    @abstractmethod
    def read(self, now: float) -> HardwareState:
        """The encoders, the arms and the power state now."""

    @abstractmethod
    def write(self, now: float, rim_speeds: np.ndarray, arm_wheels: tuple[float, float]) -> None:
        """Set-points: each base wheel's rim speed and each arm wheel's [m/s]."""

    @abstractmethod
    def set_lever(self, lob: bool) -> None:
        """Move the shooting lever: up for a lob, down for a flat shot."""

    @abstractmethod
    def fire(self, now: float, pulse_ms: float) -> None:
        """Close the relay and fire the solenoid for ``pulse_ms`` milliseconds."""

    @abstractmethod
    def close(self) -> None:
        """Stop the motors and release the interface."""


BACKENDS = ("sim", "ethercat")


def make_backend(name: str, **kwargs: Any) -> HardwareBackend:
    """The backend called ``name``: ``sim`` (needs ``world=``, ``layout=`` and optionally ``params=``, ``seed=``)
    or ``ethercat`` (``interface=``, ``layout=``, optionally ``params=``)."""
    if name == "sim":
        from nubot_hwcontrol.sim_drive import SimulatedDrive

        return SimulatedDrive(**kwargs)
    if name == "ethercat":
        from nubot_hwcontrol.ethercat import EtherCATBackend

        return EtherCATBackend(**kwargs)
    raise HardwareError(f"unknown hardware backend {name!r}; choose one of {', '.join(BACKENDS)}")

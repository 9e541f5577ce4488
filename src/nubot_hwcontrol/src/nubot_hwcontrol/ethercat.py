"""The real robot's hardware on EtherCAT (pysoem): Elmo drives for the four base wheels and the two arm
wheels, an I/O module (shooting lever, kicker relay and IGBT pulse, the emergency stop's state) and an AD
module (the arm potentiometers).

Process data, as the drives and modules are configured (``EtherCATParams``: slave positions and scales):
- Elmo drive (CiA 402, profile velocity): out ControlWord (uint16), TargetVelocity (int32, counts/s); in
  StatusWord (uint16), PositionActual (int32, counts): the encoder the odometry integrates;
- I/O module: out one byte, bit 0 lever up (lob), bit 1 relay, bit 2 IGBT; in one byte, bit 0 power on;
- AD module: in two int16 channels, the arms, ``ad_full_scale`` meaning 1.
The IGBT pulse is timed here, in the cycle that fires it, with a busy wait on the monotonic clock (pulses are
4 to 40 ms; the cycle is 20 ms, so a long pulse delays that one cycle).
Opening fails with ``HardwareError`` naming the interface and the slaves found when they are not the
expected ones: no robot software ever drives an unknown bus.
"""

from __future__ import annotations

import math
import struct
import time
from dataclasses import dataclass, replace

import numpy as np

from nubot_common.kinematics import WheelLayout
from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.backend import HardwareBackend, HardwareState

_SHUTDOWN, _SWITCH_ON, _ENABLE = 0x06, 0x07, 0x0F  # CiA 402 control words
_FAULT_RESET = 0x80
_LEVER, _RELAY, _IGBT = 0x01, 0x02, 0x04


@dataclass(frozen=True)
class EtherCATParams:
    interface: str = "eth0"
    base_drives: tuple[int, ...] = (0, 1, 2, 3)  # slave positions of the wheels' drives, in wheel order
    arm_drives: tuple[int, int] = (4, 5)  # left, right arm wheel drives
    io_module: int = 6
    ad_module: int = 7
    counts_per_revolution: int = 2000  # the drives' encoders
    arm_counts_per_metre: float = 50000.0  # arm wheel drive counts per metre of rim travel
    ad_full_scale: int = 32767
    relay_lead_time: float = 0.005  # the relay closes this long before the IGBT fires [s]

    def __post_init__(self) -> None:
        positions = (*self.base_drives, *self.arm_drives, self.io_module, self.ad_module)
        if len(set(positions)) != len(positions) or min(positions) < 0:
            raise HardwareError(f"EtherCAT slave positions must be distinct and non-negative, got {positions}")
        if self.counts_per_revolution <= 0 or self.arm_counts_per_metre <= 0 or self.ad_full_scale <= 0:
            raise HardwareError("EtherCAT scales must be positive")

    @property
    def slaves(self) -> int:
        return len(self.base_drives) + len(self.arm_drives) + 2


class EtherCATBackend(HardwareBackend):
    name = "ethercat"

    def __init__(self, layout: WheelLayout, params: EtherCATParams | None = None,
                 interface: str | None = None):
        import pysoem

        self.layout = layout
        params = params or EtherCATParams()
        self.params = params if interface is None else replace(params, interface=interface)
        if len(self.params.base_drives) != layout.wheels:
            raise HardwareError(f"{layout.wheels} wheels need {layout.wheels} base drives, "
                                f"got {len(self.params.base_drives)}")
        self._counts_per_metre = (self.params.counts_per_revolution * layout.gear_ratio
                                  / (math.pi * layout.wheel_diameter))
        self._outputs = 0
        self.master = pysoem.Master()
        name = self.params.interface
        try:
            self.master.open(name)
        except (ConnectionError, OSError, pysoem.NetworkInterfaceNotOpenError) as exc:
            raise HardwareError(f"EtherCAT: cannot open network interface {name!r} ({exc}); run as root (raw "
                                f"sockets) and name the robot's EtherCAT port with interface:=<name>") from exc
        found = self.master.config_init()
        if found != self.params.slaves:
            self.master.close()
            raise HardwareError(f"EtherCAT on {name!r}: found {max(found, 0)} slaves, expected {self.params.slaves} "
                                f"({layout.wheels} base drives, 2 arm drives, the I/O and the AD module); check the "
                                f"cable, the power of the drives and the interface name")
        self.master.config_map()
        if self.master.state_check(pysoem.SAFEOP_STATE, 50000) != pysoem.SAFEOP_STATE:
            self.master.close()
            raise HardwareError(f"EtherCAT on {name!r}: the slaves did not reach SAFE-OP")
        self.master.state = pysoem.OP_STATE
        self.master.write_state()
        self.master.send_processdata()
        self.master.receive_processdata(2000)
        if self.master.state_check(pysoem.OP_STATE, 50000) != pysoem.OP_STATE:
            self.master.close()
            raise HardwareError(f"EtherCAT on {name!r}: the slaves did not reach OP")
        self._enable_drives()

    def _drives(self) -> tuple[int, ...]:
        return (*self.params.base_drives, *self.params.arm_drives)

    def _enable_drives(self) -> None:
        for word in (_FAULT_RESET, _SHUTDOWN, _SWITCH_ON, _ENABLE):
            for pos in self._drives():
                self.master.slaves[pos].output = struct.pack("<Hi", word, 0)
            self.master.send_processdata()
            self.master.receive_processdata(2000)
            time.sleep(0.01)

    def read(self, now: float) -> HardwareState:
        self.master.receive_processdata(2000)
        slaves = self.master.slaves
        counts = tuple(struct.unpack_from("<Hi", slaves[p].input)[1] % 2**32 for p in self.params.base_drives)
        raw = struct.unpack_from("<hh", slaves[self.params.ad_module].input)
        arms = tuple(min(1.0, max(0.0, v / self.params.ad_full_scale)) for v in raw)
        power = bool(slaves[self.params.io_module].input[0] & 0x01)
        return HardwareState(now, counts, (arms[0], arms[1]), power)

    def write(self, now: float, rim_speeds: np.ndarray, arm_wheels: tuple[float, float]) -> None:
        slaves = self.master.slaves
        for pos, v in zip(self.params.base_drives, np.asarray(rim_speeds, dtype=float)):
            slaves[pos].output = struct.pack("<Hi", _ENABLE, int(round(v * self._counts_per_metre)))
        for pos, v in zip(self.params.arm_drives, arm_wheels):
            slaves[pos].output = struct.pack("<Hi", _ENABLE, int(round(v * self.params.arm_counts_per_metre)))
        slaves[self.params.io_module].output = bytes([self._outputs])
        self.master.send_processdata()

    def _io(self, bits: int) -> None:
        self._outputs = bits
        self.master.slaves[self.params.io_module].output = bytes([bits])
        self.master.send_processdata()
        self.master.receive_processdata(2000)

    def set_lever(self, lob: bool) -> None:
        self._outputs = (self._outputs | _LEVER) if lob else (self._outputs & ~_LEVER)

    def fire(self, now: float, pulse_ms: float) -> None:
        lever = self._outputs & _LEVER
        self._io(lever | _RELAY)
        time.sleep(self.params.relay_lead_time)
        self._io(lever | _RELAY | _IGBT)
        end = time.monotonic() + pulse_ms / 1000.0
        while time.monotonic() < end:
            pass
        self._io(lever)

    def close(self) -> None:
        import pysoem

        for pos in self._drives():
            self.master.slaves[pos].output = struct.pack("<Hi", _SHUTDOWN, 0)
        self.master.send_processdata()
        self.master.state = pysoem.INIT_STATE
        self.master.write_state()
        self.master.close()

"""The shooting calibration's files and measurements: (pulse, ball speed) pairs from a CSV or from kicks in
the simulator, and the fitted table as the YAML fragment ``nubot_hwcontrol.yaml`` takes.

CSV: a header ``pulse_ms,speed,lever`` (lever ``flat`` or ``lob``), one kick per row; speed is the ball's
speed just after the kick [m/s] (a light barrier or the omni camera's ball track).
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.shooting import CalibrationFit

LEVERS = ("flat", "lob")


def read_measurements(path: str | Path) -> dict[str, list[tuple[float, float]]]:
    """Pairs per lever position; a row that is not two numbers and a lever raises with its line number."""
    out: dict[str, list[tuple[float, float]]] = {lever: [] for lever in LEVERS}
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        missing = {"pulse_ms", "speed", "lever"} - set(reader.fieldnames or ())
        if missing:
            raise HardwareError(f"{path}: the header must name pulse_ms, speed and lever; missing {sorted(missing)}")
        for row in reader:
            line = reader.line_num
            lever = (row["lever"] or "").strip()
            if lever not in LEVERS:
                raise HardwareError(f"{path}:{line}: lever must be flat or lob, got {lever!r}")
            try:
                pulse, speed = float(row["pulse_ms"]), float(row["speed"])
            except (TypeError, ValueError) as exc:
                raise HardwareError(f"{path}:{line}: pulse_ms and speed must be numbers ({exc})") from exc
            if not (math.isfinite(pulse) and math.isfinite(speed)):
                raise HardwareError(f"{path}:{line}: pulse_ms and speed must be finite")
            out[lever].append((pulse, speed))
    return out


def write_measurements(path: str | Path, rows: Sequence[tuple[float, float, str]]) -> None:
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["pulse_ms", "speed", "lever"])
        for pulse, speed, lever in rows:
            writer.writerow([f"{pulse:.3f}", f"{speed:.4f}", lever])


def calibration_yaml(fits: dict[str, CalibrationFit]) -> str:
    """The ``control/calibration`` fragment of ``nubot_hwcontrol.yaml`` for the fitted levers."""
    lines = ["control:", "  calibration:"]
    for lever, fit in fits.items():
        lines += [f"    {lever}:  # v = {fit.v_max:.2f} (1 - exp(-(p - {fit.p0:.2f}) / {fit.tau:.2f})), "
                  f"RMS {fit.rms:.3f} m/s over {fit.samples} kicks",
                  f"      pulse_ms: [{', '.join(f'{p:g}' for p in fit.table.pulse_ms)}]",
                  f"      speed: [{', '.join(f'{v:g}' for v in fit.table.speed)}]"]
    return "\n".join(lines) + "\n"


def simulated_kicks(pulses: Sequence[float], lob: bool, seed: int = 0) -> list[tuple[float, float]]:
    """Kick a ball held by a robot of a fresh simulator with the simulated drive's solenoid at each pulse and
    measure the ball's speed just after: the measurements a team takes on the robot, in simulation."""
    from nubot_hwcontrol.controller import HwControlParams
    from nubot_hwcontrol.sim_drive import SimulatedDrive
    from nubot_hwcontrol.sim_world import SimulatorWorld
    from sim_visual.params import RobotSpawn, SimConfig
    from sim_visual.simulator import Simulator

    out = []
    layout = HwControlParams().regular
    for i, pulse in enumerate(pulses):
        sim = Simulator(SimConfig(robots=(RobotSpawn("nubot1", -6.0, 0.0, 0.0),), ball_start=(-5.57, 0.0),
                                  seed=seed + i))
        if not sim.ball_handle("nubot1", 1):
            raise HardwareError("the simulated robot did not capture the ball placed in its handler")
        drive = SimulatedDrive(SimulatorWorld(sim, "nubot1"), layout, seed=seed + i)
        drive.set_lever(lob)
        drive.fire(sim.time, float(pulse))
        ball = sim.world.ball_state()
        out.append((float(pulse), float(np.hypot(ball.vx, ball.vy)) if not lob else float(drive.kicks[-1][1])))
    return out

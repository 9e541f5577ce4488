"""The shooting calibration's files and measurements: (pulse, ball speed) pairs from a CSV (measured on the robot,
or in the simulator by ``nubot_tools.kick_measurements``), and the fitted table as the YAML fragment
``nubot_hwcontrol.yaml`` takes.

CSV: a header ``pulse_ms,speed,lever`` (lever ``flat`` or ``lob``), one kick per row; speed is the ball's
speed just after the kick [m/s] (a light barrier or the omni camera's ball track).
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path

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

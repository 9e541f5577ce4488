"""``rosrun nubot_tools simulate_kicks kicks.csv``: the kicker's calibration measurements taken in the simulator.

On the robot a team kicks a held ball at a range of solenoid pulses and measures the ball's speed after each; this
does the same with a fresh simulator per kick (the simulated drive of ``nubot_hwcontrol`` firing its solenoid) and
writes the CSV that ``rosrun nubot_hwcontrol fit_shot_calibration`` fits. A tool above both the simulator and
hardware control: the robot's hardware control needs no simulator. Exit status 2 on a bad argument.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

import numpy as np

from nubot_common import NubotCommonError
from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.calibration import LEVERS, write_measurements
from nubot_hwcontrol.controller import HwControlParams
from nubot_hwcontrol.sim_drive import SimulatedDrive
from nubot_hwcontrol.sim_world import SimulatorWorld
from sim_visual.params import RobotSpawn, SimConfig
from sim_visual.simulator import Simulator


def simulated_kicks(pulses: Sequence[float], lob: bool, seed: int = 0) -> list[tuple[float, float]]:
    """Kick a ball held by a robot of a fresh simulator with the simulated drive's solenoid at each pulse and
    measure the ball's speed just after: the measurements a team takes on the robot, in simulation."""
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


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="simulate_kicks", description=__doc__.splitlines()[0])
    ap.add_argument("measurements", help="the CSV to write: pulse_ms,speed,lever per kick")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    pulses = [float(p) for p in np.repeat(np.arange(4.0, 41.0, 4.0), 3)]  # 4..40 ms, three kicks each, per lever
    try:
        rows = [(p, v, lever) for lever in LEVERS for p, v in simulated_kicks(pulses, lever == "lob", args.seed)]
        write_measurements(args.measurements, rows)
    except (NubotCommonError, HardwareError, OSError) as exc:
        print(f"simulate_kicks: {exc}", file=sys.stderr)
        return 2
    print(f"measured {len(rows)} simulated kicks into {args.measurements}")
    return 0

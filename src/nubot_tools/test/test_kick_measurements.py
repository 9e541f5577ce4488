"""The kicker's calibration measured in the simulator (nubot_tools.kick_measurements) and fitted by
nubot_hwcontrol."""

import numpy as np
import pytest

from nubot_hwcontrol.calibration import calibration_yaml, read_measurements, write_measurements
from nubot_hwcontrol.shooting import fit_calibration
from nubot_tools.kick_measurements import main, simulated_kicks


def test_calibrating_the_simulated_kicker_makes_flat_shots_as_fast_as_asked(tmp_path):
    """The whole tool chain: kicks in the simulator, the CSV, the fit, the YAML, then shots at asked speeds."""
    csv = tmp_path / "kicks.csv"
    pulses = np.repeat(np.arange(4.0, 41.0, 6.0), 2)
    write_measurements(csv, [(p, v, "flat") for p, v in simulated_kicks(pulses, lob=False, seed=5)])
    fit = fit_calibration(read_measurements(csv)["flat"])
    assert "flat:" in calibration_yaml({"flat": fit})
    for asked in (4.0, 7.0, 10.0):
        pulse = fit.table.pulse_for(asked)
        measured = np.mean([v for _, v in simulated_kicks([pulse] * 4, lob=False, seed=50)])
        assert measured == pytest.approx(asked, rel=0.06)


def test_the_command_writes_both_levers_kicks_and_refuses_a_folder(tmp_path, capsys):
    csv = tmp_path / "kicks.csv"
    assert main([str(csv), "--seed", "2"]) == 0
    data = read_measurements(csv)
    assert {lever: len(pairs) for lever, pairs in data.items()} == {"flat": 30, "lob": 30}
    assert all(v > 0.0 for pairs in data.values() for _, v in pairs)
    assert main([str(tmp_path)]) == 2
    assert "simulate_kicks:" in capsys.readouterr().err

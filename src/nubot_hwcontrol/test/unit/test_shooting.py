import numpy as np
import pytest

from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.calibration import read_measurements
from nubot_hwcontrol.shooting import FLAT, LOB, Kicker, KickerParams, ShotCalibration, ShotTable, fit_calibration


def test_the_fit_recovers_a_known_kicker_from_noisy_measurements():
    rng = np.random.default_rng(3)
    pulses = np.repeat(np.arange(4.0, 41.0, 2.0), 4)
    speeds = 11.0 * (1.0 - np.exp(-(pulses - 2.0) / 12.0)) * (1.0 + rng.normal(0.0, 0.03, pulses.size))
    fit = fit_calibration(list(zip(pulses, speeds)))
    assert fit.v_max == pytest.approx(11.0, rel=0.05)
    assert fit.tau == pytest.approx(12.0, rel=0.1)
    assert fit.rms < 0.3
    for speed in (3.0, 6.0, 9.0):
        pulse = fit.table.pulse_for(speed)
        assert 11.0 * (1.0 - np.exp(-(pulse - 2.0) / 12.0)) == pytest.approx(speed, rel=0.05)


def test_a_bad_measurement_file_names_the_line(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("pulse_ms,speed,lever\n10,5.0,flat\n12,fast,flat\n")
    with pytest.raises(HardwareError, match=r"bad.csv:3"):
        read_measurements(bad)
    with pytest.raises(HardwareError, match="at least 4"):
        fit_calibration([(10.0, 5.0), (12.0, 6.0)])


def test_tables_must_increase_and_strength_must_be_a_positive_speed():
    with pytest.raises(HardwareError, match="increase"):
        ShotTable((1.0, 2.0, 3.0), (1.0, 3.0, 2.0))
    calibration = ShotCalibration()
    with pytest.raises(HardwareError, match="positive"):
        calibration.pulse_for(0.0, FLAT)
    with pytest.raises(HardwareError, match="ShootPos"):
        calibration.pulse_for(5.0, 0)
    assert calibration.pulse_for(100.0, FLAT) == calibration.flat.pulse_ms[-1]  # clamped to the table


def test_the_kicker_waits_for_the_lever_and_the_capacitor():
    kicker = Kicker(KickerParams(lever_time=0.15, recharge_time=1.0))
    kicker.request(0.0, 6.0, LOB)  # the lever must come up
    assert kicker.poll(0.1) is None
    order = kicker.poll(0.16)
    assert order is not None and order.lob
    kicker.request(0.5, 6.0, LOB)
    assert kicker.poll(0.9) is None  # recharging
    assert kicker.poll(1.17) is not None

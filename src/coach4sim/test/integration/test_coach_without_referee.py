"""The coach CLI over real ROS without a referee: it publishes CoachInfo itself, for --duration and no longer."""

import subprocess
import time

import pytest

pytestmark = pytest.mark.integration

CLI_TIMEOUT = 20.0  # [s, wall]


def test_the_duration_bounds_the_run_even_when_the_period_is_longer(ros_master):
    coach = subprocess.Popen(["rosrun", "coach4sim", "coach", "STOPROBOT", "--team", "lone", "--period", "10",
                              "--duration", "1"], env=ros_master.env, stdout=subprocess.PIPE,
                             stderr=subprocess.DEVNULL, text=True)
    try:
        started = coach.stdout.readline()  # once it publishes, after looking for the referee
        publishing = time.monotonic()
        status = coach.wait(timeout=CLI_TIMEOUT)
        ended = time.monotonic()
    finally:
        coach.kill()
        coach.wait()
        coach.stdout.close()
    assert "publishing STOPROBOT (0) to /lone/receive_from_coach every 10000 ms for 1 s" in started
    assert status == 0
    assert ended - publishing < 1.0 + 1.0, "1 s of publishing and the node's shutdown, not a 10 s period"


@pytest.mark.parametrize(("flag", "value", "message"), [
    ("--period", "1e300", "coach: --period must lie in [0.005, 10] s, got 1e+300"),
    ("--duration", "inf", "coach: --duration must be positive and at most 14400 s, got inf"),
], ids=["period_1e300", "duration_inf"])
def test_an_absurd_period_or_duration_is_a_usage_error(ros_master, flag, value, message):
    result = subprocess.run(["rosrun", "coach4sim", "coach", "STOPROBOT", flag, value], env=ros_master.env,
                            capture_output=True, text=True, timeout=CLI_TIMEOUT)
    assert (result.returncode, result.stderr.strip()) == (2, message)

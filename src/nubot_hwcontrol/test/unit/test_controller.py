import math

import pytest

from nubot_common.kinematics import REGULAR
from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.backend import BACKENDS, make_backend
from nubot_hwcontrol.sim_drive import SimulatedDrive


def test_backend_selection_by_name(rig):
    r = rig()
    backend = make_backend("sim", world=r.drive.world, layout=REGULAR)
    assert isinstance(backend, SimulatedDrive) and backend.name == "sim"
    with pytest.raises(HardwareError, match="unknown hardware backend 'can'; choose one of sim, ethercat"):
        make_backend("can")
    assert BACKENDS == ("sim", "ethercat")


def test_the_ethercat_backend_without_slaves_names_the_interface_and_the_count():
    with pytest.raises(HardwareError, match=r"EtherCAT on 'lo': found 0 slaves, expected 8"):
        make_backend("ethercat", layout=REGULAR, interface="lo")
    with pytest.raises(HardwareError, match="cannot open network interface 'nosuchif0'"):
        make_backend("ethercat", layout=REGULAR, interface="nosuchif0")


@pytest.mark.parametrize("goalie", [False, True], ids=["regular", "goalie"])
def test_the_simulated_drive_moves_the_robot_as_commanded_and_odometry_follows(rig, goalie):
    r = rig(goalie=goalie)
    r.run(3.0, command=lambda t: (1.5, 0.5, 0.3))
    assert r.truth.w == pytest.approx(0.3, abs=0.02)
    speed = math.hypot(r.truth.vx, r.truth.vy)
    assert speed == pytest.approx(math.hypot(1.5, 0.5), abs=0.05)
    odo = r.ctl.odometry.estimate
    assert (odo.vx, odo.vy, odo.w) == pytest.approx((1.5, 0.5, 0.3), abs=0.05)


def test_odometry_drifts_little_along_a_figure_eight(rig):
    r = rig(start=(-1.0, 0.0, 0.0))
    path = []

    def command(t):
        return 2.0, 0.0, 1.2 * math.copysign(1.0, math.sin(2 * math.pi * t / 10.0))

    r.run(20.0, command=command, each=lambda t, rep: path.append((r.truth.x, r.truth.y)))
    travelled = sum(math.dist(a, b) for a, b in zip(path, path[1:]))
    odo, truth = r.ctl.odometry.estimate, r.truth
    error = math.hypot(odo.x - (truth.x + 1.0), odo.y - truth.y)
    assert travelled > 35.0
    assert error / travelled * 10.0 < 0.05  # under 5 cm per 10 m (slip while accelerating)
    assert math.remainder(odo.theta - truth.theta, 2 * math.pi) == pytest.approx(0.0, abs=0.02)


def test_a_robot_pushing_against_the_goal_is_stuck_and_its_odometry_knows(rig):
    r = rig(start=(8.3, 0.0, 0.0))  # in front of the goal at +x of the 18 x 12 field
    stuck = []
    r.run(3.0, command=lambda t: (2.0, 0.0, 0.0), each=lambda t, rep: stuck.append(rep.odometry.stuck))
    assert stuck[-1], "driving into the goal's back for 3 s must read as stuck"


def test_a_silent_control_node_stops_the_base(rig):
    r = rig()
    r.run(1.0, command=lambda t: (1.0, 0.0, 0.0))
    r.run(1.0)  # no more commands
    assert math.hypot(r.truth.vx, r.truth.vy) < 0.01


def test_shooting_needs_the_ball_and_kicks_it_at_the_asked_speed(rig):
    r = rig(start=(-2.0, 0.0, 0.0), ball=(-1.2, 0.0))
    assert r.ctl.shoot(0.0, 6.0, -1) is None  # no ball yet
    r.ctl.ball_handle(1)
    r.run(2.5, command=lambda t: (0.6, 0.0, 0.0) if t < 0.8 else (0.0, 0.0, 0.0))
    assert r.ctl.ball.holding
    assert r.ctl.shoot(r.sim.time, 6.0, -1) == 0.0
    fired = []
    r.run(0.1, each=lambda t, rep: fired.append(rep.fired))
    assert any(fired)
    ball = r.sim.world.ball_state()
    assert math.hypot(ball.vx, ball.vy) == pytest.approx(6.0, rel=0.1)
    with pytest.raises(HardwareError, match="ShootPos"):
        r.ctl.shoot(r.sim.time, 6.0, 3)

"""A hostile user against the real simulator node: absurd values are refused, the node lives on and keeps stepping."""

import math
import re
import subprocess
import time

import pytest

pytestmark = pytest.mark.integration

RUN_TIMEOUT = 30.0  # [s] for a node that must refuse its parameters and exit


def _model_state(name: str, x: float, *, vx: float = 0.0):
    from nubot_common.msg import ModelState

    state = ModelState(model_name=name, reference_frame="world")
    state.pose.position.x, state.pose.position.z, state.pose.orientation.w = x, 0.11, 1.0
    state.twist.linear.x = vx
    return state


def _spawn_nan(sim):
    from geometry_msgs.msg import Pose

    from nubot_common.srv import SpawnModel

    pose = Pose()
    pose.position.x, pose.orientation.w = math.nan, 1.0
    return sim.service("/sim_visual/spawn_model", SpawnModel)("rival1", pose, -1)


def _set(sim, state):
    from nubot_common.srv import SetModelState

    return sim.service("/sim_visual/set_model_state", SetModelState)(state)


@pytest.mark.parametrize(("call", "message"), [
    (lambda sim: _set(sim, _model_state("nubot1", 1e10)), r"nubot1 at \(1e\+10, 0\) is outside the arena"),
    (lambda sim: _set(sim, _model_state("football", 1e10)), r"football at \(1e\+10, 0\) is outside the arena"),
    (lambda sim: _set(sim, _model_state("football", 50.0)), r"football at \(50, 0\) is outside the arena"),
    (lambda sim: _set(sim, _model_state("football", 1.0, vx=1e30)), "football's speed 1e\\+30 m/s exceeds 30 m/s"),
    (_spawn_nan, r"rival1 must be at a finite position, got \(nan, 0.0\)"),
], ids=["robot_x_1e10", "ball_x_1e10", "ball_x_50", "ball_v_1e30", "spawn_x_nan"])
def test_absurd_service_calls_are_refused_and_the_simulator_keeps_stepping(sim, sim_launch, call, message):
    process, _ = sim_launch
    before = {name: sim.state(name) for name in ("nubot1", "football")}
    response = call(sim)
    assert not response.success and re.search(message, response.status_message), response.status_message
    clock = sim.clock
    sim.wait_sim(0.3)
    assert process.alive(), process.log_text()[-3000:]
    assert sim.clock >= clock + 0.3, "the simulator still steps"
    with sim.lock:
        assert set(sim.states) == {"nubot1", "football"}, "nothing spawned"
    for name, state in before.items():
        assert sim.state(name) == pytest.approx(state, abs=1e-6), f"{name} did not move"
    assert not sim.goals


def test_reconfiguration_is_bounded_and_a_huge_command_stays_within_it(sim, sim_launch):
    import dynamic_reconfigure.client

    from sim_visual.params import NOISE_UPPER_BOUNDS, PLUGIN_UPPER_BOUNDS, REAL_TIME_FACTOR_MAX

    process, _ = sim_launch
    client = dynamic_reconfigure.client.Client("/sim_visual", timeout=10)
    try:
        ranges = {d["name"]: d["max"] for d in client.get_parameter_descriptions()}
        assert ranges == {**PLUGIN_UPPER_BOUNDS, **NOISE_UPPER_BOUNDS, "real_time_factor": REAL_TIME_FACTOR_MAX}
        bounded = client.update_configuration({"max_linear_speed": 1e300, "max_linear_accel": 1e300})
        assert (bounded["max_linear_speed"], bounded["max_linear_accel"]) == (10.0, 50.0)
        sim.wait_sim(0.5, command=(1e30, 0.0, 0.0))
        assert process.alive(), process.log_text()[-3000:]
        x, _, _, _, vx, *_ = sim.state("nubot1")
        assert vx == pytest.approx(10.0, abs=0.01) and x < 9.0
    finally:
        client.update_configuration({"max_linear_speed": 5.0, "max_linear_accel": 3.5})
        client.close()
    clock = sim.clock
    sim.wait_sim(1.0)
    assert sim.clock >= clock + 1.0 and process.alive()
    assert all(math.isfinite(v) for v in sim.state("nubot1"))


def test_a_crawling_real_time_factor_can_be_undone(sim, sim_launch):
    """A real_time_factor of 1e-9 set by reconfigure (one sim step per ~80 wall days) must not lock the simulator
    in one long sleep: setting it back to 1 takes effect at once."""
    import dynamic_reconfigure.client

    process, _ = sim_launch
    client = dynamic_reconfigure.client.Client("/sim_visual", timeout=10)
    try:
        client.update_configuration({"real_time_factor": 1e-9})
        time.sleep(1.0)
        client.update_configuration({"real_time_factor": 1.0})
        clock = sim.clock
        deadline = time.monotonic() + 5.0
        while sim.clock < clock + 1.0 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert sim.clock >= clock + 1.0, "the clock runs again at real time"
        assert process.alive()
    finally:
        client.update_configuration({"real_time_factor": 1.0})
        client.close()


def test_a_nan_flood_is_counted_in_a_few_log_lines(sim, sim_launch):
    import rospy

    from nubot_common.msg import VelCmd

    process, _ = sim_launch
    start = len(process.log_text())
    pub = rospy.Publisher("/nubot1/nubotcontrol/velcmd", VelCmd, queue_size=100)
    sent = 0
    try:
        sim.wait_for(lambda: pub.get_num_connections() > 0, timeout=10, what="the simulator to subscribe")
        end = time.monotonic() + 3.0
        while time.monotonic() < end:
            pub.publish(VelCmd(math.nan, 0.0, 0.0))
            sent += 1
            time.sleep(0.0005)  # up to 2000 Hz
    finally:
        pub.unregister()

    def rejections() -> list[str]:
        return [line for line in process.log_text()[start:].splitlines() if "velocity command rejected" in line]

    def counted() -> int:
        counts = [re.search(r"rejected (\d+) time\(s\)", line) for line in rejections()]
        assert all(counts), f"rejection lines without their count: {rejections()[:3]}"
        return sum(int(count[1]) for count in counts)

    # One line at the first NaN, one with the rest of the flood once the reporting interval has passed.
    sim.wait_for(lambda: len(rejections()) >= 2 and counted() >= 100, timeout=10, what="the flood's tail")
    time.sleep(0.5)
    assert sent > 1000
    assert len(rejections()) <= 3, rejections()
    assert all("latest: velocity command must be finite, got Vx=nan" in line for line in rejections())
    assert process.alive()


def test_a_flood_of_refused_shots_is_counted_in_a_few_log_lines(sim, sim_launch):
    """Each refused Shoot once gave a log line of its own (201 lines for 201 calls)."""
    from nubot_common.srv import Shoot

    process, _ = sim_launch
    start = len(process.log_text())
    shoot = sim.service("/nubot1/Shoot", Shoot)
    answers = [shoot(5, 3).ShootIsDone for _ in range(201)]  # ShootPos 3 is no kick
    assert answers == [0] * 201
    sim.wait_for(lambda: "Shoot refused" in process.log_text()[start:], timeout=10, what="the refusals' line")
    lines = [line for line in process.log_text()[start:].splitlines() if "Shoot refused" in line]
    assert 1 <= len(lines) <= 2, lines[:5]
    assert process.alive()


def _rosrun(ros_master, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["rosrun", "sim_visual", *args], env=ros_master.env, capture_output=True, text=True,
                          timeout=RUN_TIMEOUT, check=False)


def test_a_start_pose_off_the_arena_is_a_clear_fatal_error(sim_launch, ros_master):
    result = _rosrun(ros_master, "sim_visual_node", "__name:=hostile_sim",
                     "_sim:={robots: [{name: nubot7, x: 1.0e+12, y: 0.0}]}")
    assert result.returncode == 2, result.stderr[-3000:]
    assert re.search(r"bad parameters: .*nubot7's start at \(1e\+12, 0\) is outside the arena", result.stderr)


@pytest.mark.parametrize(("param", "message"), [
    ("_rate:=0", "rate must be positive, got 0"),
    ("_team_size:=0", r"team_size must lie in \[1, 20\], got 0"),
    ("_team:=nubot-1", "a team prefix is letters and underscores"),
])
def test_sim_interface_refuses_bad_parameters(ros_master, param, message):
    result = _rosrun(ros_master, "sim_interface", "__name:=hostile_relay", param)
    assert result.returncode == 2, result.stderr[-3000:]
    assert re.search(f"sim_interface: bad parameters: .*{message}", result.stderr), result.stderr[-3000:]

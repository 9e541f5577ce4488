"""The simulator node's core: which sensors a robot has, when each output is due, the pacing against the wall
clock, the robots' commands and their throttled refusals, spawning and deleting, and dynamic reconfigure."""

import math

import pytest

from sim_visual.host import CAMERA_PHASES, MAX_LAG, Pacer, RobotSensors, SensorSchedule, SimHost
from sim_visual.params import RobotSpawn, SimConfig, SimNodeParams

STEP = 0.005  # the physics step of SimConfig's default [s]


class FakeClock:
    """A wall clock that moves only when slept on (or moved by hand)."""

    def __init__(self) -> None:
        self.now = 100.0
        self.sleeps: list[float] = []

    def __call__(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.sleeps.append(seconds)
        self.now += seconds


def _params(**overrides) -> SimNodeParams:
    robots = (RobotSpawn("nubot1", -3.0, 0.0), RobotSpawn("nubot2", -1.0, 1.0), RobotSpawn("rival1", 3.0, 0.0, 0, -1))
    return SimNodeParams(sim=SimConfig(robots=robots, ball_start=(0.0, 0.0)), **overrides)


def test_a_robot_has_the_sensors_of_its_place_in_the_team():
    params = SimNodeParams(vision="nubot1,nubot2", goalie_id=1, camera_labels=True)
    goalie_camera, player_camera = RobotSensors.of(params, "nubot1"), RobotSensors.of(params, "nubot2")
    goalie_given, player_given = RobotSensors.of(params, "rival1"), RobotSensors.of(params, "rival2")
    assert goalie_camera == RobotSensors(camera=True, labels=True, ball3d=False, rgbd=True, front=False)
    assert player_camera == RobotSensors(camera=True, labels=True, ball3d=False, rgbd=False, front=True)
    assert goalie_given == RobotSensors(camera=False, labels=False, ball3d=True, rgbd=False, front=False)
    assert player_given == RobotSensors(camera=False, labels=False, ball3d=False, rgbd=False, front=False)


def test_each_output_comes_at_its_rate_and_the_cameras_take_turns():
    schedule = SensorSchedule(SimNodeParams())  # clock 1000 Hz, states 100, vision 30, odometry and IMU 50
    cameras = [f"nubot{i}" for i in range(1, CAMERA_PHASES + 1)]
    for name in cameras:
        schedule.add_camera(name, 0.0)
    counts = dict.fromkeys(("clock", "states", "percepts", "odometry", "imu"), 0)
    frames: dict[str, list[float]] = {name: [] for name in cameras}
    steps = 200  # 1 s of 5 ms steps
    for i in range(steps):
        due = schedule.tick(i * STEP)
        for key in counts:
            counts[key] += getattr(due, key)
        for name in due.cameras:
            frames[name].append(i * STEP)
    assert counts == {"clock": steps, "states": 100, "percepts": 30, "odometry": 50, "imu": 50}
    assert all(len(times) == 30 for times in frames.values())  # 30 Hz each
    firsts = [times[0] for times in frames.values()]
    assert firsts == sorted(firsts) and len(set(firsts)) == CAMERA_PHASES  # spread over the frame period
    assert max(firsts) - min(firsts) < 1.0 / 30.0


def test_model_states_come_once_per_sim_time():
    schedule = SensorSchedule(SimNodeParams())
    assert schedule.tick(0.01).states
    assert not schedule.tick(0.01).states  # sim time stood still (paused): nothing new to say


def test_the_pacer_holds_sim_time_to_the_factor_of_wall_time():
    clock = FakeClock()
    pacer = Pacer(2.0, 0.0, clock, clock.sleep)
    start = clock.now
    pacer.wait(1.0)
    assert clock.now - start == pytest.approx(0.5)  # 1 s of sim time at twice real time
    assert max(clock.sleeps) <= 0.1 + 1e-12  # looks at the factor again at least every 0.1 s
    pacer.factor = 0.0  # as fast as possible: never sleeps
    clock.sleeps.clear()
    pacer.wait(50.0)
    assert clock.sleeps == []


def test_a_pacer_far_behind_gives_the_lost_time_up_instead_of_racing():
    clock = FakeClock()
    pacer = Pacer(1.0, 0.0, clock, clock.sleep)
    clock.now += 10.0  # the machine stalled for 10 s
    pacer.wait(0.1)
    assert clock.sleeps == []
    pacer.wait(0.2)  # from now on paced again, from where it stands
    assert sum(clock.sleeps) == pytest.approx(0.1)
    assert MAX_LAG < 10.0


def test_a_new_factor_takes_effect_during_a_wait():
    clock = FakeClock()
    pacer = Pacer(0.01, 0.0, clock, lambda s: (clock.sleep(s), setattr(pacer, "factor", 1.0)))
    start = clock.now
    pacer.wait(1.0)  # 100 s at 0.01; the factor becomes 1 during the first sleep
    pacer.wait(1.0)
    assert clock.now - start < 2.0


def test_the_host_gives_percepts_and_camera_frames_at_their_rates():
    host = SimHost(_params(vision="nubot2"), FakeClock())
    percepts = cameras = odometry = ball3d = 0
    while host.sim.time < 1.0 - 1e-9:
        tick = host.step()
        for name, out in tick.robots.items():
            percepts += out.percepts is not None
            cameras += out.camera is not None and name == "nubot2" and out.truth is not None
            odometry += out.odometry is not None
            ball3d += out.has_ball3d
            assert out.front is None  # nobody listens
    # Due at 0 (the first step), then every period through 1 s: 31 percepts, 51 odometry readings.
    assert percepts == 2 * 31  # nubot1 and rival1, given percepts
    assert ball3d == 2 * 31  # both are their team's goalie (AgentID 1)
    assert cameras == 31
    assert odometry == 51  # only the camera robot has a driver's odometry


def test_a_flood_of_bad_commands_is_refused_and_reported_every_few_seconds():
    clock = FakeClock()
    host = SimHost(_params(), clock)
    lines = [host.command_velocity("nubot1", math.nan, 0.0, 0.0) for _ in range(100)]
    said = [line for line in lines if line is not None]
    assert len(said) == 1 and "velocity command rejected" in said[0]
    clock.now += 6.0
    tick = host.step()
    assert len(tick.refusals) == 1 and "99" in tick.refusals[0]  # the flood's tail, counted
    assert host.command_velocity("nobody", 1.0, 0.0, 0.0) is None  # a robot deleted meanwhile: ignored
    assert host.command_velocity("nubot1", 1.0, 0.0, 0.0) is None  # a good command says nothing


def test_wheel_speeds_drive_a_robot_and_give_its_feedback():
    host = SimHost(_params(), FakeClock())
    angles = tuple(math.radians(a) for a in (45.0, 135.0, -135.0, -45.0))
    assert host.command_wheels("nubot1", angles, 0.203, (1.0, 1.0, 1.0, 1.0)) is None
    outputs = [tick.robots.get("nubot1") for tick in (host.step() for _ in range(20))]
    feedback = [out.drive for out in outputs if out is not None and out.drive is not None]
    assert len(feedback) == 6 and all(len(speeds) == 4 for speeds, _held in feedback)  # 50 Hz: 0, 0.02 .. 0.1 s
    line = host.command_wheels("nubot2", angles[:2], 0.203, (1.0, 1.0))
    assert line is not None and "wheel speeds rejected" in line  # two wheels are no holonomic base


def test_spawned_robots_join_and_deleted_ones_leave_the_outputs():
    host = SimHost(_params(), FakeClock())
    host.spawn(RobotSpawn("nubot3", 0.0, -2.0))
    host.delete("nubot2")
    seen: set[str] = set()
    for _ in range(10):
        seen |= {name for name, out in host.step().robots.items() if out.percepts is not None}
    assert seen == {"nubot1", "nubot3", "rival1"}
    assert "nubot2" not in host.sensors and "nubot2" not in host.sim.plugins


def test_reconfigure_changes_the_pace_and_the_rules_and_refuses_bad_values_whole():
    host = SimHost(_params(), FakeClock())
    before = host.configuration()
    changed = host.reconfigure({**before, "real_time_factor": 3.0})
    assert host.pacer.factor == 3.0 and changed["real_time_factor"] == 3.0
    noise = next(name for name in before if name.endswith("_std") or "noise" in name)
    with pytest.raises(ValueError):
        host.reconfigure({**changed, noise: -1.0, "real_time_factor": 1.0})
    assert host.configuration() == changed  # nothing of the refused configuration applied
    assert {p.name for p in host.reconfigure_params()} == set(before)

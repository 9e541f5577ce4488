"""Unit tests of the robots' own sensors (sim_visual.sensors), the Simulator's sensor methods (camera_frame,
odometry, inertial_heading, observe_truth) and the labelled frames of sim_visual.camera_frames."""

import math

import numpy as np
import pytest

from nubot_common.geometry import Pose2D, wrap_angle
from nubot_common.team_frame import TeamFrame
from nubot_common.world_description import load_world
from sim_visual import SimVisualError
from sim_visual.camera_frames import main, random_scenes
from sim_visual.params import NoiseParams, RobotSpawn
from sim_visual.world import BallState, RobotState

TEAMS = (("nubot1", -2.0, 1.0, 0.3, 1), ("rival1", 2.0, -1.0, 0.0, -1), ("rival2", 4.0, 2.0, 2.0, -1))
BALL = (1.0, 2.5)
DT = 0.02  # [s] between sensor readings


@pytest.fixture
def make_match(make_sim):
    """A simulator with a robot of each team (rival attacks -x) and the ball in view of everyone."""
    def build(seed: int = 5, **overrides):
        return make_sim(robots=TEAMS, ball=BALL, seed=seed, **overrides)
    return build


# --- the inertial heading ------------------------------------------------------------------------------------
@pytest.mark.parametrize(("name", "theta", "expected"), [("rival1", 0.0, math.pi), ("rival1", math.pi, 0.0),
                                                         ("rival1", 1.0, 1.0 - math.pi), ("nubot1", 0.0, 0.0),
                                                         ("nubot1", -2.0, -2.0)])
def test_the_inertial_heading_is_in_the_robots_team_frame(make_match, name, theta, expected):
    """The inertial heading is 0 facing the goal the robot's team attacks: a rival (attacking -x) facing world
    +x reads about pi, a nubot facing world +x about 0."""
    sim = make_match()
    state = sim.world.robot_state(name)
    sim.set_model_state(name, RobotState(state.x, state.y, theta, 0.0, 0.0, 0.0))
    reading = sim.inertial_heading(name, DT)
    assert abs(wrap_angle(reading.yaw - expected)) < 0.05, f"yaw {reading.yaw:.3f}, expected {expected:.3f}"
    assert abs(reading.yaw_rate) < 0.05, "at rest"


# --- the camera: determinism and independence from the percepts' noise -----------------------------------------
def test_camera_frames_are_deterministic_per_seed(make_match):
    """Two simulators with the same seed render the same frames; another seed gives other pixel noise."""
    first, second, other = make_match(seed=5), make_match(seed=5), make_match(seed=6)
    for _ in range(2):
        a, b, c = (s.camera_frame("nubot1").image for s in (first, second, other))
        np.testing.assert_array_equal(a, b)
        assert not np.array_equal(a, c)
        assert a.shape == (480, 480, 3) and a.dtype == np.uint8


def test_rendering_frames_does_not_change_the_percepts_of_a_twin(make_match):
    """Rendering camera frames (for robots that see through the camera) draws nothing from the percepts' noise:
    the other robots' ``observe`` gives what a twin simulator that rendered nothing gives."""
    rendering, twin = make_match(), make_match()
    for name in ("nubot1", "rival1"):
        rendering.camera_frame(name, labels=True)
    rendering.odometry("nubot1", DT)
    rendering.inertial_heading("nubot1", DT)
    for name in ("rival2", "nubot1"):
        assert rendering.observe(name) == twin.observe(name)


def test_percepts_do_not_change_the_camera_frames_of_a_twin(make_match):
    """Observing (with noise) draws nothing from the camera's stream: frames match a twin that observed nothing."""
    observing, twin = make_match(), make_match()
    for _ in range(3):
        observing.observe("rival2")
    np.testing.assert_array_equal(observing.camera_frame("nubot1").image, twin.camera_frame("nubot1").image)


def test_the_percepts_are_noisy_so_the_independence_tests_can_fail(make_match):
    """(Two observations in a row differ: the percepts do draw noise, so a shared stream would show.)"""
    sim = make_match()
    assert sim.observe("nubot1") != sim.observe("nubot1")


def test_labels_come_only_on_request(make_match):
    """A frame carries each pixel's colour class only when asked for (labels cost time)."""
    sim = make_match()
    assert sim.camera_frame("nubot1").labels is None
    labels = sim.camera_frame("nubot1", labels=True).labels
    assert labels is not None and labels.shape == (480, 480) and labels.dtype == np.uint8


@pytest.mark.parametrize("method", ["camera_frame", "odometry", "inertial_heading"])
def test_sensors_of_an_unknown_robot_raise_naming_it(make_match, method):
    """Asking for the sensors of a robot that is not in the simulator raises SimVisualError naming it and the
    robots there are."""
    sim = make_match()
    args = () if method == "camera_frame" else (DT,)
    with pytest.raises(SimVisualError, match=r"no robot named 'nubot9'; robots: nubot1, rival1, rival2"):
        getattr(sim, method)("nubot9", *args)


# --- the truth -------------------------------------------------------------------------------------------------
def test_observe_truth_is_noise_free_and_in_the_team_frame(make_match):
    """``observe_truth`` gives the robot's true pose, ball and robots in its team frame, without noise and without
    the vision's range limit."""
    sim = make_match(noise=NoiseParams(vision_range=1.0))  # everything is farther than 1 m
    truth = sim.observe_truth("rival1")
    frame = TeamFrame(-1)
    assert truth.robot.pose == frame.pose_to_team(Pose2D(2.0, -1.0, 0.0))
    assert truth.ball is not None and (truth.ball.x, truth.ball.y) == pytest.approx(frame.point_to_team(*BALL))
    expected = sorted(frame.point_to_team(x, y) for _, x, y, _, _ in (TEAMS[0], TEAMS[2]))
    assert sorted(truth.obstacles) == [pytest.approx(p) for p in expected]
    noisy = sim.observe("rival1")
    assert noisy.ball is None and noisy.obstacles == (), "the noisy percepts keep the range limit"
    assert noisy.robot.pose != truth.robot.pose


def test_observe_truth_does_not_consume_the_simulators_generator(make_match):
    """Measuring the vision against the truth changes no percept: ``observe`` after ``observe_truth`` gives what
    a twin simulator's ``observe`` gives."""
    measuring, twin = make_match(), make_match()
    state = measuring.rng.bit_generator.state
    for name in ("nubot1", "rival1", "rival1"):
        measuring.observe_truth(name)
    assert measuring.rng.bit_generator.state == state
    assert measuring.observe("rival2") == twin.observe("rival2")


# --- odometry --------------------------------------------------------------------------------------------------
def drive(sim, name: str, vx: float) -> None:
    s = sim.world.robot_state(name)
    sim.set_model_state(name, RobotState(s.x, s.y, s.theta, vx * math.cos(s.theta), vx * math.sin(s.theta), 0.0))


def test_a_deleted_robot_forgets_its_odometry(make_sim):
    """A robot deleted and spawned again starts its odometry afresh: its first reading sees no acceleration from
    the old robot's last velocity (no wheel slip), as a robot that was never read."""
    respawned, kept, fresh = (make_sim(robots=(("nubot1", 0.0, 0.0, 0.0), ("nubot2", 3.0, 0.0, 0.0)), seed=3)
                              for _ in range(3))
    respawned.odometry("nubot1", DT)
    respawned.delete_robot("nubot1")
    respawned.spawn_robot(RobotSpawn("nubot1", 0.0, 0.0, 0.0))
    kept.odometry("nubot1", DT)
    fresh.odometry("nubot2", DT)  # the same draws from the sensors' generator, nubot1 never read
    readings = []
    for sim in (respawned, kept, fresh):
        drive(sim, "nubot1", 2.0)
        readings.append(sim.odometry("nubot1", DT))
    after_delete, remembered, never_read = readings
    assert after_delete == never_read
    assert remembered.vx > after_delete.vx + 0.01, "a remembered rest makes 2 m/s in 20 ms a slipping start"


def test_odometry_reads_the_body_velocity(make_sim):
    """The odometry reports the robot's velocity in its body frame (forward, left), within its noise."""
    sim = make_sim(robots=(("nubot1", 0.0, 0.0, math.pi / 2),))
    drive(sim, "nubot1", 1.5)
    sim.odometry("nubot1", DT)  # the first reading of a moving robot: no slip either
    reading = sim.odometry("nubot1", DT)
    assert reading.vx == pytest.approx(1.5, abs=0.15) and reading.vy == pytest.approx(0.0, abs=0.05)
    assert reading.robot_stuck is False


# --- camera_frames ---------------------------------------------------------------------------------------------
WORLD = load_world("18x12")


def test_random_scenes_stay_inside_the_arena():
    """Every viewer, other robot and ball of the calibration scenes stands inside the lines plus the border;
    the ball is on the carpet or in the air up to 0.6 m; the frames are 2 s apart."""
    f = WORLD.field
    hx, hy = f.half_length + f.border, f.half_width + f.border
    scenes = list(random_scenes(WORLD, 300, np.random.default_rng(0)))
    assert len(scenes) == 300
    others = 0
    for k, (t, me, ball, robots) in enumerate(scenes):
        assert t == 2.0 * k
        for thing in (me, ball, *robots):
            assert abs(thing.x) <= hx and abs(thing.y) <= hy, f"scene {k}: {thing} outside the arena"
        assert WORLD.ball.radius <= ball.z <= WORLD.ball.radius + 0.6
        assert len(robots) <= 9
        others += len(robots)
    assert others > 300 * 3, "most scenes show several other robots"


def test_random_scenes_are_seeded():
    """The same seed draws the same scenes; another seed other ones."""
    def scenes(seed: int) -> list:
        return list(random_scenes(WORLD, 5, np.random.default_rng(seed)))
    assert scenes(7) == scenes(7)
    assert scenes(7) != scenes(8)


def test_main_refuses_zero_frames(tmp_path, capsys):
    """``render_camera_frames --frames 0`` is a usage error (exit 2) saying why, and writes nothing."""
    with pytest.raises(SystemExit) as exit_info:
        main(["--out", str(tmp_path / "frames"), "--frames", "0"])
    assert exit_info.value.code == 2
    assert "--frames must be at least 1, got 0" in capsys.readouterr().err
    assert not (tmp_path / "frames").exists()


def test_main_refuses_an_unknown_field(tmp_path, capsys):
    """An unknown --field exits 2 with a one-line message naming the problem."""
    assert main(["--out", str(tmp_path / "frames"), "--frames", "1", "--field", "nowhere"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("render_camera_frames: ") and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "frames").exists()


def test_main_writes_labelled_frames(tmp_path, capsys):
    """``render_camera_frames --frames 2`` writes two frames and their labels and says so."""
    assert main(["--out", str(tmp_path / "frames"), "--frames", "2", "--seed", "4"]) == 0
    names = sorted(p.name for p in (tmp_path / "frames").iterdir())
    assert names == ["frame_0000.png", "frame_0000_labels.png", "frame_0001.png", "frame_0001_labels.png"]
    assert capsys.readouterr().out.strip() == f"render_camera_frames: 2 labelled frames in {tmp_path / 'frames'}"


def test_ball_state_in_scenes_is_at_rest():
    """The scenes are still frames: the ball does not move."""
    for _, _, ball, _ in random_scenes(WORLD, 20, np.random.default_rng(1)):
        assert isinstance(ball, BallState) and (ball.vx, ball.vy, ball.vz) == (0.0, 0.0, 0.0)

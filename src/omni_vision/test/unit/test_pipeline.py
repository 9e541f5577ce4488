"""Unit tests of omni_vision.pipeline (OmniVision) on frames rendered by the simulator's omni camera."""

import math
from pathlib import Path

import numpy as np
import pytest

from nubot_common.geometry import Pose2D, rotate, wrap_angle
from nubot_common.params import load_yaml
from nubot_common.team_frame import TeamFrame
from nubot_common.world_description import load_world
from omni_vision import OmniVisionError
from omni_vision.colors import ColorTable
from omni_vision.localization import LocalizationState
from omni_vision.pipeline import OmniVision, OmniVisionParams, VisionFrame
from sim_visual.camera_params import OmniCameraParams
from sim_visual.sensors import RobotSensors, SensorParams
from sim_visual.world import BallState, RobotState

CONFIG = Path(__file__).resolve().parents[2] / "config"
WORLD = load_world("18x12")
PARAMS = load_yaml(OmniVisionParams, CONFIG / "omni_vision.yaml")
TABLE = ColorTable.load(CONFIG / "colors_sim.npz")
BALL_Z = WORLD.ball.radius
FAR_BALL = BallState(8.5, -5.5, BALL_Z, 0.0, 0.0, 0.0)  # out of the way when a test looks elsewhere
FRAME_DT = 1.0 / 30.0  # [s]
TOLERANCE = 0.03  # [m] the localization's promise on rendered frames


@pytest.fixture
def sensors() -> RobotSensors:
    """The simulator's sensors with a fixed seed: every test sees the same frames, whatever ran before."""
    return RobotSensors(WORLD, SensorParams(), seed=11)


def still(x: float, y: float, theta: float = 0.0) -> RobotState:
    return RobotState(x, y, theta, 0.0, 0.0, 0.0)


def ball_at(x: float, y: float) -> BallState:
    return BallState(x, y, BALL_Z, 0.0, 0.0, 0.0)


def new_vision() -> OmniVision:
    return OmniVision(WORLD, PARAMS, TABLE, agent_id=2)


def run_frames(vision: OmniVision, sensors: RobotSensors, me: RobotState, frames: int, attack: int = 1,
               ball: BallState = FAR_BALL, others: tuple[RobotState, ...] = (), start: float = 0.0,
               heading: bool = True) -> list[VisionFrame]:
    """Feed ``frames`` frames of a robot standing at ``me`` (world frame): odometry at rest, the inertial heading
    in its team frame (``heading``), then the camera image."""
    out = []
    for k in range(frames):
        t = start + k * FRAME_DT
        vision.odometry(t, 0.0, 0.0, 0.0)
        if heading:
            vision.inertial(t, TeamFrame(attack).heading_to_team(me.theta))
        out.append(vision.process(t, sensors.camera(t, me, ball, others).image))
    return out


def pose_error(pose: Pose2D, truth: Pose2D) -> tuple[float, float]:
    return math.hypot(pose.x - truth.x, pose.y - truth.y), abs(wrap_angle(pose.theta - truth.theta))


def truth_of(me: RobotState, attack: int = 1) -> Pose2D:
    return TeamFrame(attack).pose_to_team(Pose2D(me.x, me.y, me.theta))


# --- self-localization ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("pose", [(2.3, -1.4, 0.7), (-6.5, 3.2, -2.4), (0.4, 0.3, 1.6), (7.6, -5.2, 3.0)])
def test_global_localization_from_an_unknown_pose_converges_within_a_few_frames(sensors, pose):
    """A robot that does not know where it is finds its pose to within 3 cm within five frames."""
    me = still(*pose)
    vision = new_vision()
    assert vision.locator.estimate.state is LocalizationState.GLOBAL_SEARCH
    frames = run_frames(vision, sensors, me, 5)
    last = frames[-1]
    assert last.localized and last.view.robot.valid
    position, heading = pose_error(last.view.robot.pose, truth_of(me))
    assert position < TOLERANCE, f"{position:.3f} m off"
    assert heading < math.radians(1.0)


def test_tracking_from_a_pose_0_3_m_off_converges_within_a_few_frames(sensors):
    """Reset with a pose 0.3 m (and 3 deg) off, the robot tracks to within 3 cm in a few frames, without
    falling back to a global search."""
    me = still(-2.0, 1.5, 2.2)
    vision = new_vision()
    start = Pose2D(me.x + 0.3 * math.cos(0.9), me.y + 0.3 * math.sin(0.9), me.theta + math.radians(3.0))
    vision.reset(start)
    frames = run_frames(vision, sensors, me, 5)
    assert all(f.estimate.state is LocalizationState.TRACKING for f in frames)
    position, heading = pose_error(frames[-1].view.robot.pose, truth_of(me))
    assert position < TOLERANCE and heading < math.radians(1.0), f"{position:.3f} m, {heading:.4f} rad off"


def test_reset_without_a_pose_forgets_it(sensors):
    """``reset()`` makes a localized vision search again: its next frame without a heading is not localized."""
    me = still(1.0, 2.0, 0.3)
    vision = new_vision()
    assert run_frames(vision, sensors, me, 2)[-1].localized
    vision.reset()
    frame = run_frames(vision, sensors, me, 1, start=1.0, heading=False)[0]
    assert frame.estimate.state is LocalizationState.GLOBAL_SEARCH and not frame.view.robot.valid


def test_a_robot_attacking_minus_x_is_reported_in_its_team_frame(sensors):
    """A robot of the team attacking the goal at -x, given its inertial heading in its team frame, reports its
    team-frame pose (the world pose turned half round the centre spot), not the world pose."""
    me = still(3.0, -2.0, 0.4)
    frame = run_frames(new_vision(), sensors, me, 4, attack=-1)[-1]
    pose = frame.view.robot.pose
    position, heading = pose_error(pose, truth_of(me, attack=-1))
    assert frame.localized and position < TOLERANCE and heading < math.radians(1.0), f"{pose}"
    assert pose.x == pytest.approx(-3.0, abs=TOLERANCE) and pose.y == pytest.approx(2.0, abs=TOLERANCE)


# --- ball and obstacles ----------------------------------------------------------------------------------------
SCENES = {  # attack, the robot's world pose, the ball and the other robots (world frame): no goal in close view
    "nubot, three robots around": (1, (2.0, -1.0, 0.5), (4.0, 0.5), ((0.0, -3.0), (5.0, -2.5), (-1.0, 1.5))),
    "rival, ball behind-left": (-1, (-3.0, 2.0, 2.8), (-5.5, 3.5), ((-1.0, 0.0), (-4.0, -1.0))),
    "rival, ball near": (-1, (4.0, -3.0, -1.0), (3.0, -4.5), ((6.5, -1.0), (1.0, -2.0), (4.0, 0.5))),
    "nubot, facing its own half": (1, (-1.5, 3.0, 3.0), (-3.0, 1.5), ((-4.0, 4.0), (1.5, 4.5))),
}


@pytest.mark.parametrize(("attack", "pose", "ball", "others"), SCENES.values(), ids=SCENES.keys())
def test_ball_and_obstacles_land_near_their_true_team_frame_positions(sensors, attack, pose, ball, others):
    """The ball and every other robot are reported in the team frame within 5 % of their distance plus 5 cm,
    and no robot is reported that is not there."""
    me = still(*pose)
    frame = run_frames(new_vision(), sensors, me, 3, attack=attack, ball=ball_at(*ball),
                       others=tuple(still(x, y) for x, y in others))[-1]
    assert frame.localized
    team = TeamFrame(attack)
    here = truth_of(me, attack)

    def close_enough(seen: tuple[float, float], world: tuple[float, float]) -> bool:
        true = team.point_to_team(*world)
        return math.dist(seen, true) <= 0.05 * math.dist(true, (here.x, here.y)) + 0.05

    assert frame.view.ball is not None, "the ball is in view"
    assert close_enough((frame.view.ball.x, frame.view.ball.y), ball), f"ball at {frame.view.ball}"
    assert frame.view.ball.stamp == pytest.approx(frame.view.stamp)
    seen = frame.view.obstacles
    assert len(seen) == len(others), f"saw {seen}"
    for other in others:
        assert any(close_enough(o, other) for o in seen), f"robot at {other} (world) not among {seen}"


@pytest.mark.parametrize("pose", [(-8.6, -0.3, 0.0), (-8.75, -0.47, -2.55), (8.7, 0.6, 2.0)])
def test_the_dark_ground_inside_a_goal_is_no_robot(sensors, pose):
    """A robot before a goal sees the goal's dark inside among its black: no obstacle is reported in a goal,
    and the robot that stands in front of the goal is (the goalie would otherwise shy away from its own goal)."""
    me = still(*pose)
    other = (math.copysign(7.4, pose[0]), 1.2)
    frame = run_frames(new_vision(), sensors, me, 3, others=(still(*other),))[-1]
    assert frame.localized
    seen = frame.view.obstacles
    assert not [o for o in seen if WORLD.field.in_goal(*o, WORLD.robot.radius)], f"saw {seen}"
    assert len(seen) == 1 and math.dist(seen[0], other) < 0.05 * math.dist(other, pose[:2]) + 0.05, f"saw {seen}"


@pytest.mark.parametrize(("distance", "bearing", "holding"), [(0.45, 0.0, True), (1.5, 0.0, False),
                                                              (0.45, math.pi / 2, False)])
def test_holding_is_a_ball_right_in_front(sensors, distance, bearing, holding):
    """A ball 0.45 m straight ahead is in the grabber; one 1.5 m ahead or 0.45 m to the left is not."""
    me = still(-2.0, 1.0, 0.3)
    ball = ball_at(me.x + distance * math.cos(me.theta + bearing), me.y + distance * math.sin(me.theta + bearing))
    frame = run_frames(new_vision(), sensors, me, 3, ball=ball)[-1]
    assert frame.ball is not None, "the ball is seen"
    assert frame.view.robot.holding is holding


def test_velocity_comes_from_odometry_turned_into_the_team_frame(sensors):
    """The reported velocity is the odometry's body velocity turned by the team-frame heading (a robot of the
    team attacking -x, facing world +x, driving forward moves towards -x of its team frame); w and the stuck
    flag pass through."""
    me = still(1.0, 2.0, 0.4)
    vision = new_vision()
    frames = run_frames(vision, sensors, me, 3, attack=-1)
    t = 2 * FRAME_DT
    vision.odometry(t, 1.0, 0.5, 0.3, stuck=True)  # at the last frame's time: no motion is integrated
    frame = vision.process(t, sensors.camera(t, me, FAR_BALL, ()).image)
    assert frames[-1].localized and frame.localized
    robot = frame.view.robot
    expected = rotate(1.0, 0.5, me.theta + math.pi)
    assert (robot.vx, robot.vy) == (pytest.approx(expected[0], abs=0.02), pytest.approx(expected[1], abs=0.02))
    assert robot.vx < -0.5, "forward is towards -x of the team frame for this robot"
    assert robot.w == 0.3 and robot.stuck is True


def test_not_localized_means_not_valid_and_no_ball_or_obstacles(sensors):
    """Without an inertial heading the vision cannot localize: the robot is not valid and reports neither the
    ball nor obstacles, although it sees them (their positions would be wrong)."""
    me = still(2.0, -1.0, 0.5)
    frame = run_frames(new_vision(), sensors, me, 3, ball=ball_at(3.0, -0.5), others=(still(0.0, -3.0),),
                       heading=False)[-1]
    assert frame.ball is not None and frame.obstacles, "the camera sees them"
    assert not frame.localized
    assert frame.view.robot.valid is False
    assert frame.view.ball is None and frame.view.obstacles == ()
    assert frame.view.robot.agent_id == 2


def test_a_stale_inertial_heading_is_not_used(sensors):
    """A heading older than heading_timeout is ignored: global localization waits for a fresh one."""
    me = still(2.0, -1.0, 0.5)
    vision = new_vision()
    vision.inertial(0.0, me.theta)
    t = PARAMS.heading_timeout + 0.1
    vision.odometry(t, 0.0, 0.0, 0.0)
    assert not vision.process(t, sensors.camera(t, me, FAR_BALL, ()).image).localized
    vision.inertial(t, me.theta)
    assert vision.process(t, sensors.camera(t, me, FAR_BALL, ()).image).localized


def carpet_image(sensors: RobotSensors) -> np.ndarray:
    """An all-green frame: the carpet's colour painted over the whole image, with the camera's noise."""
    image = np.empty((PARAMS.mirror.height, PARAMS.mirror.width, 3), np.uint8)
    image[:] = OmniCameraParams().carpet_rgb
    noise = np.random.default_rng(5).normal(0.0, 4.0, image.shape)
    return np.clip(image + noise, 0, 255).astype(np.uint8)


def test_a_frame_without_lines_while_searching_reports_not_localized(sensors):
    """A frame with no lines in view before the pose is known gives a report (not localized), no exception."""
    vision = new_vision()
    vision.odometry(0.0, 0.0, 0.0, 0.0)
    vision.inertial(0.0, 0.5)
    frame = vision.process(0.0, carpet_image(sensors))
    assert len(frame.lines.points) == 0
    assert not frame.localized and not frame.view.robot.valid
    assert frame.view.ball is None and frame.view.obstacles == ()


def test_a_frame_without_lines_while_tracking_keeps_the_prediction(sensors):
    """A frame with no lines in view while tracking keeps the odometry's prediction: still localized, the pose
    where it was."""
    me = still(-3.0, 2.0, -0.8)
    vision = new_vision()
    before = run_frames(vision, sensors, me, 3)[-1]
    t = 3 * FRAME_DT
    vision.odometry(t, 0.0, 0.0, 0.0)
    vision.inertial(t, me.theta)
    frame = vision.process(t, carpet_image(sensors))
    assert len(frame.lines.points) == 0
    assert frame.localized and frame.estimate.state is LocalizationState.TRACKING
    position, heading = pose_error(frame.view.robot.pose, before.view.robot.pose)
    assert position < 0.01 and heading < 0.01


# --- bad input ---------------------------------------------------------------------------------------------
def localized_vision(sensors: RobotSensors, me: RobotState) -> OmniVision:
    vision = new_vision()
    assert run_frames(vision, sensors, me, 2)[-1].localized
    return vision


BAD_IMAGES = {
    "wrong size": (np.zeros((240, 320, 3), np.uint8),
                   r"the image must be RGB of 480 x 480 px .*got shape \(240, 320, 3\)"),
    "grey": (np.full((480, 480), 90, np.uint8), r"the image must be RGB of 480 x 480 px .*got shape \(480, 480\)"),
    "float": (np.full((480, 480, 3), 90.0), r"the image must be uint8, got float64"),
    "black": (np.zeros((480, 480, 3), np.uint8), r"the image is black"),
    "not an array": ([[0, 0, 0]], r"the image must be a numpy array, got list"),
}


@pytest.mark.parametrize(("image", "message"), BAD_IMAGES.values(), ids=BAD_IMAGES.keys())
def test_an_unusable_image_raises_and_the_next_good_frame_works(sensors, image, message):
    """A frame of the wrong size, grey, float or black raises OmniVisionError saying what is wrong; the vision
    keeps its pose and localizes the next good frame."""
    me = still(1.5, -2.5, 1.1)
    vision = localized_vision(sensors, me)
    t = 2 * FRAME_DT
    with pytest.raises(OmniVisionError, match=message):
        vision.process(t, image)
    frame = run_frames(vision, sensors, me, 1, start=t)[0]
    position, _ = pose_error(frame.view.robot.pose, truth_of(me))
    assert frame.localized and position < TOLERANCE


@pytest.mark.parametrize("odometry", [(math.nan, 0.0, 0.0), (0.0, math.inf, 0.0), (0.0, 0.0, math.nan)])
def test_non_finite_odometry_raises_and_changes_nothing(sensors, odometry):
    """A NaN or infinite odometry velocity raises OmniVisionError naming it; the pose does not take it in and the
    next good frame is localized where the robot is."""
    me = still(1.5, -2.5, 1.1)
    vision = localized_vision(sensors, me)
    t = 2 * FRAME_DT
    with pytest.raises(OmniVisionError, match=r"odometry must be finite, got t .*\(.*(nan|inf).*\)"):
        vision.odometry(t, *odometry)
    frame = run_frames(vision, sensors, me, 1, start=t)[0]
    position, _ = pose_error(frame.view.robot.pose, truth_of(me))
    assert frame.localized and position < TOLERANCE
    assert all(math.isfinite(v) for v in (frame.view.robot.vx, frame.view.robot.vy, frame.view.robot.w))


def test_a_non_finite_odometry_time_raises():
    """Odometry stamped NaN raises OmniVisionError too."""
    with pytest.raises(OmniVisionError, match="odometry must be finite, got t nan"):
        new_vision().odometry(math.nan, 0.0, 0.0, 0.0)


@pytest.mark.parametrize(("t", "heading"), [(0.0, math.nan), (0.0, math.inf), (math.nan, 0.3)])
def test_a_non_finite_inertial_heading_raises_and_the_next_good_one_works(sensors, t, heading):
    """A NaN heading (or stamp) raises OmniVisionError; the vision localizes with the next good heading."""
    vision = new_vision()
    with pytest.raises(OmniVisionError, match="the inertial heading must be finite"):
        vision.inertial(t, heading)
    me = still(-4.0, -2.0, 2.0)
    frame = run_frames(vision, sensors, me, 3)[-1]
    position, _ = pose_error(frame.view.robot.pose, truth_of(me))
    assert frame.localized and position < TOLERANCE


def test_an_agent_id_below_1_is_refused():
    """The vision serves one robot: an AgentID of 0 is refused naming it."""
    with pytest.raises(OmniVisionError, match="agent_id must be an AgentID from 1, got 0"):
        OmniVision(WORLD, PARAMS, TABLE, agent_id=0)


def test_each_stage_reports_its_time(sensors):
    """Every frame tells each stage's time, and the total covers them."""
    frame = run_frames(new_vision(), sensors, still(0.0, 0.0), 1)[0]
    stages = ("sample", "lines", "ball", "obstacles", "localization")
    assert set(frame.timings) == {*stages, "total"}
    assert all(frame.timings[s] >= 0.0 for s in stages)
    assert frame.timings["total"] == pytest.approx(sum(frame.timings[s] for s in stages), rel=1e-6, abs=1e-9)

"""Unit tests of the simulated omni-directional camera (sim_visual.omni_camera)."""

import math

import cv2
import numpy as np
import pytest

from nubot_common.color_class import ColorClass
from nubot_common.mirror import MirrorModel
from nubot_common.params import from_mapping
from nubot_common.world_description import WorldDescription
from sim_visual.camera_params import OmniCameraParams
from sim_visual.omni_camera import OmniCameraRenderer
from sim_visual.world import BallState, RobotState

WORLD = WorldDescription()  # the 18 x 12 m field
MIRROR = MirrorModel()
BALL_RADIUS = WORLD.ball.radius
ROBOT_RADIUS = WORLD.robot.radius
CORNER_BALL = BallState(-8.5, -5.5, BALL_RADIUS, 0.0, 0.0, 0.0)  # out of the way when a test looks elsewhere
WORLD_PARAMS = OmniCameraParams()
STEADY = OmniCameraParams(noise_std=0.0, lighting_field_amplitude=0.0, lighting_time_amplitude=0.0)


def still(x: float, y: float, theta: float = 0.0) -> RobotState:
    return RobotState(x, y, theta, 0.0, 0.0, 0.0)


def ball_at(x: float, y: float, z: float = BALL_RADIUS) -> BallState:
    return BallState(x, y, z, 0.0, 0.0, 0.0)


@pytest.fixture(scope="module")
def steady() -> OmniCameraRenderer:
    """A camera without noise and with even, constant lighting."""
    return OmniCameraRenderer(WORLD, MIRROR, STEADY)


@pytest.fixture(scope="module")
def camera() -> OmniCameraRenderer:
    """The camera with its default lighting and noise."""
    return OmniCameraRenderer(WORLD, MIRROR, OmniCameraParams())


def polar() -> tuple[np.ndarray, np.ndarray]:
    """Every pixel's bearing [rad] (0 ahead, counter-clockwise) and image radius [px]."""
    v, u = np.mgrid[0:MIRROR.height, 0:MIRROR.width].astype(float)
    du, dv = u - MIRROR.centre_u, v - MIRROR.centre_v
    return np.arctan2(-du, -dv), np.hypot(du, dv)


BEARING, RADIUS = polar()


def pixels_along(bearing: float, radii: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The (row, column) indices of the pixels at ``radii`` [px] along the ray of ``bearing`` [rad]."""
    u = np.round(MIRROR.centre_u - radii * math.sin(bearing)).astype(int)
    v = np.round(MIRROR.centre_v - radii * math.cos(bearing)).astype(int)
    return v, u


def grey(image: np.ndarray) -> np.ndarray:
    """Luma (the Y of YUV) of an RGB image."""
    return image.astype(float) @ np.array([0.299, 0.587, 0.114])


LINE, SPOT = WORLD.field.line_width / 2, WORLD.field.spot_diameter / 2
MARKINGS = {  # robot pose, a bearing [rad] from it, the distance [m] and half width [m] of the marking it
    # crosses, and how slanted [1 / cos] the ray crosses it
    "touch line to the left": ((3.0, 5.0, 0.0), math.pi / 2, 1.0, LINE, 1.0),
    "touch line ahead": ((3.0, 5.0, math.pi / 2), 0.0, 1.0, LINE, 1.0),
    "centre spot ahead": ((-1.0, 0.0, 0.0), 0.0, 1.0, SPOT, 1.0),
    "centre circle ahead-left": ((0.0, 0.0, 0.0), 0.35, 2.0, LINE, 1.0),
    "centre circle behind-right": ((0.0, 0.0, 0.0), -2.2, 2.0, LINE, 1.0),
    "corner arc": ((8.0, 5.0, math.pi / 4), 0.0, math.sqrt(2.0) - WORLD.field.corner_arc_radius, LINE, 1.0),
    "field corner (closed)": ((8.0, 5.0, math.pi / 4), 0.0, math.sqrt(2.0), LINE, math.sqrt(2.0)),
}


@pytest.mark.parametrize(("pose", "bearing", "distance", "half", "slant"), MARKINGS.values(), ids=MARKINGS.keys())
def test_a_marking_appears_where_the_mirror_model_puts_it(steady, pose, bearing, distance, half, slant):
    """Along a ray crossing a white marking, the pixels that show the ground within its width are white, in
    labels and brightness, and those beyond its edges are carpet: lines, spots and arcs lie where the mirror
    model puts them."""
    frame = steady.render(still(*pose), CORNER_BALL, [], 0.0, np.random.default_rng(0), labels=True)
    radii: np.ndarray = np.arange(max(MIRROR.r_min + 2, float(MIRROR.radius(distance - 0.4))),
                                  float(MIRROR.radius(distance + 0.4)))
    rows, cols = pixels_along(bearing, radii)
    ground = MIRROR.distance(np.hypot(cols - MIRROR.centre_u, rows - MIRROR.centre_v))
    labels, brightness = frame.labels[rows, cols], grey(frame.image)[rows, cols]
    tolerance = 0.03  # a texel and a pixel's footprint
    on_mark = np.abs(ground - distance) < (half - tolerance) * slant
    off_mark = np.abs(ground - distance) > (half + tolerance) * slant
    assert on_mark.sum() >= 2
    assert np.all(labels[on_mark] == ColorClass.WHITE)
    assert np.all(labels[off_mark] == ColorClass.GREEN)
    assert brightness[on_mark].min() > brightness[off_mark].max() + 100


def test_a_calibrated_mirror_in_a_wider_image_is_followed_too():
    """With a calibration table for the mirror and a 640 x 480 image centred off the middle, the image has that
    size, the own body sits on the mirror centre, and the touch line 1 m to the left lands where this model
    puts it."""
    table = tuple((float(r), 1.1 * float(MIRROR.distance(r))) for r in np.linspace(0.0, MIRROR.r_max, 47))
    mirror = MirrorModel(width=640, height=480, centre_u=330.0, centre_v=240.0, table=table)
    frame = OmniCameraRenderer(WORLD, mirror, STEADY).render(still(3.0, 5.0), CORNER_BALL, [], 0.0,
                                                           np.random.default_rng(0), labels=True)
    assert frame.image.shape == (480, 640, 3) and frame.labels is not None
    assert frame.labels[240, 330] == ColorClass.BLACK and frame.labels[240, 20] == ColorClass.UNKNOWN
    for distance, label in ((1.0, ColorClass.WHITE), (0.85, ColorClass.GREEN), (1.15, ColorClass.GREEN)):
        u, v = mirror.body_to_pixel(0.0, distance)
        assert frame.labels[round(float(v)), round(float(u))] == label, distance


def test_far_lines_are_still_drawn_at_their_distance(steady):
    """Far out (the coarse texture level) the goal-area line 4.25 m and the goal line 5 m ahead each show as
    a brightness peak within a pixel of the radius the mirror model predicts; the nearer is labelled white
    there (the farther is narrower than a pixel's footprint, which a label may miss)."""
    frame = steady.render(still(4.0, 0.0), CORNER_BALL, [], 0.0, np.random.default_rng(0), labels=True)
    radii = np.arange(200, 219)
    rows, cols = pixels_along(0.0, radii)
    brightness = grey(frame.image)[rows, cols]
    carpet = np.median(grey(frame.image)[pixels_along(0.0, np.arange(190, 200))])
    for distance in (4.25, 5.0):
        nearest = np.abs(radii - MIRROR.radius(distance)) <= 1.0
        assert brightness[nearest].max() > carpet + 40, distance
    white = radii[frame.labels[rows, cols] == ColorClass.WHITE]
    assert np.min(np.abs(white - MIRROR.radius(4.25))) <= 1.0


def ball_pixels(frame) -> tuple[np.ndarray, np.ndarray]:
    """Bearings and radii of the pixels that look orange (more ball than carpet: what a colour threshold finds)."""
    def orange(rgb) -> np.ndarray:
        return np.asarray(rgb, float)[..., 0] - np.asarray(rgb, float)[..., 2]

    mask = orange(frame.image) > (orange(WORLD_PARAMS.ball_rgb) + orange(WORLD_PARAMS.carpet_rgb)) / 2.0
    return BEARING[mask], RADIUS[mask]


def test_the_ball_two_metres_ahead_appears_straight_up_at_the_predicted_radius(steady):
    """A ball on the ground at (2, 0) m of the body frame: an orange blob straight up the image, as wide as the
    ball's bearing span 2 asin(r / 2), covering the radius of its centre's ray and within the radii of its
    nearest and farthest points."""
    frame = steady.render(still(-5.0, -3.0), ball_at(-3.0, -3.0), [], 0.0, np.random.default_rng(0), labels=True)
    bearing, radius = ball_pixels(frame)
    assert bearing.size > 30
    assert np.mean(bearing) == pytest.approx(0.0, abs=0.005)
    assert np.ptp(bearing) == pytest.approx(2.0 * math.asin(BALL_RADIUS / 2.0), abs=0.015)
    centre = MIRROR.radius(MIRROR.ground_distance(2.0, BALL_RADIUS))
    assert radius.min() < centre < radius.max()
    assert radius.min() >= MIRROR.radius(2.0 - BALL_RADIUS) - 1.0
    assert radius.max() <= MIRROR.radius(MIRROR.ground_distance(2.0 + BALL_RADIUS, 2.0 * BALL_RADIUS)) + 1.0
    red, green, blue = frame.image[frame.labels == ColorClass.BALL].astype(float).mean(axis=0)
    assert red > green + 50 > blue + 50, "orange"


def test_a_lofted_ball_appears_farther_out_and_not_at_all_above_the_viewpoint(steady):
    """The same ground point with the ball 0.4 m up: the blob lies wholly outside the grounded ball's, around
    the radius of its centre's ray; at or above the viewpoint the ball is not seen."""
    me = still(-5.0, -3.0)
    grounded = steady.render(me, ball_at(-3.0, -3.0), [], 0.0, np.random.default_rng(0), labels=True)
    lofted = steady.render(me, ball_at(-3.0, -3.0, 0.4), [], 0.0, np.random.default_rng(0), labels=True)
    _, low = ball_pixels(grounded)
    bearing, high = ball_pixels(lofted)
    assert high.size > 0 and high.min() > low.max()
    assert np.mean(bearing) == pytest.approx(0.0, abs=0.005)
    assert np.min(np.abs(high - MIRROR.radius(MIRROR.ground_distance(2.0, 0.4)))) < 1.0
    for z in (MIRROR.viewpoint_height, 1.5):
        frame = steady.render(me, ball_at(-3.0, -3.0, z), [], 0.0, np.random.default_rng(0), labels=True)
        assert not np.any(frame.labels == ColorClass.BALL), z


def test_a_robot_three_metres_left_blacks_out_a_wedge_to_the_rim(steady):
    """A robot 3 m to the left hides the bearings within asin(R / 3) of the left, from its near side out to the
    rim, in black; the ground before it and the bearings beside the wedge stay visible."""
    frame = steady.render(still(-5.0, -3.0), CORNER_BALL, [still(-5.0, 0.0)], 0.0, np.random.default_rng(0),
                          labels=True)
    d, half = 3.0, math.asin(ROBOT_RADIUS / 3.0)
    off = np.abs(BEARING - math.pi / 2)
    ring = (RADIUS > MIRROR.r_min + 2) & (RADIUS < MIRROR.r_max - 1) & (off < 0.4)  # clear of the struts
    inside = off < half
    # Where each bearing's ray first meets the cylinder (on the ground: a circle of radius R at distance d).
    near_side = d * np.cos(off) - np.sqrt(np.maximum(ROBOT_RADIUS ** 2 - (d * np.sin(off)) ** 2, 0.0))
    near_edge = MIRROR.radius(near_side)
    margin = 2.5 / np.maximum(RADIUS, 1.0)  # 2.5 px, as an angle: labels leave out the blended edge
    behind = ring & (off < half - margin) & (RADIUS > near_edge + 2.5)
    assert behind.sum() > 300
    assert np.all(frame.labels[behind] == ColorClass.BLACK)
    assert grey(frame.image)[behind].max() < 40
    beside = ring & (off > half + margin)
    before = ring & inside & (RADIUS < near_edge - 2.5)
    assert beside.sum() > 1000 and before.sum() > 1000
    assert not np.any(frame.labels[beside | before] == ColorClass.BLACK)
    far_ring = ring & (RADIUS > 214) & (RADIUS < 216) & (frame.labels == ColorClass.BLACK)
    assert np.ptp(BEARING[far_ring]) == pytest.approx(2.0 * half, abs=0.02), "the wedge is 2 asin(R / d) wide"


def test_a_ball_in_front_of_a_robot_shows_and_one_behind_it_does_not(steady):
    """Bodies hide what lies radially behind them: a ball 1 m ahead of a robot standing 2 m ahead is seen (over
    the robot's wedge), a ball 3.5 m ahead is not."""
    me, robot = still(-5.0, -3.0), [still(-3.0, -3.0)]
    front = steady.render(me, ball_at(-4.0, -3.0), robot, 0.0, np.random.default_rng(0), labels=True)
    behind = steady.render(me, ball_at(-1.5, -3.0), robot, 0.0, np.random.default_rng(0), labels=True)
    assert np.sum(front.labels == ColorClass.BALL) > 50
    assert not np.any(behind.labels == ColorClass.BALL)
    straight_up = pixels_along(0.0, np.array([MIRROR.radius(2.0 + ROBOT_RADIUS), MIRROR.r_max - 2]))
    assert np.all(front.labels[straight_up] == ColorClass.BLACK)


def test_the_goal_posts_are_white_wedges_and_the_goal_inside_is_darker(steady):
    """Facing the +x goal from 2.5 m: each post hides a white wedge from its near side to the rim; the ground
    inside the goal is darker than the carpet and not labelled as carpet."""
    me = still(6.5, 0.5)
    frame = steady.render(me, CORNER_BALL, [], 0.0, np.random.default_rng(0), labels=True)
    for px, py in WORLD.field.goal_posts(1):
        bx, by = px - me.x, py - me.y
        d = math.hypot(bx, by)
        rows, cols = pixels_along(math.atan2(by, bx), np.array([MIRROR.radius(d + 0.1), MIRROR.r_max - 3]))
        assert np.all(frame.labels[rows, cols] == ColorClass.WHITE), (px, py)
    inside = (9.3 - me.x, 0.0 - me.y)  # a point on the ground inside the goal
    rows, cols = pixels_along(math.atan2(inside[1], inside[0]), np.array([MIRROR.radius(math.hypot(*inside))]))
    assert frame.labels[rows, cols][0] == ColorClass.UNKNOWN
    carpet = np.median(grey(frame.image)[frame.labels == ColorClass.GREEN])
    assert grey(frame.image)[rows, cols][0] < carpet - 20


def test_the_own_body_fills_the_centre_and_outside_the_rim_is_black(camera):
    """Inside r_min: the robot's own body (dark, labelled black), as are its mirror holder's struts across the
    ring; outside r_max every pixel is exactly black and unlabelled, noise and lighting notwithstanding."""
    frame = camera.render(still(0.0, 0.0), CORNER_BALL, [], 20.0, np.random.default_rng(3), labels=True)
    body = RADIUS < MIRROR.r_min - 1.0
    assert np.all(frame.labels[body] == ColorClass.BLACK)
    assert grey(frame.image)[body].mean() < 40
    outside = RADIUS > MIRROR.r_max + 0.5
    assert np.all(frame.image[outside] == 0) and np.all(frame.labels[outside] == ColorClass.UNKNOWN)
    for strut in camera.params.strut_angles_deg:
        rows, cols = pixels_along(math.radians(strut), np.arange(int(MIRROR.r_min) + 5, int(MIRROR.r_max) - 2))
        assert np.all(frame.labels[rows, cols] == ColorClass.BLACK), strut
    assert np.mean(frame.labels[(RADIUS > MIRROR.r_min) & (RADIUS < MIRROR.r_max)] == ColorClass.BLACK) < 0.1


def blend_share(pixels: np.ndarray, rgb, scene: np.ndarray) -> np.ndarray:
    """For each pixel, the least share t of another scene colour o that explains it as (1 - t) rgb + t o
    (within 6 grey levels); 1 where no single other colour explains it."""
    c = np.array(rgb, float)
    best = np.ones(len(pixels))
    for other in scene:
        step = other - c
        if not np.any(step):
            continue
        t = np.clip((pixels - c) @ step / (step @ step), 0.0, 1.0)
        fits = np.linalg.norm(pixels - c - t[:, None] * step, axis=1) <= 6.0
        best = np.where(fits, np.minimum(best, t), best)
    return best


def test_labelled_pixels_show_their_class_colour_unblended(steady):
    """Labels are for calibrating colours: a pixel labelled with a class shows that class's colour blended with
    at most a quarter of another; edges, and far lines that blend into the carpet, are UNKNOWN."""
    params = steady.params
    colours = {ColorClass.GREEN: params.carpet_rgb, ColorClass.WHITE: params.line_rgb,
               ColorClass.BALL: params.ball_rgb, ColorClass.BLACK: params.robot_rgb}
    scene = np.array(list(colours.values()) + [params.goal_inside_rgb, params.surround_rgb], float)
    me = still(6.0, -1.0, 0.3)  # the goal, lines near and far, a ball and robots in view
    others = [still(7.5, 0.0), still(4.5, -2.5), still(6.0, 1.5)]
    frame = steady.render(me, ball_at(7.0, -1.5), others, 0.0, np.random.default_rng(0), labels=True)
    for label, rgb in colours.items():
        pixels = frame.image[frame.labels == label].astype(float)
        assert len(pixels) > 50, label
        assert blend_share(pixels, rgb, scene).max() <= 0.27, label
    assert np.mean(frame.labels[(RADIUS > MIRROR.r_min) & (RADIUS < MIRROR.r_max)] == ColorClass.UNKNOWN) < 0.2


def test_the_same_seed_gives_the_same_image_and_another_seed_another(camera, steady):
    """All randomness comes from the generator passed in: equal seeds give identical images and leave the
    generators in the same state, other seeds other noise; without noise the seed does not matter."""
    me, ball, others = still(1.0, 2.0, 0.7), ball_at(2.0, 1.0), [still(3.0, 3.0), still(-1.0, 0.5)]
    first_rng, second_rng = np.random.default_rng(11), np.random.default_rng(11)
    first = camera.render(me, ball, others, 5.0, first_rng, labels=True)
    second = camera.render(me, ball, others, 5.0, second_rng, labels=True)
    assert np.array_equal(first.image, second.image) and np.array_equal(first.labels, second.labels)
    assert first_rng.random() == second_rng.random()
    other = camera.render(me, ball, others, 5.0, np.random.default_rng(12))
    assert np.mean(other.image != first.image) > 0.5
    quiet = [steady.render(me, ball, others, 5.0, np.random.default_rng(seed)).image for seed in (11, 12)]
    assert np.array_equal(*quiet)


def test_the_pixel_noise_has_the_configured_spread(camera):
    """Against the noise-free image, the noise on unsaturated carpet pixels has mean 0 and std noise_std."""
    params = camera.params
    clean = OmniCameraRenderer(WORLD, MIRROR, OmniCameraParams(noise_std=0.0))
    scene: tuple[RobotState, BallState, list[RobotState], float] = (still(-2.0, 3.0, 1.0), CORNER_BALL, [], 7.0)
    noisy = camera.render(*scene, np.random.default_rng(5), labels=True)
    exact = clean.render(*scene, np.random.default_rng(5))
    carpet = cv2.erode((noisy.labels == ColorClass.GREEN).astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    diff = noisy.image[carpet].astype(float) - exact.image[carpet].astype(float)
    assert diff.mean() == pytest.approx(0.0, abs=0.1)
    assert diff.std() == pytest.approx(params.noise_std, rel=0.05)


def carpet_pixels(frame) -> np.ndarray:
    """Carpet pixels away from any other class (no blended edges)."""
    return cv2.erode((frame.labels == ColorClass.GREEN).astype(np.uint8), np.ones((5, 5), np.uint8)) > 0


def test_each_carpet_pixel_shows_the_lighting_of_the_ground_point_it_sees():
    """With a strong, short lighting pattern (amplitude 0.5, wavelength 2 m), every carpet pixel, near (fine
    texture) and far (coarse texture), is the carpet colour times 1 + A cos(kx) cos(ky) at the world point the
    mirror model says it shows: the texture is world-fixed and each level is where it should be."""
    params = OmniCameraParams(noise_std=0.0, lighting_time_amplitude=0.0, lighting_field_amplitude=0.5,
                              lighting_wavelength=2.0)
    camera = OmniCameraRenderer(WORLD, MIRROR, params)
    me = still(-2.5, 1.5, 0.4)
    frame = camera.render(me, CORNER_BALL, [], 0.0, np.random.default_rng(0), labels=True)
    carpet = carpet_pixels(frame)
    bx, by = MIRROR.pixel_to_body(*np.nonzero(carpet)[::-1])
    c, s = math.cos(me.theta), math.sin(me.theta)
    light = params.field_lighting(me.x + c * bx - s * by, me.y + s * bx + c * by)
    error = np.abs(frame.image[carpet][:, 1] - params.carpet_rgb[1] * light)
    far = np.hypot(bx, by) > camera.split_distance
    assert far.sum() > 1000 and (~far).sum() > 10000
    assert error[~far].max() <= 1.5
    assert np.percentile(error[far], 99) <= 2.5 and error[far].max() <= 6.0  # a few pixels blend a far line


def test_the_lighting_across_the_field_is_as_strong_as_configured():
    """Near a bright and a dark spot of the default lighting the carpet's brightness differs by about
    (1 + A) / (1 - A)."""
    params = OmniCameraParams(noise_std=0.0, lighting_time_amplitude=0.0)
    camera = OmniCameraRenderer(WORLD, MIRROR, params)
    near = RADIUS < MIRROR.radius(0.7)
    means = []
    for spot in (still(-4.0, -4.0), still(-4.0, 0.0)):  # lighting 1 + A and 1 - A
        view = camera.render(spot, CORNER_BALL, [], 0.0, np.random.default_rng(0), labels=True)
        means.append(view.image[carpet_pixels(view) & near][:, 1].mean())
    amplitude = params.lighting_field_amplitude
    assert means[0] / means[1] == pytest.approx((1 + amplitude) / (1 - amplitude), rel=0.1)


def test_the_lighting_changes_slowly_over_time_by_the_configured_amplitude():
    """At a quarter and three quarters of the lighting period the whole carpet is 1 + B and 1 - B times as
    bright as at time 0."""
    params = OmniCameraParams(noise_std=0.0, lighting_field_amplitude=0.0)
    camera = OmniCameraRenderer(WORLD, MIRROR, params)
    period, amplitude = params.lighting_period, params.lighting_time_amplitude
    frames = [camera.render(still(1.0, -2.0), CORNER_BALL, [], t, np.random.default_rng(0), labels=True)
              for t in (0.0, period / 4, 3 * period / 4)]
    carpet = carpet_pixels(frames[0])
    base, bright, dark = (frame.image[carpet][:, 1].mean() for frame in frames)
    assert bright / base == pytest.approx(1 + amplitude, rel=0.01)
    assert dark / base == pytest.approx(1 - amplitude, rel=0.01)


def test_an_image_without_labels_is_an_rgb_image_of_the_mirror_size(camera):
    frame = camera.render(still(0.0, 0.0), CORNER_BALL, [], 0.0, np.random.default_rng(0))
    assert frame.labels is None
    assert frame.image.shape == (MIRROR.height, MIRROR.width, 3) and frame.image.dtype == np.uint8


def test_parameters_load_from_a_mapping():
    """The node reads its YAML into the dataclass: lists become tuples, values are checked."""
    params = from_mapping(OmniCameraParams, {"carpet_rgb": [10, 100, 20], "strut_angles_deg": [0, 120, 240],
                                             "noise_std": 2})
    assert params.carpet_rgb == (10, 100, 20) and params.strut_angles_deg == (0.0, 120.0, 240.0)
    assert params.noise_std == 2.0


@pytest.mark.parametrize(("field", "value", "message"), [
    ("lighting_field_amplitude", 1.0, "lighting_field_amplitude must lie in"),
    ("lighting_time_amplitude", -0.1, "lighting_time_amplitude must lie in"),
    ("lighting_wavelength", 0.0, "lighting_wavelength must be positive"),
    ("lighting_period", -5.0, "lighting_period must be positive"),
    ("noise_std", 41.0, "noise_std must lie in"),
    ("texture_resolution", 0.5, "texture_resolution must lie in"),
    ("carpet_rgb", (0, 0, 256), "carpet_rgb must be three integers"),
    ("ball_rgb", (255, 0), "ball_rgb must be three integers"),
    ("strut_angles_deg", (0.0, math.nan), "strut_angles_deg must be"),
    ("strut_width", -1.0, "strut_width must lie in"),
])
def test_bad_parameters_are_refused_naming_the_field(field, value, message):
    with pytest.raises(ValueError, match=message):
        OmniCameraParams(**{field: value})

"""Unit tests of the Fig. 13 experiment's core (PathTracker) on a kinematic robot."""

import math

import numpy as np
import pytest

from nubot_common.geometry import Pose2D, rotate
from nubot_common.world_description import WorldDescription
from nubot_control.params import MotionParams
from nubot_control.path_tracking import PathTracker, PathTrackingParams

DT = 1 / 33


def run(tracker, seconds, start=(-6.0, -3.0), obstacles=((-4.0, 0.0), (0.0, 0.0))):
    pose, samples = Pose2D(*start, 0.0), []
    for k in range(int(seconds / DT)):
        (bx, by, w), sample = tracker.step(k * DT, pose, list(obstacles))
        samples.append(sample)
        vx, vy = rotate(bx, by, pose.theta)
        pose = Pose2D(pose.x + vx * DT, pose.y + vy * DT, pose.theta + w * DT)
    return pose, samples


@pytest.mark.parametrize("tracker", ["mpc", "baseline"])
def test_stands_still_for_the_start_delay_then_drives_to_p3_and_finishes(tracker):
    params = PathTrackingParams(start_delay=1.0, motion=MotionParams(tracker=tracker, max_speed=3.25))
    pose, samples = run(PathTracker(params, WorldDescription()), 16.0)
    assert all(s.command == (0.0, 0.0) for s in samples[:32]), "still during the start delay"
    assert samples[40].command != (0.0, 0.0)
    done = next(k for k, s in enumerate(samples) if s.finished)
    assert math.dist((pose.x, pose.y), params.waypoints[-1]) < params.arrive_tolerance
    assert all(s.finished and s.command == (0.0, 0.0) for s in samples[done + 1:]), "it stays finished and still"
    assert max(math.hypot(*s.command) for s in samples) <= 3.25 + 1e-6


@pytest.mark.parametrize("seed", [0, 6, 25])
def test_on_a_base_that_lags_and_a_noisy_pose_the_robot_really_ends_within_a_tenth_of_a_metre_of_p3(seed):
    """Over ROS the Fig. 13 run once ended 0.11 m from p3: the robot saw itself within the tolerance at the slow turn
    of a small overshoot (its pose has 2 cm of noise, its base follows a command in about 0.1 s). These seeds ended
    0.10-0.14 m off with a 0.1 m tolerance on the seen pose."""
    params = PathTrackingParams(start_delay=0.0, motion=MotionParams(max_speed=3.25))
    tracker = PathTracker(params, WorldDescription())
    rng = np.random.default_rng(seed)
    x, y, vx, vy = -6.0, -3.0, 0.0, 0.0
    follow = DT / 0.12  # the base closes this share of the gap to its command each cycle
    for k in range(int(16.0 / DT)):
        seen = Pose2D(x + 0.02 * rng.standard_normal(), y + 0.02 * rng.standard_normal(), 0.0)
        (bx, by, _), sample = tracker.step(k * DT, seen, [(-4.0, 0.0), (0.0, 0.0)])
        if sample.finished:
            break
        vx, vy = vx + (bx - vx) * follow, vy + (by - vy) * follow
        x, y = x + vx * DT, y + vy * DT
    assert sample.finished
    for _ in range(30):  # it coasts to a stop
        vx, vy = vx * (1 - follow), vy * (1 - follow)
        x, y = x + vx * DT, y + vy * DT
    assert math.dist((x, y), params.waypoints[-1]) < 0.1


def test_mpc_error_to_the_reference_stays_small_on_a_kinematic_robot():
    params = PathTrackingParams(start_delay=0.0, motion=MotionParams(max_speed=3.25))
    _, samples = run(PathTracker(params, WorldDescription()), 12.0)
    errors = [s.error for s in samples if not s.finished]
    assert max(errors) < 0.05 and sum(e * e for e in errors) / len(errors) < 0.02 ** 2


def test_a_stale_pose_is_carried_forward_with_the_commanded_velocity():
    params = PathTrackingParams(start_delay=0.0, waypoints=((5.0, 0.0),), motion=MotionParams(max_speed=2.0))
    tracker = PathTracker(params, WorldDescription())
    pose = Pose2D(0.0, 0.0, 0.0)
    for k in range(30):
        tracker.step(k * DT, pose, [])
    vx, _ = tracker.motion.velocity
    _, sample = tracker.step(30 * DT, pose, [], seen_at=30 * DT - 0.05)
    assert sample.position[0] == pytest.approx(vx * 0.05, abs=1e-6)


@pytest.mark.parametrize("waypoints", [(), ((1.0, math.nan),)])
def test_bad_waypoints_are_refused(waypoints):
    with pytest.raises(ValueError, match="waypoint"):
        PathTrackingParams(waypoints=waypoints)

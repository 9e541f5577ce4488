"""Unit tests of the go-to motion with obstacle avoidance."""

import math

import pytest

from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D, rotate
from nubot_control.motion import MotionController, sub_target
from nubot_control.params import MotionParams

P = MotionParams()


def drive(start, target, obstacles, seconds=8.0, dt=1 / 33):
    """Integrate the commands kinematically; return the path."""
    ctl = MotionController(P, FieldGeometry())
    pose, path = start, [start]
    for _ in range(int(seconds / dt)):
        bx, by, w = ctl.command(pose, target, obstacles, dt)
        vx, vy = rotate(bx, by, pose.theta)
        pose = Pose2D(pose.x + vx * dt, pose.y + vy * dt, pose.theta + w * dt)
        path.append(pose)
    return path, ctl


def test_reaches_the_target_pose():
    path, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(4.0, -2.0, 1.5), [])
    end = path[-1]
    assert (end.x, end.y, end.theta) == pytest.approx((4.0, -2.0, 1.5), abs=0.03)


def test_speed_and_acceleration_stay_within_limits():
    path, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(8.0, 0.0, 0.0), [], seconds=5.0)
    dt = 1 / 33
    speeds = [math.hypot(b.x - a.x, b.y - a.y) / dt for a, b in zip(path, path[1:])]
    assert max(speeds) <= P.max_speed + 1e-6
    accels = [abs(b - a) / dt for a, b in zip(speeds, speeds[1:])]
    assert max(accels) <= P.max_accel + 1e-6


@pytest.mark.parametrize("offset", [0.0, 0.2, -0.3])
def test_never_drives_through_an_obstacle(offset):
    obstacles = [(3.0, offset), (5.0, -offset)]
    path, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(8.0, 0.0, 0.0), obstacles, seconds=10.0)
    closest = min(math.hypot(p.x - ox, p.y - oy) for p in path for ox, oy in obstacles)
    assert closest > 2 * P.robot_radius, "the hulls never touch"
    assert path[-1].x == pytest.approx(8.0, abs=0.05)


def test_sub_target_is_the_goal_when_the_way_is_free():
    assert sub_target((0.0, 0.0), (5.0, 0.0), [(2.0, 3.0)], 0.8) == (5.0, 0.0)
    aside = sub_target((0.0, 0.0), (5.0, 0.0), [(2.5, 0.1)], 0.8)
    assert aside != (5.0, 0.0) and abs(aside[1] - 0.1) >= 0.8

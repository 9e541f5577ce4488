"""Unit tests of planned_path: the motion layer's plan as a few points, from the robot to the goal."""

import math

import pytest

from nubot_common.geometry import Pose2D, rotate
from nubot_common.world_description import WorldDescription
from nubot_control.motion import MotionController
from nubot_control.params import MotionParams
from nubot_control.planned_path import MAX_POINTS, MIN_SPACING, planned_path

DT = 1 / 33
TRACKERS = ["mpc", "baseline"]


def drive(ctl, pose, target, obstacles=(), cycles=1, waypoints=None):
    """Run ``cycles`` control cycles on a kinematic robot; return its pose."""
    for _ in range(cycles):
        if waypoints is None:
            bx, by, w = ctl.command(pose, target, list(obstacles), DT)
        else:
            bx, by, w = ctl.follow(pose, waypoints, target.theta, list(obstacles), DT)
        vx, vy = rotate(bx, by, pose.theta)
        pose = Pose2D(pose.x + vx * DT, pose.y + vy * DT, pose.theta + w * DT)
    return pose


def controller(tracker):
    return MotionController(MotionParams(tracker=tracker), WorldDescription(), DT)


@pytest.mark.parametrize("tracker", TRACKERS)
def test_no_plan_no_path(tracker):
    ctl = controller(tracker)
    assert planned_path(ctl) == []
    drive(ctl, Pose2D(0.0, 0.0, 0.0), Pose2D(3.0, 1.0, 0.0))
    assert planned_path(ctl)
    ctl.reset()  # what a STOP does
    assert planned_path(ctl) == []


@pytest.mark.parametrize("tracker", TRACKERS)
def test_the_path_runs_from_the_robot_to_the_goal(tracker):
    ctl = controller(tracker)
    pose = drive(ctl, Pose2D(-4.0, -1.0, 0.0), Pose2D(5.0, 2.0, 0.0), cycles=10)
    path = planned_path(ctl)
    assert 2 <= len(path) <= MAX_POINTS
    assert path[0] == pytest.approx(ctl.position)
    assert math.dist(path[0], (pose.x, pose.y)) < 0.2  # the robot before its last step
    assert path[-1] == pytest.approx((5.0, 2.0), abs=1e-6)
    to_goal = [math.dist(p, (5.0, 2.0)) for p in path]
    # the plan's point for now is within a centimetre of the robot, which may be a hair ahead of it
    assert to_goal[1] < to_goal[0] + 0.01, f"the plan is where the robot is: {path}"
    assert all(b < a for a, b in zip(to_goal[1:], to_goal[2:])), f"a straight path leads towards the goal: {path}"


def test_a_long_mpc_path_keeps_its_shape_in_at_most_max_points():
    """Around an obstacle in the way the points bend round it, each outside the robot's clearance."""
    ctl = controller("mpc")
    obstacle = (0.0, 0.0)
    drive(ctl, Pose2D(-6.0, 0.0, 0.0), Pose2D(6.0, 0.05, 0.0), obstacles=[obstacle])
    path = planned_path(ctl)
    assert len(path) == MAX_POINTS
    radius = WorldDescription().robot.radius
    assert min(math.dist(p, obstacle) for p in path) > 2 * radius
    assert max(abs(p[1]) for p in path) > 2 * radius, "the path goes round the obstacle"
    steps = [math.dist(a, b) for a, b in zip(path[1:], path[2:])]
    assert max(steps) < 1.5 * min(steps), "evenly spaced along the path"


def test_a_short_path_has_few_points():
    ctl = controller("mpc")
    drive(ctl, Pose2D(0.0, 0.0, 0.0), Pose2D(0.5, 0.0, 0.0))
    path = planned_path(ctl)
    assert 3 <= len(path) <= math.ceil(0.5 / MIN_SPACING) + 2
    assert path[-1] == pytest.approx((0.5, 0.0), abs=1e-6)


def test_the_mpc_path_starts_where_the_plan_has_the_robot_now():
    """What the robot has travelled is not drawn: the first planned point moves along with it."""
    ctl = controller("mpc")
    pose = drive(ctl, Pose2D(-5.0, 0.0, 0.0), Pose2D(5.0, 0.0, 0.0), cycles=40)
    path = planned_path(ctl)
    assert pose.x > -4.0
    assert path[1][0] == pytest.approx(ctl.reference[0][0], abs=0.05)
    assert all(p[0] >= path[1][0] - 1e-6 for p in path[1:])


def test_the_baseline_path_is_the_robot_and_the_waypoints_left():
    ctl = controller("baseline")
    route = [(-2.0, 2.0), (0.0, 2.0), (2.0, 0.0)]
    pose = drive(ctl, Pose2D(-2.0, 1.9, 0.0), Pose2D(2.0, 0.0, 0.0), waypoints=route)
    assert planned_path(ctl) == [ctl.position, (0.0, 2.0), (2.0, 0.0)]  # the first waypoint was reached
    assert ctl.position == pytest.approx((-2.0, 1.9))
    assert pose.x != -2.0 or pose.y != 1.9


def test_a_long_baseline_route_keeps_the_next_waypoints_and_the_goal():
    ctl = controller("baseline")
    route = [(float(x), 1.0) for x in range(-8, 8)]
    drive(ctl, Pose2D(-8.0, -3.0, 0.0), Pose2D(7.0, 1.0, 0.0), waypoints=route)
    path = planned_path(ctl, max_points=5)
    assert path == [ctl.position, (-8.0, 1.0), (-7.0, 1.0), (-6.0, 1.0), (7.0, 1.0)]


def test_bad_limits_are_refused():
    with pytest.raises(ValueError, match="max_points >= 2"):
        planned_path(controller("mpc"), max_points=1)


def test_the_message_round_trips_in_the_team_frame():
    from io import BytesIO

    from nubot_common import conversions as conv
    from nubot_common.msg import PlannedPath

    msg = conv.planned_path_msg([(0.5, -1.25), (2.0, 3.5)], 12.5, "rival")
    buffer = BytesIO()
    msg.serialize(buffer)
    back = PlannedPath().deserialize(buffer.getvalue())
    assert conv.planned_path(back) == [(0.5, -1.25), (2.0, 3.5)]
    assert (back.header.frame_id, back.header.stamp.to_sec()) == ("rival", 12.5)
    assert conv.planned_path(conv.planned_path_msg([], 1.0, "nubot")) == []

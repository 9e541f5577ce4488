"""Percepts: what a teammate's report says a moment later."""

import dataclasses
import math

import pytest

from nubot_common.geometry import Pose2D
from nubot_common.percepts import RobotReport
from nubot_common.team_play import Role


def test_a_report_moved_on_is_the_report_built_anew_at_the_new_pose():
    """Every field but the pose as it was, the pose moved on at the reported velocity, the heading wrapped; equal to
    (and hashing like) the same report built through its constructor, and the original unchanged."""
    report = RobotReport(3, Pose2D(1.0, -2.0, 3.1), vx=1.5, vy=-0.5, w=2.0, holding=True, role=Role.ACTIVE,
                         role_time=4.0, target_nums=(1, 2, 3, 4), static_pass=2, target=(0.5, 0.5))
    moved = report.moved_on(0.1)
    expected = dataclasses.replace(report, pose=Pose2D(1.15, -2.05, 3.3 - 2.0 * math.pi))
    assert moved.pose.x == pytest.approx(expected.pose.x) and moved.pose.y == pytest.approx(expected.pose.y)
    assert moved.pose.theta == pytest.approx(expected.pose.theta)
    assert dataclasses.replace(moved, pose=expected.pose) == expected
    assert hash(dataclasses.replace(moved, pose=expected.pose)) == hash(expected)
    assert type(moved) is RobotReport and report.pose == Pose2D(1.0, -2.0, 3.1)
    assert report.moved_on(0.0) is report
    with pytest.raises(dataclasses.FrozenInstanceError):
        moved.vx = 0.0  # type: ignore[misc]


def test_a_replaced_report_is_what_dataclasses_replace_makes():
    report = RobotReport(3, Pose2D(1.0, -2.0, 0.5), vx=0.4, holding=True, target_nums=(1, 2, 3, 4))
    changes = {"role": Role.ACTIVE, "role_time": 2.5, "target": (4.0, 1.0), "static_pass": 2}
    made = report.replaced(**changes)
    assert made == dataclasses.replace(report, **changes) and made is not report
    assert hash(made) == hash(dataclasses.replace(report, **changes))
    assert report.role == Role.NOROLE  # the original is left as it was
    with pytest.raises(TypeError, match="no field colour"):
        report.replaced(colour="red")

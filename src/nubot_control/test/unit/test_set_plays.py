"""Set-play formations obey the MSL distance rules."""

import math

import pytest

from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D
from nubot_common.match_mode import OUR_SET_PLAYS, THEIR_SET_PLAYS, MatchMode
from nubot_common.percepts import RobotReport
from nubot_common.team_play import Role
from nubot_common.world_state import FusedBall
from nubot_control.areas import AREA_MARGIN, in_area
from nubot_control.params import PlayParams
from nubot_control.set_plays import HOLD_DISTANCE, KeptFormation, formation

FIELD, PLAY = FieldGeometry(), PlayParams(goalie_id=1)
TEAM = [RobotReport(i, Pose2D(x, y, 0.0)) for i, (x, y) in
        {1: (-8.5, 0.0), 2: (1.0, 0.0), 3: (-2.0, 3.0), 4: (-4.0, -2.0), 5: (-6.0, 0.0)}.items()]
ROLES = {1: Role.GOALIE, 2: Role.ACTIVE, 3: Role.ASSISTANT, 4: Role.PASSIVE, 5: Role.MIDFIELD}
BALLS = [FusedBall(0.0, 0.0), FusedBall(4.0, 5.9), FusedBall(-8.9, -5.9), FusedBall(-6.0, 0.5), FusedBall(8.0, -3.0),
         FusedBall(-8.0, 0.9), FusedBall(-8.9, 0.0)]  # the last two near the own goal: the goalie has to step aside


@pytest.mark.parametrize("ball", BALLS)
@pytest.mark.parametrize("mode", sorted(THEIR_SET_PLAYS - {MatchMode.OPP_PENALTY, MatchMode.OPP_KICKOFF}))
def test_opponent_set_pieces_keep_three_metres(mode, ball):
    plan = formation(mode, ball, TEAM, ROLES, FIELD, PLAY)
    assert set(plan.targets) == {1, 2, 3, 4, 5}
    for agent, pose in plan.targets.items():
        assert math.hypot(pose.x - ball.x, pose.y - ball.y) >= 3.0, f"robot {agent} too close at {mode.name}"
        assert FIELD.is_inside(pose.x, pose.y), f"robot {agent} sent off the field (behind a goal) at {pose}"


def _apart(plan, metres=0.8):
    poses = sorted(plan.targets.items())
    for k, (a, p) in enumerate(poses):
        for b, q in poses[k + 1:]:
            assert math.hypot(p.x - q.x, p.y - q.y) >= metres, f"robots {a} and {b} sent to the same spot"


@pytest.mark.parametrize("ball", BALLS + [FusedBall(-7.0, 3.5), FusedBall(-5.0, -2.0), FusedBall(-6.5, -4.0)])
@pytest.mark.parametrize("mode", [MatchMode.OPP_FREEKICK, MatchMode.OPP_CORNERKICK, MatchMode.OPP_THROWIN])
def test_defenders_wait_apart_and_outside_the_penalty_areas(mode, ball):
    """Near the own goal the ring around the ball crosses the penalty area, which the motion layer walls the field
    robots out of: each gets its own spot beyond the wall instead of all being pushed onto the same part of it."""
    plan = formation(mode, ball, TEAM, ROLES, FIELD, PLAY)
    _apart(plan)
    for agent in (2, 3, 4, 5):
        pose = plan.targets[agent]
        for own in (True, False):
            assert not in_area(pose.x, pose.y, FIELD, own, margin=AREA_MARGIN), f"robot {agent} at {pose}"
        assert math.hypot(pose.x - ball.x, pose.y - ball.y) >= 3.3 - 1e-9


def test_defenders_away_from_the_goal_stand_on_the_ring_between_ball_and_goal():
    ball = FusedBall(0.0, 0.0)
    plan = formation(MatchMode.OPP_FREEKICK, ball, TEAM, ROLES, FIELD, PLAY)
    for agent in (2, 3, 4, 5):
        pose = plan.targets[agent]
        assert math.hypot(pose.x - ball.x, pose.y - ball.y) == pytest.approx(3.3), "as close as the rule allows"
        assert pose.x < ball.x - 2.0, "goal side of the ball"


def test_kickoffs_keep_everyone_in_the_own_half():
    ball = FusedBall(0.0, 0.0)
    theirs = formation(MatchMode.OPP_KICKOFF, ball, TEAM, ROLES, FIELD, PLAY)
    for pose in theirs.targets.values():
        assert pose.x < 0.0
        assert math.hypot(pose.x, pose.y) > FIELD.center_circle_radius, "outside the centre circle"
    ours = formation(MatchMode.OUR_KICKOFF, ball, TEAM, ROLES, FIELD, PLAY)
    assert ours.taker == 2 and ours.receiver != 0
    assert all(pose.x < 0.0 for pose in ours.targets.values())
    taker = ours.targets[2]
    assert math.hypot(taker.x, taker.y) == pytest.approx(0.55) and abs(taker.theta) < 1e-6, "faces the ball"


@pytest.mark.parametrize("ball", BALLS)
def test_drop_ball_keeps_one_metre(ball):
    plan = formation(MatchMode.DROPBALL, ball, TEAM, ROLES, FIELD, PLAY)
    for pose in plan.targets.values():
        assert math.hypot(pose.x - ball.x, pose.y - ball.y) >= 1.0
        assert FIELD.is_inside(pose.x, pose.y)
    _apart(plan)
    active = plan.targets[2]
    assert not any(in_area(active.x, active.y, FIELD, own, goal_area=True, margin=AREA_MARGIN) for own in (True, False))


def test_the_goalie_steps_along_its_goal_line_out_of_a_set_pieces_circle():
    ball = FusedBall(-8.0, 0.9)
    goalie = formation(MatchMode.OPP_FREEKICK, ball, TEAM, ROLES, FIELD, PLAY).targets[1]
    assert goalie.x == pytest.approx(-FIELD.half_length + 0.4), "still on its line in front of the goal"
    assert math.hypot(goalie.x - ball.x, goalie.y - ball.y) == pytest.approx(3.3), "just outside the circle"
    assert goalie.y < 0.0, "on the side nearer its own spot, away from the ball"


@pytest.mark.parametrize("mode", sorted(OUR_SET_PLAYS - {MatchMode.OUR_KICKOFF, MatchMode.OUR_PENALTY}))
def test_our_restart_has_a_taker_at_the_ball_and_a_receiver_three_metres_away(mode):
    ball = FusedBall(3.0, 5.9)
    plan = formation(mode, ball, TEAM, ROLES, FIELD, PLAY)
    taker, receiver = plan.targets[plan.taker], plan.targets[plan.receiver]
    assert plan.taker == 2, "the active robot takes it"
    assert math.hypot(taker.x - ball.x, taker.y - ball.y) == pytest.approx(0.55)
    assert math.hypot(receiver.x - ball.x, receiver.y - ball.y) == pytest.approx(3.0, abs=0.6)
    assert FIELD.is_inside(receiver.x, receiver.y)


def test_opponent_penalty_leaves_only_the_goalie_near_the_goal():
    plan = formation(MatchMode.OPP_PENALTY, FusedBall(-6.0, 0.0), TEAM, ROLES, FIELD, PLAY)
    assert plan.targets[1].x < -8.0
    spot = (-FIELD.half_length + FIELD.penalty_mark_distance, 0.0)
    for agent in (2, 3, 4, 5):
        pose = plan.targets[agent]
        assert math.hypot(pose.x - spot[0], pose.y - spot[1]) >= 3.0
        assert pose.x > -FIELD.half_length + FIELD.penalty_area_length


def test_parking_lines_up_along_the_side_line():
    plan = formation(MatchMode.PARKINGROBOT, FusedBall(0.0, 0.0), TEAM, ROLES, FIELD, PLAY)
    ys = {round(p.y, 6) for p in plan.targets.values()}
    assert ys == {-FIELD.half_width - 0.5}
    xs = sorted(p.x for p in plan.targets.values())
    assert min(b - a for a, b in zip(xs, xs[1:])) >= 1.0, "robots park apart"


def test_a_kept_formation_stays_while_the_ball_estimate_wanders_and_is_made_anew_when_the_ball_is_moved():
    kept = KeptFormation()
    mode = MatchMode.OPP_FREEKICK
    first = kept.formation(mode, FusedBall(2.0, 1.0), TEAM, ROLES, FIELD, PLAY)
    assert first == formation(mode, FusedBall(2.0, 1.0), TEAM, ROLES, FIELD, PLAY)
    wandered = FusedBall(2.0 + 0.6 * HOLD_DISTANCE, 1.0 - 0.6 * HOLD_DISTANCE)
    assert kept.formation(mode, wandered, TEAM, ROLES, FIELD, PLAY) is first  # the spots do not follow the noise
    for agent, pose in first.targets.items():  # and still keep the rule's distance from the ball
        assert math.hypot(pose.x - wandered.x, pose.y - wandered.y) >= PLAY.set_play_distance, agent
    moved = FusedBall(2.0 + 1.5 * HOLD_DISTANCE, 1.0)
    again = kept.formation(mode, moved, TEAM, ROLES, FIELD, PLAY)
    assert again == formation(mode, moved, TEAM, ROLES, FIELD, PLAY) and again != first
    other_mode = kept.formation(MatchMode.OPP_CORNERKICK, moved, TEAM, ROLES, FIELD, PLAY)
    assert other_mode == formation(MatchMode.OPP_CORNERKICK, moved, TEAM, ROLES, FIELD, PLAY)
    fewer = TEAM[:4]
    assert set(kept.formation(MatchMode.OPP_CORNERKICK, moved, fewer, ROLES, FIELD, PLAY).targets) == {1, 2, 3, 4}
    swapped = {**ROLES, 3: Role.PASSIVE, 4: Role.ASSISTANT}
    assert (kept.formation(MatchMode.OPP_CORNERKICK, moved, fewer, swapped, FIELD, PLAY)
            == formation(MatchMode.OPP_CORNERKICK, moved, fewer, swapped, FIELD, PLAY))
    kept.clear()
    assert kept.formation(mode, wandered, TEAM, ROLES, FIELD, PLAY) == formation(mode, wandered, TEAM, ROLES, FIELD,
                                                                                  PLAY)

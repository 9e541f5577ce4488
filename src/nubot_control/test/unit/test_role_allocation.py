"""Unit tests of the hybrid distributed role allocation."""

import math
from dataclasses import replace

from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D
from nubot_common.percepts import RobotReport
from nubot_common.team_play import Role
from nubot_common.world_state import FusedBall
from nubot_control.params import MotionParams, PlayParams
from nubot_control.role_allocation import RoleAllocator, support_positions
from nubot_control.team_state import TeamState

FIELD = FieldGeometry()
ALLOCATOR = RoleAllocator(PlayParams(goalie_id=1), MotionParams(), FIELD)


def team(ball=(2.0, 0.0), overrides=None):
    overrides = overrides or {}
    poses = {1: (-8.5, 0.0), 2: (1.0, 0.0), 3: (-2.0, 3.0), 4: (-4.0, -2.0), 5: (-6.0, 0.0)}
    mates = [RobotReport(i, Pose2D(x, y, 0.0), **overrides.get(i, {})) for i, (x, y) in poses.items()]
    return mates, FusedBall(*ball)


def state_for(me_id, mates, ball, t=10.0):
    me = next(m for m in mates if m.agent_id == me_id)
    return TeamState(t, me, tuple(m for m in mates if m.agent_id != me_id), ball, (), FIELD)


def test_every_robot_computes_the_same_assignment():
    mates, ball = team()
    answers = [ALLOCATOR.assign(state_for(i, mates, ball)) for i in range(1, 6)]
    assert all(a == answers[0] for a in answers)
    roles = answers[0]
    assert roles[1] == Role.GOALIE and roles[2] == Role.ACTIVE, "the robot nearest the ball attacks"
    assert sorted(roles.values()) == sorted([Role.GOALIE, Role.ACTIVE, Role.PASSIVE, Role.ASSISTANT,
                                             Role.MIDFIELD])


def test_support_roles_go_to_the_nearest_robots():
    mates, ball = team()
    roles = ALLOCATOR.assign(state_for(2, mates, ball))
    spots = support_positions(ball, FieldGeometry())
    for agent, role in roles.items():
        if role in spots:
            mate = next(m for m in mates if m.agent_id == agent)
            others = [m for m in mates if roles[m.agent_id] in spots and m.agent_id != agent]
            # Swapping with any other support robot would not shorten the total distance.
            for other in others:
                mine = mate.pose.distance_to(*spots[role]) + other.pose.distance_to(*spots[roles[other.agent_id]])
                swapped = mate.pose.distance_to(*spots[roles[other.agent_id]]) + other.pose.distance_to(*spots[role])
                assert mine <= swapped + 1e-9


def test_a_teammate_that_drops_out_is_replaced():
    mates, ball = team()
    roles = ALLOCATOR.assign(state_for(3, mates, ball))
    assert roles[2] == Role.ACTIVE
    without = [m for m in mates if m.agent_id != 2]
    roles = ALLOCATOR.assign(state_for(3, without, ball))
    assert 2 not in roles
    assert Role.ACTIVE in roles.values(), "someone else attacks"
    assert sorted(roles.values()) == sorted([Role.GOALIE, Role.ACTIVE, Role.PASSIVE, Role.ASSISTANT])


def test_hysteresis_keeps_the_active_robot_against_a_slightly_faster_challenger():
    mates, ball = team(ball=(0.0, 0.0), overrides={3: {"role": Role.ACTIVE, "role_time": 5.0}})
    mates = [replace(m, pose=Pose2D(1.2, 0.0, math.pi)) if m.agent_id == 3 else m for m in mates]
    roles = ALLOCATOR.assign(state_for(2, mates, ball))
    assert roles[3] == Role.ACTIVE, "robot 2 is only a little faster: no switch"
    far = [replace(m, pose=Pose2D(6.0, 5.0, math.pi)) if m.agent_id == 3 else m for m in mates]
    roles = ALLOCATOR.assign(state_for(2, far, ball))
    assert roles[3] != Role.ACTIVE, "a much faster challenger takes over"
    assert roles[4] == Role.ACTIVE, "robot 4 (4.5 m away, facing the ball) is the fastest"


def test_the_ball_holder_is_always_active():
    mates, ball = team(overrides={4: {"holding": True}})
    assert ALLOCATOR.assign(state_for(2, mates, ball))[4] == Role.ACTIVE


def test_no_goalie_when_the_goalie_is_gone():
    mates, ball = team()
    roles = ALLOCATOR.assign(state_for(2, [m for m in mates if m.agent_id != 1], ball))
    assert Role.GOALIE not in roles.values()


def test_a_lost_ball_keeps_the_announced_attacker():
    """With the ball not known, nobody is nearer to it: the robot that was attacking stays the attacker."""
    mates, _ = team(overrides={3: {"role": Role.ACTIVE, "role_time": 5.0}})
    mates = [replace(m, pose=Pose2D(6.0, 5.0, math.pi)) if m.agent_id == 3 else m for m in mates]
    lost = FusedBall(0.0, 0.0, known=False)  # last seen at the centre spot, next to robot 2
    roles = ALLOCATOR.assign(state_for(2, mates, lost))
    assert roles[3] == Role.ACTIVE
    assert ALLOCATOR.assign(state_for(2, mates, FusedBall(0.0, 0.0)))[3] != Role.ACTIVE, "a seen ball does switch"


def test_a_lost_ball_with_no_attacker_goes_to_the_nearest_to_where_it_was_seen():
    mates, _ = team()
    roles = ALLOCATOR.assign(state_for(3, mates, FusedBall(1.5, 0.0, known=False)))
    assert roles[2] == Role.ACTIVE

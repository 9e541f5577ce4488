"""The strategy in an in-process match (simulator core, no ROS): kickoff, set pieces, open play."""

import math
from dataclasses import replace

import pytest

from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D, rotate
from nubot_common.match_mode import MatchMode
from nubot_common.percepts import RobotReport
from nubot_common.team_play import Role
from nubot_common.world_description import WorldDescription
from nubot_common.world_state import FusedBall
from nubot_control.behaviours import Action
from nubot_control.params import ControlParams
from nubot_control.strategy import Strategy
from nubot_control.team_state import TeamState
from sim_visual.params import NoiseParams

TEAMS = [("nubot1", -8.4, 0, 0), ("nubot2", -1.0, 0, 0), ("nubot3", -3, 2.5, 0), ("nubot4", -3, -2.5, 0),
         ("nubot5", -5.5, 0, 0), ("rival1", 8.4, 0, math.pi), ("rival2", 1.0, 0, math.pi),
         ("rival3", 3, -2.5, math.pi), ("rival4", 3, 2.5, math.pi), ("rival5", 5.5, 0, math.pi)]


def test_kickoff_formation_then_the_static_pass(make_match):
    match = make_match(TEAMS)
    match.command("nubot", MatchMode.OUR_KICKOFF)
    match.run(4.0)
    for name in ("rival2", "rival3", "rival4", "rival5"):
        s = match.sim.world.robot_state(name)
        assert s.x > 0.0 and math.hypot(s.x, s.y) > 2.0, f"{name} respects the opponent kickoff"
    taker = next(n for n, o in match.outputs.items() if o.role == Role.PASSOFPASS)
    receiver = next(n for n, o in match.outputs.items() if o.role == Role.CATCHOFPASS)
    assert taker.startswith("nubot") and receiver.startswith("nubot")
    match.command("nubot", MatchMode.STARTROBOT)
    kicks = []
    for _ in range(200):
        match.run(0.05)
        if match.sim.holder is not None and match.sim.holder != taker:
            kicks.append(match.sim.holder)
            break
    assert kicks and kicks[0] == receiver, "the kickoff pass reaches the receiver"


def test_a_short_match_moves_the_ball_and_everyone_keeps_a_role(make_match):
    match = make_match(TEAMS, mode=MatchMode.STARTROBOT)
    match.command("nubot", MatchMode.STARTROBOT)
    positions = []
    for _ in range(30):
        match.run(1.0)
        b = match.sim.world.ball_state()
        positions.append((b.x, b.y))
    travelled = sum(math.dist(a, b) for a, b in zip(positions, positions[1:]))
    assert travelled > 15.0
    for team in ("nubot", "rival"):
        roles = [o.role for n, o in match.outputs.items() if n.startswith(team)]
        assert roles.count(Role.GOALIE) == 1 and roles.count(Role.ACTIVE) <= 2


def test_stop_halts_every_robot(make_match):
    match = make_match(TEAMS)
    match.command("nubot", MatchMode.STARTROBOT)
    match.run(2.0)
    match.command("nubot", MatchMode.STOPROBOT)
    match.run(1.5)
    for name in match.agents:
        s = match.sim.world.robot_state(name)
        assert math.hypot(s.vx, s.vy) < 0.05, f"{name} still moves"


def team_state(me, mates, ball, opponents=(), mode=MatchMode.STARTROBOT, t=1.0):
    return TeamState(t, me, tuple(mates), ball, tuple(opponents), FieldGeometry(), mode)


def test_the_midfielder_marks_an_opponent_lurking_in_our_half():
    # With the ball at (4, 0) the support spots are: passive (-3.2, 0), assistant (6.5, 3), midfield (1.5, -2.5).
    mates = (RobotReport(1, Pose2D(-8.5, 0, 0)), RobotReport(2, Pose2D(3.5, 0, 0)), RobotReport(3, Pose2D(6, 3, 0)),
             RobotReport(5, Pose2D(-3, 0, 0)))
    me = RobotReport(4, Pose2D(1.5, -2.4, 0))
    lurker = (-5.0, -2.0)
    state = team_state(me, mates, FusedBall(4.0, 0.0), (lurker, (5.0, 1.0)))
    out = Strategy(ControlParams(), WorldDescription(), 4).step(state)
    assert out.role == Role.MIDFIELD and out.action == Action.MARK
    # Between the lurker and the own goal, 1 m from the lurker.
    assert math.dist(out.target, lurker) == pytest.approx(1.0)
    assert -9.0 < out.target[0] < lurker[0]


def drive(strategy, me, mates, ball, seconds, dt=1 / 33):
    """Run ``strategy`` for ``seconds``, moving ``me`` as commanded (an ideal base); return the poses."""
    poses = []
    for k in range(round(seconds / dt)):
        out = strategy.step(team_state(me, mates, ball, t=k * dt))
        vx, vy = rotate(out.velocity.vx, out.velocity.vy, me.pose.theta)
        me = replace(me, pose=Pose2D(me.pose.x + vx * dt, me.pose.y + vy * dt, me.pose.theta + out.velocity.w * dt))
        poses.append(me.pose)
    return poses, out


@pytest.mark.parametrize("last_seen", [(4.0, 0.0), (-1.0, 3.0)])
def test_a_robot_whose_ball_is_lost_does_not_chase_a_phantom(last_seen):
    """The attacker heads for where the ball was last seen, stops short of it and turns to look for it."""
    me = RobotReport(2, Pose2D(0.0, 0.0, 0.0), role=Role.ACTIVE, role_time=5.0)
    mates = (RobotReport(1, Pose2D(-8.5, 0, 0)),)
    lost = FusedBall(*last_seen, known=False)
    strategy = Strategy(ControlParams(), WorldDescription(), 2)
    poses, out = drive(strategy, me, mates, lost, 6.0)
    assert out.action == Action.SEARCH and out.role == Role.ACTIVE
    nearest = min(math.dist((p.x, p.y), last_seen) for p in poses)
    assert nearest > 1.2, "it never drives onto a ball it does not see"
    end = poses[-1]
    assert math.dist((end.x, end.y), last_seen) == pytest.approx(1.5, abs=0.25), "it waits 1.5 m short"
    turned = abs(poses[-1].theta - poses[-34].theta)
    assert turned > 0.5, "and turns on the spot to find the ball"
    assert out.velocity.vx ** 2 + out.velocity.vy ** 2 < 0.1 ** 2


def test_a_goalie_whose_ball_is_lost_guards_the_middle_of_its_goal():
    me = RobotReport(1, Pose2D(-8.6, 1.0, 0.0))
    strategy = Strategy(ControlParams(), WorldDescription(), 1)
    poses, out = drive(strategy, me, (RobotReport(2, Pose2D(0, 0, 0)),), FusedBall(-5.0, 4.0, known=False), 3.0)
    assert out.role == Role.GOALIE
    assert abs(poses[-1].y) < 0.1 and poses[-1].x == pytest.approx(-8.6, abs=0.1)


def test_a_ball_lost_in_a_match_is_searched_where_it_was_last_seen(make_match):
    """In the in-process match, the ball vanishes from every robot's vision: nobody drives off after a ghost."""
    match = make_match(TEAMS[:5], ball=(3.0, 1.0))
    match.run(1.0)
    seen = {n: match.sim.world.robot_state(n) for n in match.agents}
    match.sim.update_params(noise=NoiseParams(0, 0, 0, 0, vision_range=0.01))  # every robot is now blind
    match.run(4.0)
    for name in match.agents:
        world = match.steps[name].world
        assert not world.ball.known and world.ball.position == pytest.approx((3.0, 1.0), abs=0.05)
        s = match.sim.world.robot_state(name)
        assert math.hypot(s.x - 3.0, s.y - 1.0) > 1.2, f"{name} came onto the lost ball"
    active = [n for n, r in match.outputs.items() if r.role == Role.ACTIVE]
    assert len(active) == 1 and match.outputs[active[0]].action == Action.SEARCH
    before = seen[active[0]]
    assert math.hypot(before.x - 3.0, before.y - 1.0) > 1.5


@pytest.mark.parametrize("mode", [MatchMode.OUR_THROWIN, MatchMode.OPP_THROWIN])
def test_robots_walking_into_a_set_play_formation_do_not_push_the_ball(make_match, mode):
    # Everyone starts inside the field of a ball placed on the side line; the taker's spot is beyond it.
    robots = [("nubot1", -8.4, 0, 0), ("nubot2", 2.0, 5.0, 0), ("nubot3", 2.0, 3.5, 0), ("nubot4", 1.0, 4.5, 0),
              ("nubot5", 3.0, 4.2, 0)]
    match = make_match(robots, ball=(0.0, 5.9))
    match.command("nubot", mode)
    match.run(6.0)
    ball = match.sim.world.ball_state()
    assert math.hypot(ball.x, ball.y - 5.9) < 0.05, "the placed ball stays where the referee put it"
    if mode == MatchMode.OUR_THROWIN:
        name = next(n for n, out in match.outputs.items() if out.role == Role.PASSOFPASS)
        taker = match.sim.world.robot_state(name)
        assert math.hypot(taker.x - ball.x, taker.y - ball.y) < 0.7, "the taker reached its spot at the ball"


def test_on_the_22_by_14_field_the_robots_take_its_kickoff_spots(make_match):
    """The goalie stands on its own goal line of the field the match is played on: x = -10.6 on 22 x 14."""
    from nubot_common.world_description import load_world

    match = make_match(TEAMS, world=load_world("22x14"))
    match.command("rival", MatchMode.OUR_KICKOFF)
    match.run(5.0)
    goalie = match.sim.world.robot_state("nubot1")
    assert (goalie.x, goalie.y) == pytest.approx((-10.6, 0.0), abs=0.15)
    keeper = match.sim.world.robot_state("rival1")
    assert (keeper.x, keeper.y) == pytest.approx((10.6, 0.0), abs=0.15), "the other team's goal line, too"
    for name in ("nubot2", "nubot3", "nubot4", "nubot5"):
        s = match.sim.world.robot_state(name)
        assert s.x < 0.0 and math.hypot(s.x, s.y) > 2.0, f"{name} respects the opponent kickoff"


# --- choosing the shot, pressing, marking, keeping the rules ----------------------------------------------------
def holder_state(me_xy, heading, opponents, mates=(), t=1.0, carried_from=None):
    me = RobotReport(2, Pose2D(*me_xy, heading), holding=True, role=Role.ACTIVE, role_time=5.0)
    ball = FusedBall(me_xy[0] + 0.43 * math.cos(heading), me_xy[1] + 0.43 * math.sin(heading))
    mates = (RobotReport(1, Pose2D(-8.5, 0, 0)), *mates)
    return team_state(me, mates, ball, opponents, t=t)


def test_a_good_chance_is_taken_and_a_poor_one_is_not():
    goalie = (8.6, 0.0)
    strategy = Strategy(ControlParams(), WorldDescription(), 2)
    near = strategy.step(holder_state((4.0, -0.3), math.atan2(0.65, 4.6), [goalie]))  # facing the far corner
    assert near.action == Action.SHOOT
    far = Strategy(ControlParams(), WorldDescription(), 2).step(holder_state((-2.0, 0.0), 0.0, [goalie]))
    assert far.action == Action.DRIBBLE and far.kick is None, "from 11 m it carries the ball on"


def test_a_shot_waits_until_the_robot_faces_its_aim():
    strategy = Strategy(ControlParams(), WorldDescription(), 2)
    out = strategy.step(holder_state((4.0, -0.3), 0.8, [(8.6, 0.0)]))  # facing well off the goal
    assert out.action == Action.SHOOT and out.kick is None and abs(out.velocity.w) > 0.0


def test_a_blocked_lane_from_close_in_is_lobbed_over_the_defender():
    strategy = Strategy(ControlParams(), WorldDescription(), 2)
    heading = math.atan2(0.0 - 0.0, 9.0 - 4.43)
    out = strategy.step(holder_state((4.0, 0.0), heading, [(6.3, 0.0), (6.4, 0.7), (6.4, -0.7)]))  # a wall 2 m out
    assert out.action == Action.SHOOT and out.kick is not None and out.kick.kind == 1


def test_a_pressed_carrier_passes_to_a_free_teammate_rather_than_shoot_a_poor_chance():
    mate = RobotReport(3, Pose2D(5.0, 3.5, 0))
    state = holder_state((0.0, 0.0), math.atan2(3.5, 5.0), [(1.3, -0.5), (8.6, 0.0)], mates=(mate,))
    out = Strategy(ControlParams(), WorldDescription(), 2).step(state)
    assert out.action == Action.PASS and out.pass_cmd.catch_id == 3


@pytest.mark.parametrize("lurker_y, passes", [(0.6, True), (0.8, False)])
def test_a_pressed_carrier_passes_only_when_the_pass_beats_every_opponent_by_the_margin(lurker_y, passes):
    """Pressed in its own half, a pass an opponent may reach in time is not worth the risk: it clears instead."""
    from nubot_control.behaviours import pass_options
    from nubot_control.chances import ChanceParams

    mate = RobotReport(3, Pose2D(-1.0, 3.0, 0))
    presser, lurker = (-5.6, -0.9), (-3.0, lurker_y)  # one at its side, one near the pass's line
    state = holder_state((-5.0, 0.0), math.atan2(3.0, 4.0), [presser, lurker, (8.6, 0.0)], mates=(mate,))
    params = ControlParams()
    (option,) = pass_options(state, params, ChanceParams())
    assert 0.0 <= option.margin and (option.margin >= params.play.pass_margin) == passes, "the setting holds"
    out = Strategy(params, WorldDescription(), 2).step(state)
    assert (out.action == Action.PASS) == passes
    if not passes:
        assert out.action == Action.DRIBBLE and out.pass_cmd is None, "it turns to clear the ball instead"


def test_a_carrier_lets_the_ball_go_before_3_m():
    """With nobody to pass to and no shot, it carries the ball at most carry_limit from where it caught it."""
    strategy = Strategy(ControlParams(), WorldDescription(), 2)
    me = RobotReport(2, Pose2D(-4.0, 0.0, 0.0), holding=True, role=Role.ACTIVE, role_time=5.0)
    mates = (RobotReport(1, Pose2D(-8.5, 0, 0)),)
    dt, kicked_at = 1 / 33, None
    for k in range(250):
        ball = FusedBall(me.pose.x + 0.43 * math.cos(me.pose.theta), me.pose.y + 0.43 * math.sin(me.pose.theta))
        out = strategy.step(team_state(me, mates, ball, [(8.6, 0.0)], t=k * dt))
        if out.kick is not None:
            kicked_at = (ball.x, ball.y)
            break
        vx, vy = rotate(out.velocity.vx, out.velocity.vy, me.pose.theta)
        me = replace(me, pose=Pose2D(me.pose.x + vx * dt, me.pose.y + vy * dt, me.pose.theta + out.velocity.w * dt))
    assert kicked_at is not None
    assert math.dist(kicked_at, (-4.0 + 0.43, 0.0)) < 3.0, "released inside the 3 m circle"


def test_a_carrier_pinned_on_the_halfway_line_lets_the_ball_go_after_hold_limit():
    """Pressed where it cannot move, on the halfway line, with no pass and no shot: it lets the ball go within
    hold_limit and a turn, however its position jitters across the line (a match once stood still for 15 min)."""
    strategy = Strategy(ControlParams(), WorldDescription(), 2)
    hold_limit = ControlParams().play.hold_limit
    me = RobotReport(2, Pose2D(0.0, 1.8, math.pi / 2), holding=True, role=Role.ACTIVE, role_time=5.0)
    mates = (RobotReport(1, Pose2D(-8.5, 0, 0)),)
    opponents = [(-0.9, 1.6), (0.9, 2.2), (2.0, -1.0), (-2.0, -1.0), (8.6, 0.0)]  # pressed from both sides
    dt, kicked_after = 1 / 33, None
    for k in range(int((hold_limit + 4.0) / dt)):
        jitter = 0.1 if k % 2 else -0.1  # the pose estimate wanders across x = 0
        me = replace(me, pose=Pose2D(jitter, 1.8, me.pose.theta))
        ball = FusedBall(me.pose.x + 0.43 * math.cos(me.pose.theta), me.pose.y + 0.43 * math.sin(me.pose.theta))
        out = strategy.step(team_state(me, mates, ball, opponents, t=1.0 + k * dt))
        if out.kick is not None:
            kicked_after = k * dt
            break
        me = replace(me, pose=Pose2D(me.pose.x, me.pose.y, me.pose.theta + out.velocity.w * dt))  # pinned: turns only
    assert kicked_after is not None, "the ball must go"
    assert kicked_after < hold_limit + 3.0


def test_the_active_robot_presses_an_opponent_playing_the_ball_from_between_ball_and_goal():
    me = RobotReport(2, Pose2D(-1.0, 2.0, 0), role=Role.ACTIVE, role_time=5.0)
    carrier = (1.0, 0.0)
    state = team_state(me, (RobotReport(1, Pose2D(-8.5, 0, 0)),), FusedBall(0.6, 0.0), (carrier, (8.6, 0.0)))
    out = Strategy(ControlParams(), WorldDescription(), 2).step(state)
    assert out.action == Action.DEFEND and out.role == Role.ACTIVE
    assert out.target[0] < 0.6 and abs(out.target[1]) < 0.1, "on the line to our goal"
    assert math.dist(out.target, (0.6, 0.0)) == pytest.approx(ControlParams().play.press_distance)


def test_when_they_have_the_ball_the_assistant_marks_their_second_most_dangerous_robot():
    mates = (RobotReport(1, Pose2D(-8.5, 0, 0)), RobotReport(2, Pose2D(2.0, 0.5, 0)),
             RobotReport(4, Pose2D(-2.0, -2.0, 0)), RobotReport(5, Pose2D(-4.0, 0, 0)))
    me = RobotReport(3, Pose2D(-1.0, 3.0, 0))
    opponents = ((3.0, 0.0), (-5.0, -2.0), (-3.0, 3.5), (8.6, 0.0))  # the carrier at the ball, two lurking
    state = team_state(me, mates, FusedBall(2.6, 0.0), opponents)
    out = Strategy(ControlParams(), WorldDescription(), 3).step(state)
    assert (out.role, out.action) == (Role.ASSISTANT, Action.MARK), "without the ball it would take its spot at (5, 3)"
    assert math.dist(out.target, (-3.0, 3.5)) == pytest.approx(1.0)


@pytest.mark.parametrize("agent", [3, 4, 5])
def test_field_robots_never_aim_into_the_goal_areas_and_supporters_not_into_the_penalty_areas(agent):
    from nubot_control.areas import in_area

    mates = tuple(RobotReport(i, Pose2D(-7.5 + 0.3 * i, 0.5 * i - 1.0, 0)) for i in range(1, 6) if i != agent)
    me = RobotReport(agent, Pose2D(-6.0, 0.0, 0))
    state = team_state(me, mates, FusedBall(-8.0, 0.5), ((-7.0, 2.5), (8.6, 0.0)))
    out = Strategy(ControlParams(), WorldDescription(), agent).step(state)
    field = FieldGeometry()
    assert not in_area(*out.target, field, own=True, goal_area=True)
    if out.role not in (Role.ACTIVE, Role.GOALIE):
        assert not in_area(*out.target, field, own=True), f"{out.role.name} aims into our penalty area"


def test_pressed_in_its_own_half_with_no_pass_on_a_robot_clears_the_ball_where_no_opponent_can_reach_it():
    from nubot_control.behaviours import clearance_target
    from nubot_control.chances import ChanceParams

    opponents = [(-5.3, -1.1), (0.0, -3.5), (1.0, -0.5), (8.6, 0.0)]  # one pressing from beside, two to the right
    state = holder_state((-5.0, 0.0), 0.0, opponents)
    target = clearance_target(state, ChanceParams())
    assert target[0] > -1.0 and target[1] > 2.0, "up the field, on the wing nobody covers"
    out = Strategy(ControlParams(), WorldDescription(), 2).step(state)
    assert out.action == Action.DRIBBLE and out.kick is None, "it turns to the target first"
    assert out.velocity.w > 0.0, "to its left, towards the free wing"


def test_near_our_goal_the_passive_robot_blocks_the_lane_to_the_side_the_goalie_leaves_open():
    from nubot_control.behaviours import block_lane

    keeper = RobotReport(1, Pose2D(-8.6, 0.4, 0))
    me = RobotReport(3, Pose2D(-4.0, 0.0, 0))
    state = team_state(me, (keeper,), FusedBall(-4.5, 2.5), ((-4.2, 2.8), (8.6, 0.0)))
    out = block_lane(state, ControlParams())
    lane = (-9.0 + 4.5, -0.84 - 2.5)  # from the ball to the far post's side
    d = math.hypot(*lane)
    expected = (-4.5 + lane[0] / d * 1.6, 2.5 + lane[1] / d * 1.6)
    assert (out.target.x, out.target.y) == pytest.approx(expected, abs=1e-6)
    assert block_lane(team_state(me, (keeper,), FusedBall(3.0, 0.0)), ControlParams()) is None, "far away: none"


def test_a_receiver_goes_to_meet_a_pass_on_the_ball_s_line():
    """The ball rolls towards the receiver a little off it: the receiver steps onto the line, towards the ball, so
    the ball has less way to go for an opponent to cut it off; a ball that has rolled past is run after."""
    from nubot_common.team_play import PassCommand
    from nubot_control.behaviours import catch_pass

    me = RobotReport(3, Pose2D(0.0, 0.0, math.pi), role=Role.CATCHOFPASS)
    plan = PassCommand(2, 3, (-4.0, 0.3), (0.0, 0.0), is_passout=True, is_dynamic_pass=True)
    rolling = FusedBall(-4.0, 0.3, vx=4.0, velocity_known=True)
    out = catch_pass(team_state(me, (), rolling), plan, ControlParams())
    assert out.action == Action.CATCH and out.dribble
    assert out.target.y == pytest.approx(0.3), "on the ball's line"
    assert -1.5 < out.target.x < -0.3, "up the line, towards the ball"
    assert abs(math.cos(out.target.theta) + 1.0) < 1e-6, "facing the ball"
    past = FusedBall(1.0, 0.3, vx=2.0, velocity_known=True)
    out = catch_pass(team_state(me, (), past), plan, ControlParams())
    assert (out.target.x, out.target.y) == pytest.approx((1.0, 0.3)), "after the ball"
    passer = RobotReport(2, Pose2D(-4.4, 0.3, 0.0), holding=True)
    carried = catch_pass(team_state(me, (passer,), rolling), plan, ControlParams())
    assert (carried.target.x, carried.target.y) == pytest.approx((0.0, 0.0)), "a held ball is not kicked yet: wait"

"""Unit tests of the WorldModel agent: ball fusion, teammate validity, own shared state, bad input."""

import math

import pytest

from nubot_common.percepts import BallPercept, RobotView
from nubot_common.team_play import StrategyReport
from nubot_common.world_state import BallSource
from world_model import WorldModelError


def test_own_ball_is_preferred_and_teammates_agreeing_raise_the_confidence(make_model, see, mate_view):
    model = make_model(agent_id=1)
    see(model, 10.0, ball=(1.0, 2.0))
    alone = model.snapshot(10.01).ball
    model.on_teammate(10.0, mate_view(10.0, 2, 1.3, 2.0, ball=(1.1, 2.05)))  # nearer to the ball
    ball = model.snapshot(10.01).ball
    assert ball.known and ball.source is BallSource.OWN and ball.source_id == 1
    assert (ball.x, ball.y) == (1.0, 2.0)
    assert ball.seen_by == (1, 2)
    assert ball.confidence > alone.confidence > 0.5
    assert ball.radius == pytest.approx((3.0**2 + 2.0**2) ** 0.5)


def test_stale_own_ball_falls_back_to_the_teammate_nearest_to_its_ball(make_model, see, mate_view):
    model = make_model(agent_id=1)
    see(model, 10.0, ball=(1.0, 2.0))
    see(model, 10.35, ball=None)  # not seen for 0.35 s > ball_timeout
    model.on_teammate(10.35, mate_view(10.34, 2, -3.0, 0.0, ball=(1.2, 2.0)))  # 4.7 m from its ball
    model.on_teammate(10.35, mate_view(10.33, 3, 0.5, 2.5, ball=(1.1, 2.1)))  # 0.7 m from its ball
    ball = model.snapshot(10.36).ball
    assert ball.source is BallSource.TEAMMATE and ball.source_id == 3
    assert (ball.x, ball.y) == (1.1, 2.1)
    assert ball.seen_by == (2, 3), "1 no longer sees it"


def test_stale_teammate_is_invalid_and_its_ball_ignored(make_model, see, mate_view):
    model = make_model(agent_id=1)
    see(model, 10.0, ball=None)
    model.on_teammate(10.0, mate_view(10.0, 3, 0.9, 2.0, ball=(1.0, 2.0)))
    model.on_teammate(10.0, mate_view(10.0, 2, -6.0, 0.0, ball=(1.1, 2.0)))
    model.on_teammate(10.3, mate_view(10.3, 2, -6.0, 0.0, ball=(1.1, 2.0)))  # 2 keeps talking, 3 falls silent
    see(model, 10.35, ball=None)
    state = model.snapshot(10.35)
    assert [r.valid for r in state.robots] == [True, True, False, False, False]
    assert state.robots[2].age == pytest.approx(0.35) and state.robots[2].report is not None, "kept, but invalid"
    assert state.robots[3].report is None and state.robots[3].age == float("inf"), "never heard of"
    assert state.ball.source_id == 2, "3 was nearer its ball, but is silent for more than 0.3 s"
    assert state.team_balls[2] is None


def test_teammate_reporting_itself_invalid_is_invalid(make_model, see, mate_view):
    model = make_model(agent_id=1)
    see(model, 10.0, ball=None)
    model.on_teammate(10.0, mate_view(10.0, 4, 0.9, 2.0, ball=(1.0, 2.0), valid=False))
    state = model.snapshot(10.01)
    assert not state.robots[3].valid and not state.ball.known


def test_own_message_relayed_back_is_ignored(make_model, see, mate_view):
    model = make_model(agent_id=2)
    see(model, 10.0, pose=(3.0, 1.0, 0.5), ball=None)
    assert model.on_teammate(10.0, mate_view(10.0, 2, -9.0, -9.0, ball=(0.0, 0.0))) is False
    state = model.snapshot(10.01)
    assert state.me.pose.x == 3.0 and not state.ball.known


def test_no_ball_anywhere_is_unknown_but_remembers_where_it_was(make_model, see):
    model = make_model()
    see(model, 10.0, ball=(4.0, -1.0))
    assert model.snapshot(10.0).ball.known
    see(model, 10.5, ball=None)
    ball = model.snapshot(10.5).ball
    assert not ball.known and ball.source is BallSource.UNKNOWN and ball.confidence == 0.0
    assert (ball.x, ball.y) == (4.0, -1.0) and ball.seen_by == ()


def test_own_ball_velocity_is_fitted_not_taken_from_the_frame(make_model, robot):
    model = make_model()
    for k in range(10):
        t = 10.0 + k / 30.0
        # Positions roll at 1 m/s along +x; the per-frame velocity claims 5 m/s sideways.
        model.on_vision(RobotView(t, robot(1, 0.0, 0.0), BallPercept(t, 1.0 * k / 30.0, 0.0, 0.0, 5.0, True)))
    ball = model.snapshot(10.3).ball
    assert ball.velocity_known and (ball.vx, ball.vy) == pytest.approx((1.0, 0.0), abs=1e-6)


def test_teammate_ball_velocity_is_fitted_over_its_reports_despite_relay_repeats(make_model, see, mate_view):
    model = make_model(agent_id=1)
    see(model, 10.0, ball=None)
    for k in range(9):
        t = 10.0 + k / 30.0
        view = mate_view(t, 2, 0.0, 0.0, ball=(1.0, 2.0 - 0.5 * k / 30.0))
        model.on_teammate(t, view)
        model.on_teammate(t + 0.01, view)  # the same message again
    see(model, 10.27, ball=None)
    ball = model.snapshot(10.28).ball
    assert ball.source is BallSource.TEAMMATE
    assert (ball.vx, ball.vy) == pytest.approx((0.0, -0.5), abs=1e-6)


def test_own_robot_is_invalid_when_its_vision_is_stale_or_it_says_so(make_model, see):
    model = make_model()
    assert not model.snapshot(1.0).me.valid and model.own_view(1.0) is None, "nothing seen yet"
    see(model, 10.0)
    assert model.snapshot(10.29).me.valid
    assert not model.snapshot(10.31).me.valid
    see(model, 11.0, valid=False)
    assert not model.snapshot(11.0).me.valid


def test_own_view_carries_role_fields_fresh_ball_with_fitted_velocity_and_obstacles(make_model, see):
    model = make_model(agent_id=3)
    model.on_strategy(9.0, StrategyReport(9.0, 3, role=1, role_time=4.5, target_nums=(3, 2, 1, 4),
                                          static_pass=3, static_catch=2, target=(-2.5, 1.5)))
    for k in range(5):
        see(model, 10.0 + k / 30.0, pose=(1.0, 1.0, 0.0), ball=(2.0 + 0.1 * k, 1.0), obstacles=((4.0, 0.0),))
    now = 10.0 + 4 / 30.0
    view = model.own_view(now)
    assert view.robot.agent_id == 3 and view.robot.valid
    assert (view.robot.role, view.robot.role_time, view.robot.target_nums) == (1, 4.5, (3, 2, 1, 4))
    assert (view.robot.static_pass, view.robot.static_catch) == (3, 2)
    assert view.robot.target == (-2.5, 1.5), "RobotInfo.target comes from the robot's own strategy"
    assert view.ball.velocity_known and (view.ball.vx, view.ball.vy) == pytest.approx((3.0, 0.0), abs=1e-6)
    assert view.obstacles == ((4.0, 0.0),)
    assert model.snapshot(now).me.role == 1
    later = model.own_view(now + 0.31)
    assert later.ball is None and later.obstacles == () and not later.robot.valid


def test_bad_agent_ids_are_refused_by_name(make_model, mate_view):
    with pytest.raises(WorldModelError, match=r"agent_id must lie in 1..5, got 6"):
        make_model(agent_id=6)
    model = make_model(agent_id=1)
    with pytest.raises(WorldModelError, match=r"teammate message: AgentID 7 outside 1..5"):
        model.on_teammate(1.0, mate_view(1.0, 7, 0.0, 0.0))
    with pytest.raises(WorldModelError, match=r"own strategy carries AgentID 2, this robot is 1"):
        model.on_strategy(1.0, StrategyReport(1.0, 2))


def test_a_clock_going_back_forgets_everything_but_the_game(make_model, see, mate_view):
    model = make_model()
    model.on_coach(50.0, 15)
    see(model, 50.0)
    model.on_teammate(50.0, mate_view(50.0, 2, 0.0, 0.0, ball=(1.0, 1.0)))
    see(model, 0.1, ball=None)  # the simulator restarted
    state = model.snapshot(0.1)
    assert not state.ball.known and not state.robots[1].valid and state.robots[1].report is None
    assert state.game.mode == 15


def test_a_teammate_whose_strategy_falls_silent_no_longer_plays(make_model, see, mate_view):
    """Its world model still talks, but its control stopped: the others take over its role."""
    model = make_model(agent_id=1)
    valid_at = {}
    for k in range(60):
        t = 10.0 + k / 30.0
        see(model, t, ball=None)
        for mate in (2, 3):
            model.on_teammate(t, mate_view(t, mate, 0.0, float(mate)))
        model.on_teammate_strategy(t, StrategyReport(min(t, 10.5), 2))  # 2's control stops at 10.5 s
        model.on_teammate_strategy(t, StrategyReport(t, 3))
        valid_at[round(t, 2)] = [r.valid for r in model.snapshot(t).robots[1:3]]
    assert valid_at[11.4] == [True, True], "0.9 s of silence: within strategy_timeout"
    assert valid_at[11.97] == [False, True], "1.47 s of silence: 2 no longer plays, though its state is fresh"
    before = make_model(agent_id=1)
    see(before, 10.0, ball=None)
    before.on_teammate(10.0, mate_view(10.0, 2, 0.0, 2.0))
    assert before.snapshot(10.0).robots[1].valid, "no strategy heard at all (e.g. other nodes): everyone plays"


def test_balls_and_robots_off_the_field_are_not_believed(make_model, see, mate_view):
    model = make_model(agent_id=1)  # the 18 x 12 field: lines at |x| 9, |y| 6, a 1 m border
    see(model, 10.0, ball=(10.5, 0.0))
    assert not model.snapshot(10.0).ball.known, "a ball 1.5 m behind the goal line is a false detection"
    see(model, 10.1, ball=(9.8, 6.8))
    assert model.snapshot(10.1).ball.known, "on the border: it can be there"
    model.on_teammate(10.1, mate_view(10.1, 2, 0.0, 7.5))
    assert not model.snapshot(10.1).robots[1].valid, "a teammate reporting itself 1.5 m off the field is lost"


def test_percepts_that_are_not_finite_are_nothing_seen_and_the_world_stays_finite(make_model, see, mate_view):
    """A NaN or infinite ball, obstacle or teammate position (a broken camera, a hostile packet) is not taken for one:
    the snapshot the strategy reads holds numbers only, and a teammate that is nowhere is not valid."""
    model = make_model(agent_id=1)
    nan, inf = math.nan, math.inf
    see(model, 10.0, ball=(nan, 2.0), obstacles=((1.0, 1.0), (nan, 0.0), (inf, 3.0)))
    model.on_teammate(10.0, mate_view(10.0, 2, nan, 1.0, ball=(inf, 0.0), obstacles=((nan, nan), (4.0, -1.0))))
    state = model.snapshot(10.02)
    assert not state.ball.known, "no ball is where nothing finite was seen"
    assert not state.robots[1].valid, "a teammate reported nowhere is not valid"
    assert [(o.x, o.y) for o in state.obstacles] == [pytest.approx((1.0, 1.0))]
    numbers = [state.ball.x, state.ball.y, state.ball.angle, state.ball.radius]
    numbers += [v for o in state.obstacles for v in (o.x, o.y, o.angle, o.radius, o.vx, o.vy)]
    assert all(math.isfinite(v) for v in numbers)
    view = model.own_view(10.02)
    assert view is not None and view.ball is None and len(view.obstacles) == 1

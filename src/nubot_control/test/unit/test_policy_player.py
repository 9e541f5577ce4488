"""A robot playing a trained policy file: what it sees, when the policy drives it, and the team YAML that names it."""

import math
import xml.etree.ElementTree as ET
from dataclasses import replace

import numpy as np
import pytest

from nubot_common import NubotCommonError
from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D
from nubot_common.match_mode import MatchMode
from nubot_common.params import from_mapping
from nubot_common.percepts import RobotReport
from nubot_common.policy import PolicyError, PolicyNet
from nubot_common.world_description import WorldDescription
from nubot_common.world_state import FusedBall
from nubot_control.agent import Controller
from nubot_control.params import ControlParams
from nubot_control.policy_player import OBSERVABLE, PolicyPlayer, observation
from nubot_control.strategy import Strategy
from nubot_control.team_config import TeamConfig, team_launch_xml
from nubot_control.team_state import TeamState

FIELD = FieldGeometry()
ACT_LOW, ACT_HIGH = [-5.0, -5.0, -12.0, 0.0, 0.0], [5.0, 5.0, 12.0, 1.0, 1.0]
TURN_AND_KICK = [0.5, 0.0, 4.0, 1.0, 0.75]  # creep forward turning at 4 rad/s, handler on, kick at 9 m/s


def policy(action=TURN_AND_KICK, names=OBSERVABLE, **meta):
    n = len(names)
    return PolicyNet.constant(action, names, [-20.0] * n, [20.0] * n, ACT_LOW, ACT_HIGH,
                              **{"kick_max_speed": 12.0, **meta})


def state(t=10.0, mode=MatchMode.STARTROBOT, previous=MatchMode.STOPROBOT, holding=False, ball_velocity=True):
    me = RobotReport(2, Pose2D(1.0, -2.0, math.pi / 2), vx=0.3, vy=-0.1, w=0.2, holding=holding)
    ball = FusedBall(3.0, 1.0, vx=-1.0, vy=0.5, velocity_known=ball_velocity)
    return TeamState(t, me, (), ball, ((8.6, 0.4), (2.0, 2.0)), FIELD, mode, previous, t - 0.1)


def test_the_observation_is_the_world_model_s_in_the_environment_s_names():
    obs = dict(zip(OBSERVABLE, observation(OBSERVABLE, state(), 0.25)))
    assert obs["x"] == 1.0 and obs["y"] == -2.0
    assert (obs["cos_theta"], obs["sin_theta"]) == pytest.approx((0.0, 1.0))
    assert (obs["vx"], obs["vy"], obs["w"]) == (0.3, -0.1, 0.2)
    assert (obs["ball_dx"], obs["ball_dy"], obs["ball_vx"], obs["ball_vy"]) == (2.0, 3.0, -1.0, 0.5)
    assert (obs["goalie_x"], obs["goalie_y"]) == (8.6, 0.4), "the opponent nearest the attacked goal"
    assert obs["holding"] == 0.0 and obs["time_left"] == 0.25
    still = dict(zip(OBSERVABLE, observation(OBSERVABLE, state(ball_velocity=False), 1.0)))
    assert (still["ball_vx"], still["ball_vy"]) == (0.0, 0.0), "no velocity before the world model knows it"
    alone = dict(zip(OBSERVABLE, observation(OBSERVABLE, replace(state(), opponents=()), 1.0)))
    assert (alone["goalie_x"], alone["goalie_y"]) == (FIELD.half_length, 0.0)


def test_in_open_play_the_policy_drives_and_the_strategy_keeps_the_role():
    player = PolicyPlayer(Strategy(ControlParams(), WorldDescription(), 2), policy())
    out = player.step(state())
    assert (out.velocity.vx, out.velocity.vy, out.velocity.w) == pytest.approx((0.5, 0.0, 4.0))
    assert out.dribble and out.kick is None, "no kick without the ball"
    assert player.role == out.role == player.inner.role and player.playing
    held = player.step(state(t=10.03, holding=True))
    assert held.kick is not None and held.kick.strength == 9


def test_outside_open_play_the_strategy_decides_alone():
    """A free kick of the opponents being set up, and after START until their kick is taken: the strategy's."""
    for mode, previous in ((MatchMode.OPP_FREEKICK, MatchMode.STOPROBOT),
                           (MatchMode.STARTROBOT, MatchMode.OPP_FREEKICK), (MatchMode.STOPROBOT, MatchMode.STARTROBOT)):
        player = PolicyPlayer(Strategy(ControlParams(), WorldDescription(), 2), policy())
        alone = Strategy(ControlParams(), WorldDescription(), 2)
        s = state(mode=mode, previous=previous)
        assert player.step(s) == alone.step(s) and not player.playing


def test_the_episode_clock_runs_over_open_play_and_starts_again():
    player = PolicyPlayer(Strategy(ControlParams(), WorldDescription(), 2), policy(episode_steps=4))
    seen = []
    player.net.act = lambda obs: (seen.append(obs[OBSERVABLE.index("time_left")]),  # type: ignore[method-assign]
                                  np.array(TURN_AND_KICK))[1]
    for k in range(6):
        player.step(state(t=10.0 + 0.03 * k))
    assert seen == [1.0, 0.75, 0.5, 0.25, 1.0, 0.75]


def test_a_policy_reading_what_a_match_robot_cannot_know_is_refused():
    with pytest.raises(PolicyError, match="reads mate2_x"):
        PolicyPlayer(Strategy(ControlParams(), WorldDescription(), 2), policy(names=("x", "mate2_x")))


def test_the_controller_plays_the_policy_file_of_its_parameters(tmp_path):
    path = policy().save(tmp_path / "policy.npz")
    controller = Controller(ControlParams(policy=str(path)), WorldDescription(), 2)
    assert isinstance(controller.strategy, PolicyPlayer)
    with pytest.raises(PolicyError, match="no policy file"):
        Controller(ControlParams(policy=str(tmp_path / "gone.npz")), WorldDescription(), 2)


TEAM = {"name": "x", "prefix": "x", "attack": 1, "goalie": 1, "robots": [{"x": -8, "y": 0}, {"x": -1, "y": 0},
                                                                         {"x": -3, "y": 2}]}


def test_a_team_names_its_policy_and_the_robots_playing_it(tmp_path):
    policy().save(tmp_path / "striker.npz")
    team = from_mapping(TeamConfig, {**TEAM, "policy": "striker.npz", "policy_robots": [2, 3]}).resolved(tmp_path)
    assert team.policy == str(tmp_path / "striker.npz")
    assert [team.policy_of(k) for k in (1, 2, 3)] == ["", team.policy, team.policy]
    root = ET.fromstring(team_launch_xml(team))
    given = [inc.find("arg[@name='policy']").get("value") for inc in root.findall("include")]
    assert given == ["", team.policy, team.policy]
    for bad, words in (({"policy": "striker.npz"}, "needs the robots"), ({"policy_robots": [2]}, "needs the robots"),
                       ({"policy": "striker.npz", "policy_robots": [4]}, "4 is not one of the robots")):
        with pytest.raises(NubotCommonError, match=words):
            from_mapping(TeamConfig, {**TEAM, **bad})
    with pytest.raises(PolicyError, match="no policy file"):
        from_mapping(TeamConfig, {**TEAM, "policy": "gone.npz", "policy_robots": [2]}).resolved(tmp_path)

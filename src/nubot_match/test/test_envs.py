"""The Gymnasium and PettingZoo environments: the libraries' checkers, determinism, team frames, rewards, errors."""

import math

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from pettingzoo.test import parallel_api_test, parallel_seed_test

from nubot_match import NubotMatchError
from nubot_match.envs import SCORE_AGAINST_GOALIE, ScoreAgainstGoalieEnv, parallel_env
from nubot_match.envs.example import ScriptedAttacker, main, random_policy, run_episodes

pytestmark = pytest.mark.filterwarnings("ignore:.*symmetric and normalized space:UserWarning")
FEW = ("nubot2", "rival3")  # two agents of the 5 vs 5; the other eight play the built-in strategy


def rollout(env, seed, steps):
    """Observations and rewards of ``steps`` steps with actions sampled from a generator seeded like the env."""
    obs, _ = env.reset(seed=seed)
    env.action_space.seed(seed)
    seen, rewards = [obs], []
    for _ in range(steps):
        obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
        seen.append(obs)
        rewards.append(reward)
        if terminated or truncated:
            break
    return np.array(seen), rewards


# --- the libraries' checkers ---------------------------------------------------------------------------
def test_score_env_passes_the_gymnasium_checker():
    env = gymnasium.make(SCORE_AGAINST_GOALIE, max_steps=20)
    check_env(env.unwrapped)
    assert env.unwrapped.spec.id == SCORE_AGAINST_GOALIE


def test_match_env_passes_the_parallel_api_test_with_all_ten_and_with_two_agents():
    parallel_api_test(parallel_env(max_cycles=8), num_cycles=8)
    parallel_api_test(parallel_env(agents=FEW), num_cycles=15)


def test_match_env_passes_the_parallel_seed_test():
    parallel_seed_test(lambda: parallel_env(agents=FEW, max_cycles=20))


# --- determinism ------------------------------------------------------------------------------------------
def test_a_seed_repeats_a_score_env_rollout_and_another_seed_does_not():
    one, rewards_one = rollout(ScoreAgainstGoalieEnv(max_steps=60), 5, 60)
    two, rewards_two = rollout(ScoreAgainstGoalieEnv(max_steps=60), 5, 60)
    assert len(one) == 61 and np.array_equal(one, two) and rewards_one == rewards_two
    other, _ = rollout(ScoreAgainstGoalieEnv(max_steps=60), 6, 0)
    assert not np.array_equal(one[0], other[0])


def test_reset_without_a_seed_continues_the_generator():
    env = ScoreAgainstGoalieEnv()
    first, _ = env.reset(seed=1)
    again, _ = env.reset(seed=1)
    following, _ = env.reset()
    assert np.array_equal(first, again) and not np.array_equal(first, following)


def test_a_seed_repeats_a_match_env_rollout_over_many_steps():
    def run():
        env = parallel_env(agents=FEW, max_cycles=40)
        obs, _ = env.reset(seed=9)
        for k, agent in enumerate(env.agents):
            env.action_space(agent).seed(k)
        seen = [obs]
        while env.agents:
            obs, *_ = env.step({a: env.action_space(a).sample() for a in env.agents})
            seen.append(obs)
        return np.array([[o[a] for a in FEW] for o in seen])

    one, two = run(), run()
    assert one.shape[0] == 41 and np.array_equal(one, two)


# --- behaviour ----------------------------------------------------------------------------------------------
def test_the_scripted_attacker_scores_and_holds_the_ball_more_often_than_a_random_policy():
    env = ScoreAgainstGoalieEnv(max_steps=300)
    seeds = range(6)  # kicks scatter and the goalie saves some: about half the scripted shots score
    scripted = run_episodes(env, ScriptedAttacker(env.field.half_length), seeds)
    randomly = run_episodes(env, random_policy(env.action_space, 0), seeds)
    assert scripted.goals >= 2 and scripted.goals > randomly.goals
    assert scripted.touched > randomly.touched
    assert np.mean(scripted.returns) > np.mean(randomly.returns) + 0.5


def test_a_robot_attacking_minus_x_sees_the_goal_it_attacks_at_plus_x():
    env = ScoreAgainstGoalieEnv(attack=-1, max_steps=300)
    obs, _ = env.reset(seed=0, options={"robot": (5.0, 1.0, 0.0), "ball": (6.0, 1.0)})
    me = env.match.sim.world.robot_state(env.learner)
    goalie = env.match.sim.world.robot_state(env.goalie)
    assert (me.x, me.y) == pytest.approx((-5.0, -1.0)) and abs(abs(me.theta) - math.pi) < 1e-9
    assert goalie.x < -8.0  # the goal it attacks is the world's goal at -x ...
    assert obs[:4] == pytest.approx([5.0, 1.0, 1.0, 0.0], abs=1e-6)  # ... in its own frame at +x
    assert obs[7:9] == pytest.approx([1.0, 0.0], abs=1e-6) and obs[12] > 8.0
    out = run_episodes(env, ScriptedAttacker(env.field.half_length), [0, 1, 2, 3])  # aiming at +x scores at -x
    assert out.goals >= 1, "a goal counts only in the goal attacked (the goalie may save some shots)"


def test_each_team_of_the_match_env_sees_itself_from_its_own_goal():
    env = parallel_env(agents=("nubot2", "rival2"))
    obs, _ = env.reset(seed=0)
    assert env.match.sim.world.robot_state("rival2").x == pytest.approx(1.0)  # rival attacks -x: starts at +x
    names = env.observation_layout("rival2")
    for agent in ("nubot2", "rival2"):  # both start at (-1, 0) facing +x in their own frame
        assert obs[agent][:4] == pytest.approx([-1.0, 0.0, 1.0, 0.0], abs=1e-6)
        assert obs[agent][names.index("opp1_x")] == pytest.approx(8.4)  # the other goalie guards +x
    assert env.observation_space("rival2").contains(obs["rival2"])


# --- rewards ---------------------------------------------------------------------------------------------------
def test_a_custom_reward_function_is_called_with_both_observations_and_the_info():
    calls = []

    def reward(prev_obs, obs, info):
        calls.append((prev_obs, obs, info))
        return 42.0

    env = ScoreAgainstGoalieEnv(reward_fn=reward)
    first, _ = env.reset(seed=0)
    obs, r, *_ = env.step(np.zeros(5, dtype=np.float32))
    assert r == 42.0 and calls[0][0] is first and calls[0][1] is obs and "ball_progress" in calls[0][2]
    menv = parallel_env(agents=FEW, max_cycles=3, reward_fn=lambda p, o, i: 1.0 if i["agent"] == "rival3" else 2.0)
    menv.reset(seed=0)
    _, rewards, *_ = menv.step({a: np.zeros(5, dtype=np.float32) for a in FEW})
    assert rewards == {"nubot2": 2.0, "rival3": 1.0}


def test_the_default_rewards_count_goals():
    env = ScoreAgainstGoalieEnv()
    out = run_episodes(env, ScriptedAttacker(env.field.half_length), [3])
    assert out.goals == 1 and out.returns[0] > 1.0  # +1 for the goal, the ball's progress minus the step costs


# --- bad input ---------------------------------------------------------------------------------------------------
def test_bad_input_is_refused_with_a_clear_error():
    with pytest.raises(NubotMatchError, match=r"unknown: \['nubot9'\]"):
        parallel_env(agents=("nubot2", "nubot9"))
    with pytest.raises(NubotMatchError, match="render_mode must be None"):
        ScoreAgainstGoalieEnv(render_mode="human")
    env = ScoreAgainstGoalieEnv()
    with pytest.raises(NubotMatchError, match="call reset"):
        env.step(np.zeros(5))
    env.reset(seed=0)
    with pytest.raises(NubotMatchError, match=r"must have shape \(5,\) \[vx, vy, w, dribble, kick\], got shape \(3,\)"):
        env.step(np.zeros(3))
    with pytest.raises(NubotMatchError, match=r"nubot1's action vx=9 is outside \[-5, 5\]"):
        env.step(np.array([9.0, 0.0, 0.0, 0.0, 0.0]))
    with pytest.raises(NubotMatchError, match="kick=nan"):
        env.step(np.array([0.0, 0.0, 0.0, 0.0, np.nan]))
    with pytest.raises(NubotMatchError, match="unknown reset options"):
        env.reset(options={"goalie": (0.0, 0.0)})
    menv = parallel_env(agents=FEW)
    with pytest.raises(NubotMatchError, match="unknown agent 'rival9'"):
        menv.observation_space("rival9")
    menv.reset(seed=0)
    zero = np.zeros(5, dtype=np.float32)
    with pytest.raises(NubotMatchError, match=r"unknown: \['rival1'\]; missing: \['rival3'\]"):
        menv.step({"nubot2": zero, "rival1": zero})


def test_the_example_prints_both_policies_returns(capsys):
    assert main(["--episodes", "1", "--max-steps", "20"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == ["random", "scripted"] and all("returns [" in x for x in lines)


def test_the_match_env_ends_at_full_time_and_rewards_the_goal_difference():
    from nubot_match.envs.score_env import CONFIG
    from sim_visual.world import BallState

    env = parallel_env(home=CONFIG / "score_attacker.yaml", away=CONFIG / "score_goalie.yaml", half_seconds=2.0,
                       halves=1)
    env.reset(seed=0)
    still = np.zeros(5, dtype=np.float32)
    totals = dict.fromkeys(env.possible_agents, 0.0)
    placed = False
    while env.agents:
        obs, rewards, terminations, truncations, infos = env.step(dict.fromkeys(env.agents, still))
        totals = {a: totals[a] + rewards[a] for a in totals}
        if not placed and obs["nubot1"][env.observation_layout("nubot1").index("running")] == 1.0:
            # rolling into the goal at -x (rival attacks it; nubot kicked off, so a goal straight from its kick-off
            # would not count), past the goalie
            ball = env.match.config.world.ball
            env.match.sim.set_model_state(env.match.config.world.ball_name,
                                          BallState(-8.7, 0.9, ball.radius, -3.0, 0.0, 0.0))
            placed = True
    assert placed and all(terminations.values()) and not any(truncations.values())
    assert totals == {"nubot1": -1.0, "rival1": 1.0}
    assert infos["nubot1"]["score"] == (0, 1) and infos["rival1"]["score"] == (1, 0)

"""Training a robot (make train): a short run with Stable-Baselines3 writes checkpoints and a policy file that plays a
lockstep episode, the same seed learns the same, a run resumes, bad options are refused; the policy file plays in a
team's lockstep match and against the scripted striker (make evaluate POLICY=...). Learning itself is measured by
make bench (scripts/bench_train.py), not here."""

import csv
import json
from dataclasses import replace

import numpy as np
import pytest

from nubot_common.policy import PolicyError, PolicyNet
from nubot_control.policy_player import playable
from nubot_match import NubotMatchError
from nubot_match.config import TEAMS, match_config
from nubot_match.engine import LockstepMatch
from nubot_match.envs import SCORE_AGAINST_GOALIE
from nubot_match.learn import compare, trainer
from nubot_match.learn.episodes import SCRIPTED, play, play_team, player
from nubot_match.learn.tasks import TASKS, single_task, task
from nubot_match.learn.trainer import TrainOptions, train

pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning")


@pytest.fixture(scope="module")
def short_run(tmp_path_factory):
    """1,024 steps on two worker processes, a checkpoint every 512 steps scored on one seeded episode."""
    out = tmp_path_factory.mktemp("train") / "run"
    train(TrainOptions(steps=1024, workers=2, seed=3, out=str(out), checkpoint_every=512, eval_episodes=1))
    return out


def test_a_short_run_writes_checkpoints_a_curve_and_a_policy_file_that_plays_a_lockstep_episode(short_run):
    manifest = json.loads((short_run / "run.json").read_text())
    assert manifest["env_id"] == SCORE_AGAINST_GOALIE and manifest["options"]["seed"] == 3
    assert {"torch", "stable-baselines3", "gymnasium", "numpy"} <= set(manifest["versions"])
    assert manifest["steps"] == 1024 and manifest["this_session"]["steps_per_second"] > 0
    assert sorted(p.name for p in (short_run / "checkpoints").iterdir()) == ["ppo_1024.zip", "ppo_512.zip"]
    with open(short_run / "curve.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert [int(float(r["steps"])) for r in rows] == [512, 1024] and all(r["episodes"] == "1.0" for r in rows)
    assert (short_run / "learning_curve.png").stat().st_size > 0
    assert any((short_run / "tensorboard").rglob("events.out.tfevents.*"))

    net = PolicyNet.load(short_run / "policy.npz")
    assert net.meta["env_id"] == SCORE_AGAINST_GOALIE and net.meta["trained_steps"] == 1024
    [episode] = play(task("score"), player(str(short_run / "policy.npz"), task("score")), [0])
    assert 1 <= episode.steps <= task("score").episode_steps and episode.end in ("goal", "out", "dropped ball", "time")


def test_the_policy_file_acts_as_the_trained_network(short_run):
    """numpy's forward pass of the file gives the learner's own deterministic action (through the rescaled spaces)."""
    from stable_baselines3 import PPO

    model = PPO.load(short_run / "checkpoints" / "ppo_1024.zip", device="cpu")
    net = PolicyNet.load(short_run / "policy.npz")
    act = player(str(short_run / "policy.npz"), task("score"))
    env = task("score").make()
    for seed in range(5):
        obs, _ = env.reset(seed=seed)
        action, _ = model.predict(obs, deterministic=True)
        raw = env.unwrapped._obs  # the environment's own observation, before the policy's view and the rescaling
        expected = net.act_low + (np.clip(action, -1, 1) + 1.0) / 2.0 * (net.act_high - net.act_low)
        assert act(raw) == pytest.approx(expected, abs=1e-4)
    env.close()


def test_the_same_seed_learns_the_same_and_a_run_resumes(tmp_path):
    runs = []
    for name in ("a", "b"):
        train(TrainOptions(steps=256, workers=1, seed=5, out=str(tmp_path / name), checkpoint_every=256,
                           eval_episodes=0))
        runs.append(PolicyNet.load(tmp_path / name / "policy.npz"))
    for wa, wb in zip(runs[0].weights, runs[1].weights):
        assert np.array_equal(wa, wb)
    train(TrainOptions(steps=1024, workers=1, seed=5, out=str(tmp_path / "a"), checkpoint_every=512,
                       eval_episodes=0, resume=True))
    manifest = json.loads((tmp_path / "a" / "run.json").read_text())
    assert manifest["steps"] == 1024 and manifest["this_session"]["steps"] == 512
    assert PolicyNet.load(tmp_path / "a" / "policy.npz").meta["trained_steps"] == 1024
    with pytest.raises(NubotMatchError, match="other seed"):
        train(TrainOptions(steps=2048, workers=1, seed=6, out=str(tmp_path / "a"), resume=True))


@pytest.mark.parametrize("argv, words", [
    (["--task", "juggle"], "unknown task 'juggle'; known: duo, score"),
    (["--steps", "-5"], "--steps must be at least 1, got -5"),
    (["--algorithm", "dqn"], "unknown algorithm 'dqn'; known: ppo"),
    (["--workers", "0"], "--workers must be at least 1"),
    (["--resume"], "--resume needs the --out"),
])
def test_bad_training_options_get_a_clear_error(argv, words, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert trainer.main(argv) == 2
    assert words in capsys.readouterr().err and not (tmp_path / "runs").exists()


def spinner(tmp_path):
    """A policy file that turns at 4 rad/s on the spot, whatever it sees, in the score task's layout."""
    env = task("score").raw()
    obs, act = env.observation_space, env.action_space
    env.close()
    names = env.unwrapped.layout.names
    return PolicyNet.constant([0.0, 0.0, 4.0, 0.0, 0.0], names, obs.low, obs.high, act.low, act.high,
                              env_id=SCORE_AGAINST_GOALIE, kick_max_speed=12.0).save(tmp_path / "spin.npz")


def test_a_team_yaml_policy_drives_its_robot_in_a_lockstep_match(tmp_path):
    path = spinner(tmp_path)
    team = (TEAMS / "nubot.yaml").read_text() + f"policy: {path.name}\npolicy_robots: [3]\n"
    (tmp_path / "learners.yaml").write_text(team)
    match = LockstepMatch(match_config(tmp_path / "learners.yaml", TEAMS / "rival.yaml", half_seconds=12, halves=1))
    match.reset(0)
    turned, last = 0.0, match.sim.world.robot_state("nubot3").theta
    while not match.done:
        match.run(until=match.sim.time + 0.1)
        theta = match.sim.world.robot_state("nubot3").theta
        turned += abs(np.angle(np.exp(1j * (theta - last))))
        last = theta
    assert type(match.agents["nubot3"].controller.strategy).__name__ == "PolicyPlayer"
    assert turned > 4 * 2 * np.pi, f"nubot3 turned {turned:.1f} rad in 12 s: the policy did not drive it"


def test_make_evaluate_compares_a_policy_file_with_the_scripted_striker(tmp_path, capsys):
    path = spinner(tmp_path)
    assert compare.main(["--policy", str(path), "--episodes", "2", "--jobs", "1", "--out", str(tmp_path / "ev")]) == 0
    results = json.loads((tmp_path / "ev" / "results.json").read_text())
    spin, scripted = (results["episodes"][k] for k in ("policy spin.npz", "scripted striker"))
    assert [e["seed"] for e in spin] == [e["seed"] for e in scripted] == [0, 1]
    assert not any(e["scored"] for e in spin), "a robot turning on the spot scores no goal"
    assert "| difference (paired by seed) |" in (tmp_path / "ev" / "table.md").read_text()
    assert (tmp_path / "ev" / "success.png").stat().st_size > 0
    capsys.readouterr()
    assert compare.main(["--policy", str(tmp_path / "gone.npz")]) == 2
    assert "no policy file" in capsys.readouterr().err
    assert compare.main(["--policy", str(path), "--task", "juggle"]) == 2
    assert "unknown task 'juggle'" in capsys.readouterr().err


def test_a_policy_trained_elsewhere_is_refused(tmp_path):
    other = PolicyNet.load(spinner(tmp_path))
    other.meta["env_id"] = "NuBot/Juggle-v0"
    other.save(tmp_path / "other.npz")
    with pytest.raises(NubotMatchError, match="trained on 'NuBot/Juggle-v0'"):
        player(str(tmp_path / "other.npz"), task("score"))
    assert callable(player(SCRIPTED, task("score")))


def test_the_team_task_trains_one_policy_for_both_attackers_through_supersuit(tmp_path):
    """make train TASK=duo: nubot2 and nubot3 of a 3 vs 3 share one policy (PettingZoo, SuperSuit, PPO)."""
    train(TrainOptions(task="duo", steps=512, workers=1, seed=1, out=str(tmp_path / "duo"), checkpoint_every=512,
                       eval_episodes=0))
    net = PolicyNet.load(tmp_path / "duo" / "policy.npz")
    assert net.meta["env_id"] == "nubot_match_v0" and net.meta["task"] == "duo"
    assert "mate3_x" in net.observations and "opp2_x" in net.observations
    [episode] = play_team(replace(TASKS["duo"], episode_steps=30), net, [0])
    assert episode.steps == 30
    with pytest.raises(PolicyError, match="which a robot in a match does not know"):
        playable(net)
    with pytest.raises(NubotMatchError, match="trains a team in the PettingZoo environment"):
        player(str(tmp_path / "duo" / "policy.npz"), single_task("duo"))

"""A policy file: what it plays, how it is kept, and the clear error for a file that cannot be played."""

import json
import math
import zipfile

import numpy as np
import pytest

from nubot_common.commands import KickKind
from nubot_common.policy import DERIVED, MAX_WEIGHTS, PolicyError, PolicyNet, command_from_action, derived, policy_input

NAMES = ("x", "y", "holding")
LOW, HIGH = np.array([-10.0, -7.0, 0.0]), np.array([10.0, 7.0, 1.0])
ACT_LOW = np.array([-5.0, -5.0, -12.0, 0.0, 0.0])
ACT_HIGH = np.array([5.0, 5.0, 12.0, 1.0, 1.0])


def net(seed=0, hidden=4, **meta):
    rng = np.random.default_rng(seed)
    return PolicyNet(NAMES, LOW, HIGH, ACT_LOW, ACT_HIGH, [rng.normal(size=(hidden, 3)), rng.normal(size=(5, hidden))],
                     [rng.normal(size=hidden), rng.normal(size=5)], meta=dict(meta))


def test_act_is_the_mlp_over_the_rescaled_spaces():
    policy = net()
    obs = np.array([5.0, -3.5, 1.0])
    x = 2.0 * (obs - LOW) / (HIGH - LOW) - 1.0
    out = np.clip(policy.weights[1] @ np.tanh(policy.weights[0] @ x + policy.biases[0]) + policy.biases[1], -1, 1)
    assert policy.act(obs) == pytest.approx(ACT_LOW + (out + 1.0) / 2.0 * (ACT_HIGH - ACT_LOW))
    # an observation beyond its bounds is taken at the bound, as the environment clips it
    assert policy.act([50.0, -3.5, 1.0]) == pytest.approx(policy.act([10.0, -3.5, 1.0]))
    assert np.all(policy.act(obs) >= ACT_LOW) and np.all(policy.act(obs) <= ACT_HIGH)


def test_a_saved_policy_loads_the_same(tmp_path):
    policy = net(env_id="NuBot/ScoreAgainstGoalie-v0", trained_steps=1024)
    path = policy.save(tmp_path / "policy.npz")
    loaded = PolicyNet.load(path)
    assert loaded.observations == NAMES and loaded.meta == {"env_id": "NuBot/ScoreAgainstGoalie-v0",
                                                            "trained_steps": 1024}
    for obs in np.random.default_rng(1).uniform(LOW, HIGH, size=(20, 3)):
        assert loaded.act(obs) == pytest.approx(policy.act(obs), abs=0.0)
    assert not list(tmp_path.glob("*.partial"))


def test_command_from_action():
    cmd = command_from_action([1.0, -0.5, 2.0, 0.9, 0.0], kick_max_speed=12.0)
    assert (cmd.velocity.vx, cmd.velocity.vy, cmd.velocity.w) == (1.0, -0.5, 2.0)
    assert cmd.dribble and cmd.ball_handle == 1 and cmd.kick is None
    kick = command_from_action([0.0, 0.0, 0.0, 0.9, 0.75], kick_max_speed=12.0)
    assert kick.kick is not None and kick.kick.kind == KickKind.GROUND and kick.kick.strength == 9
    assert kick.ball_handle is None  # the handler is left on for the kick to take the ball
    off = command_from_action([0.0, 0.0, 0.0, 0.2, 0.1], kick_max_speed=12.0)
    assert not off.dribble and off.ball_handle == 0 and off.kick is None


@pytest.mark.parametrize("obs, words", [([1.0, 2.0], "3 entries"), ([1.0, float("nan"), 0.0], "not finite: y")])
def test_a_bad_observation_is_named(obs, words):
    with pytest.raises(PolicyError, match=words):
        net().act(obs)


def _write(path, **arrays):
    with open(path, "wb") as handle:
        np.savez(handle, **arrays)
    return path


def test_files_that_are_no_policy_get_a_clear_error(tmp_path):
    good = net().save(tmp_path / "good.npz")
    with np.load(good) as data:
        arrays = {k: data[k] for k in data.files}
    cases = {
        "no policy file": tmp_path / "missing.npz",
        "not a policy file": (tmp_path / "text.npz", b"hello"),
        "lacks w0": _write(tmp_path / "partial.npz", **{k: v for k, v in arrays.items() if k != "w0"}),
        "format 7": _write(tmp_path / "future.npz", **{**arrays, "format": np.array([7])}),
        "takes 3 inputs": _write(tmp_path / "shapes.npz", **{**arrays, "w0": np.ones((4, 5))}),
        "not finite": _write(tmp_path / "nan.npz", **{**arrays, "b1": np.full(5, np.nan)}),
        "actions other than": _write(tmp_path / "acts.npz", **{**arrays, "meta": np.array(json.dumps(
            {"observations": list(NAMES), "actions": ["vx"]}))}),
    }
    for words, case in cases.items():
        if isinstance(case, tuple):
            case[0].write_bytes(case[1])
            case = case[0]
        with pytest.raises(PolicyError, match=words):
            PolicyNet.load(case)


def test_a_file_declaring_huge_layers_is_refused_unread(tmp_path):
    """The header of a small file may declare a layer of billions of numbers: refused before reading it."""
    good = net().save(tmp_path / "good.npz")
    huge = tmp_path / "huge.npz"
    with zipfile.ZipFile(good) as source, zipfile.ZipFile(huge, "w") as out:
        for name in source.namelist():
            data = source.read(name)
            if name == "w0.npy":
                header = np.lib.format.header_data_from_array_1_0(np.zeros((4, 3)))
                header["shape"] = (MAX_WEIGHTS, 3)
                with out.open(name, "w") as stream:
                    np.lib.format.write_array_header_1_0(stream, header)
                continue
            out.writestr(name, data)
    with pytest.raises(PolicyError, match="declares"):
        PolicyNet.load(huge)



def test_the_robot_s_own_view_is_derived_from_the_team_frame_entries():
    """A robot at (1, -2) facing +y; the ball at (3, 1): 3 m ahead and 2 m to its right; the goal's centre (9, 0)."""
    values = {"x": 1.0, "y": -2.0, "cos_theta": 0.0, "sin_theta": 1.0, "ball_dx": 2.0, "ball_dy": 3.0,
              "ball_vx": 1.0, "ball_vy": 0.0, "goalie_x": 1.0, "goalie_y": -2.0, "holding": 0.0}
    view = derived(values, half_length=9.0)
    assert (view["ball_forward"], view["ball_left"]) == pytest.approx((3.0, -2.0))
    assert (view["ball_vforward"], view["ball_vleft"]) == pytest.approx((0.0, -1.0)), "moving to the robot's right"
    assert view["ball_distance"] == pytest.approx(math.sqrt(13.0))
    assert (view["ball_cos"], view["ball_sin"]) == pytest.approx((3.0 / math.sqrt(13), -2.0 / math.sqrt(13)))
    assert (view["goal_distance"], view["goal_cos"], view["goal_sin"]) == pytest.approx(
        (math.sqrt(68.0), 2.0 / math.sqrt(68), -8.0 / math.sqrt(68)))
    assert (view["goalie_distance"], view["goalie_cos"], view["goalie_sin"]) == (0.0, 1.0, 0.0), "on top of it"
    assert set(view) == set(DERIVED)
    vector = policy_input(values, ("holding", "ball_forward", "x"), half_length=9.0)
    assert vector == pytest.approx([0.0, 3.0, 1.0])

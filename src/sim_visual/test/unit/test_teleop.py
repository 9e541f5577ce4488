"""Unit tests of the keyboard teleop core: bindings, limits, ball requests and parameter checks."""

import math

import pytest

from nubot_common import NubotCommonError
from nubot_common.commands import BodyVelocity, KickCommand, KickKind, RobotCommand
from nubot_common.params import from_mapping
from sim_visual.teleop import (
    HELP,
    KEYS,
    MAX_PASS_STRENGTH,
    MIN_PASS_STRENGTH,
    KeyTeleop,
    TeleopParams,
)


@pytest.fixture
def teleop() -> KeyTeleop:
    return KeyTeleop(TeleopParams())


def press(teleop: KeyTeleop, keys: str) -> RobotCommand | None:
    action: RobotCommand | None = RobotCommand()
    for key in keys:
        action = teleop.handle(key)
    return action


@pytest.mark.parametrize(("key", "expected"), [
    ("w", (0.25, 0.0, 0.0)),
    ("s", (-0.25, 0.0, 0.0)),
    ("a", (0.0, 0.25, 0.0)),
    ("d", (0.0, -0.25, 0.0)),
    ("q", (0.0, 0.0, 0.5)),
    ("e", (0.0, 0.0, -0.5)),
])
def test_motion_keys_step_the_command(teleop, key, expected):
    action = teleop.handle(key)
    assert (action.velocity.vx, action.velocity.vy, action.velocity.w) == expected
    assert (teleop.vx, teleop.vy, teleop.w) == expected
    assert action.ball_handle is None and action.kick is None


def test_motion_keys_accumulate_and_cancel(teleop):
    action = press(teleop, "wwwaq")
    assert (action.velocity.vx, action.velocity.vy, action.velocity.w) == (0.75, 0.25, 0.5)
    action = press(teleop, "sssde")
    assert (action.velocity.vx, action.velocity.vy, action.velocity.w) == (0.0, 0.0, 0.0)


def test_odd_steps_cancel_to_exact_zero():
    teleop = KeyTeleop(TeleopParams(linear_step=0.1, angular_step=0.1))
    action = press(teleop, "wwwsss" "aaaddd" "qqqeee")
    assert (action.velocity.vx, action.velocity.vy, action.velocity.w) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize(("key", "axis", "sign"), [("w", 0, 1), ("s", 0, -1), ("a", 1, 1), ("d", 1, -1)])
def test_linear_speed_is_clamped_per_axis(teleop, key, axis, sign):
    action = press(teleop, key * 20)  # 20 * 0.25 = 5 m/s requested
    assert (action.velocity.vx, action.velocity.vy)[axis] == pytest.approx(sign * 3.0)
    assert (action.velocity.vx, action.velocity.vy)[1 - axis] == 0.0


def test_linear_speed_is_clamped_on_the_norm_keeping_direction():
    teleop = KeyTeleop(TeleopParams(linear_step=2.0, max_linear=2.0))
    action = press(teleop, "wa")  # (2, 2) requested: 2.83 m/s diagonally
    assert (action.velocity.vx, action.velocity.vy) == pytest.approx((math.sqrt(2.0), math.sqrt(2.0)))


def test_diagonal_driving_stays_within_the_norm(teleop):
    for key in "wa" * 20:
        action = teleop.handle(key)
        assert math.hypot(action.velocity.vx, action.velocity.vy) <= 3.0 + 1e-12
    assert math.hypot(action.velocity.vx, action.velocity.vy) == pytest.approx(3.0)


@pytest.mark.parametrize(("key", "sign"), [("q", 1), ("e", -1)])
def test_angular_speed_is_clamped(teleop, key, sign):
    action = press(teleop, key * 20)  # 20 * 0.5 = 10 rad/s requested
    assert action.velocity.w == sign * 6.0


def test_clamping_follows_the_parameters():
    teleop = KeyTeleop(TeleopParams(linear_step=1.0, angular_step=1.0, max_linear=1.5, max_angular=2.0))
    action = press(teleop, "wwwqqq")
    assert (action.velocity.vx, action.velocity.w) == (1.5, 2.0)


@pytest.mark.parametrize("key", [" ", "k"])
def test_stop_zeroes_the_command_only(teleop, key):
    press(teleop, "wwaqh+")
    action = teleop.handle(key)
    assert (action.velocity.vx, action.velocity.vy, action.velocity.w) == (0.0, 0.0, 0.0)
    assert action.ball_handle is None and action.kick is None
    assert teleop.dribbling and teleop.pass_strength == 6


def test_dribble_toggle_alternates_enable_and_release(teleop):
    requests = [teleop.handle("h").ball_handle for _ in range(4)]
    assert requests == [1, 0, 1, 0]


def test_dribble_toggle_keeps_the_motion_command(teleop):
    press(teleop, "wq")
    action = teleop.handle("h")
    assert (action.velocity.vx, action.velocity.vy, action.velocity.w, action.ball_handle) == (0.25, 0.0, 0.5, 1)


def test_a_made_kick_turns_the_dribble_mode_off(teleop):
    teleop.handle("h")
    teleop.kick_result(False)
    assert teleop.dribbling, "a refused kick leaves the simulator's dribble mode on"
    teleop.kick_result(True)
    assert not teleop.dribbling
    assert teleop.handle("h").ball_handle == 1


def test_ground_pass_requests_a_shoot_at_the_pass_strength(teleop):
    action = teleop.handle("p")
    assert action.kick == KickCommand(KickKind.GROUND, 5)
    assert action.ball_handle is None


def test_lob_requests_a_shoot_at_the_goal(teleop):
    press(teleop, "+++")
    action = teleop.handle("l")
    assert action.kick == KickCommand(KickKind.LOB, 0)


def test_shoot_keys_keep_the_motion_command(teleop):
    press(teleop, "ww")
    action = teleop.handle("p")
    assert (action.velocity.vx, action.velocity.vy, action.velocity.w) == (0.5, 0.0, 0.0)


def test_pass_strength_steps_by_one(teleop):
    teleop.handle("+")
    assert teleop.handle("p").kick == KickCommand(KickKind.GROUND, 6)
    press(teleop, "--")
    assert teleop.handle("p").kick == KickCommand(KickKind.GROUND, 4)


def test_pass_strength_is_bounded(teleop):
    action = press(teleop, "+" * 20)
    assert action.kick is None
    assert teleop.pass_strength == MAX_PASS_STRENGTH == 12
    assert teleop.handle("p").kick == KickCommand(KickKind.GROUND, 12)
    press(teleop, "-" * 20)
    assert teleop.pass_strength == MIN_PASS_STRENGTH == 1
    assert teleop.handle("p").kick == KickCommand(KickKind.GROUND, 1)


@pytest.mark.parametrize("key", ["x", "\x03"])
def test_quit_keys(teleop, key):
    press(teleop, "w")
    assert teleop.handle(key) is None, "quit: no command to send"


@pytest.mark.parametrize("key", ["z", "W", "1", "\x1b", "\n", "", "ww", "é"])
def test_unknown_keys_change_nothing(teleop, key):
    press(teleop, "wdqh++")
    before = (teleop.vx, teleop.vy, teleop.w, teleop.dribbling, teleop.pass_strength)
    action = teleop.handle(key)
    assert action == RobotCommand(BodyVelocity(0.25, -0.25, 0.5), dribble=True)
    assert (teleop.vx, teleop.vy, teleop.w, teleop.dribbling, teleop.pass_strength) == before
    assert key not in KEYS


def test_help_names_every_binding():
    for label in ("w / s", "a / d", "q / e", "space, k", "h ", "p ", "l ", "+ / -", "x, Ctrl-C"):
        assert label in HELP


def test_status_describes_the_command(teleop):
    press(teleop, "wqh")
    assert teleop.status() == "Vx +0.25 m/s  Vy +0.00 m/s  w +0.50 rad/s  pass 5 m/s  dribble on"


def test_defaults():
    assert TeleopParams() == TeleopParams(linear_step=0.25, angular_step=0.5, max_linear=3.0, max_angular=6.0,
                                          pass_strength=5)


@pytest.mark.parametrize(("field", "value", "message"), [
    ("linear_step", 0.0, r"linear_step must be a positive finite number, got 0\.0"),
    ("angular_step", -0.5, r"angular_step must be a positive finite number, got -0\.5"),
    ("max_linear", math.inf, r"max_linear must be a positive finite number, got inf"),
    ("max_angular", math.nan, r"max_angular must be a positive finite number, got nan"),
    ("pass_strength", 0, r"pass_strength must be in 1\.\.12 m/s, got 0"),
    ("pass_strength", 13, r"pass_strength must be in 1\.\.12 m/s, got 13"),
    ("pass_strength", 5.0, r"pass_strength must be an integer \[m/s\], got 5\.0"),
    ("pass_strength", True, r"pass_strength must be an integer \[m/s\], got True"),
])
def test_invalid_params_raise(field, value, message):
    with pytest.raises(ValueError, match=message):
        TeleopParams(**{field: value})


def test_params_load_from_a_mapping_and_reject_typos():
    assert from_mapping(TeleopParams, {"max_linear": 2, "pass_strength": 8}, "~") == TeleopParams(
        max_linear=2.0, pass_strength=8)
    with pytest.raises(NubotCommonError, match=r"~: unknown parameter\(s\) max_speed"):
        from_mapping(TeleopParams, {"max_speed": 2.0}, "~")
    with pytest.raises(NubotCommonError, match=r"~: pass_strength must be in 1\.\.12 m/s, got 20"):
        from_mapping(TeleopParams, {"pass_strength": 20}, "~")

"""Unit tests of the own sensors' order of trust (omni, front, RGB-D) and of the ball's flight in 3-D."""

import math

import pytest

from nubot_common.ball_flight import GRAVITY
from nubot_common.percepts import Ball3dPercept
from nubot_common.world_state import BallSensor, BallSource
from world_model import WorldModelError

R = 0.11  # the default ball's radius [m]


def lob(t: float, t0: float = 10.0) -> Ball3dPercept:
    """A lob launched at t0 from (2, 0, R) towards the own goal: 5 m/s back, 5 m/s up (fitted velocity known)."""
    dt = t - t0
    return Ball3dPercept(t, 2.0 - 5.0 * dt, 0.5, R + 5.0 * dt + 0.5 * GRAVITY * dt * dt, -5.0, 0.0,
                         5.0 + GRAVITY * dt, True)


def test_omni_is_trusted_before_front_and_front_before_rgbd(make_model, see):
    model = make_model()
    see(model, 10.0, pose=(-2.0, 0.0, math.pi / 2), ball=(-1.0, 1.0))
    model.on_front_ball(10.0, (0.8, 0.1))  # 0.8 m ahead of a robot facing +y: (-2.1, 0.8)
    model.on_ball3d(Ball3dPercept(10.0, -2.0, 1.5, R))
    ball = model.snapshot(10.02).ball
    assert ball.source is BallSource.OWN and ball.sensor is BallSensor.OMNI and (ball.x, ball.y) == (-1.0, 1.0)

    see(model, 10.2, pose=(-2.0, 0.0, math.pi / 2), ball=None)  # omni loses it
    model.on_front_ball(10.2, (0.8, 0.1))
    model.on_ball3d(Ball3dPercept(10.2, -2.0, 1.5, R))
    ball = model.snapshot(10.22).ball
    assert ball.sensor is BallSensor.FRONT
    assert (ball.x, ball.y) == pytest.approx((-2.1, 0.8))

    model.on_ball3d(Ball3dPercept(10.4, -2.0, 1.5, R))  # only the RGB-D cameras still see it
    ball = model.snapshot(10.41).ball
    assert ball.sensor is BallSensor.RGBD and (ball.x, ball.y) == (-2.0, 1.5)


def test_without_a_fresh_sensor_the_freshest_own_sighting_beats_a_teammate(make_model, see, mate_view):
    model = make_model()
    see(model, 10.0, ball=(1.0, 2.0))
    model.on_front_ball(10.1, (1.0, 0.0))  # at (-1, 0): the robot stands at (-2, 0) facing +x
    model.on_teammate(10.3, mate_view(10.3, 2, 0.0, 0.0, ball=(3.0, 3.0)))
    ball = model.snapshot(10.3).ball  # omni 0.3 s old, front 0.2 s: neither within sensor_timeout
    assert ball.source is BallSource.OWN and ball.sensor is BallSensor.FRONT and (ball.x, ball.y) == (-1.0, 0.0)
    ball = model.snapshot(10.45).ball  # both older than ball_timeout now
    assert ball.source is BallSource.TEAMMATE and ball.source_id == 2


def test_a_ball_in_the_air_comes_from_the_rgbd_cameras_with_its_touchdown(make_model, see):
    model = make_model()
    for k in range(10):
        t = 10.0 + k / 30
        see(model, t, ball=(1.0 - 3.0 * k / 30, 0.5))  # omni sees the lob on the floor plane, misplaced
        model.on_ball3d(lob(t))
    t = 10.0 + 9 / 30
    state = model.snapshot(t + 0.01)
    assert state.ball.sensor is BallSensor.RGBD
    assert (state.ball.x, state.ball.y) == pytest.approx((lob(t).x, 0.5))
    assert (state.ball.vx, state.ball.vy) == (-5.0, 0.0), "the cameras' parabola, not a fit on the floor plane"
    flight = state.flight
    assert flight is not None and flight.in_air and flight.touchdown is not None
    x, y, when = flight.touchdown
    flight_time = -2 * 5.0 / GRAVITY  # up and down to the launch height, which is the ball's radius
    assert when == pytest.approx(10.0 + flight_time)
    assert (x, y) == pytest.approx((2.0 - 5.0 * flight_time, 0.5))


def test_a_ball_on_the_ground_has_no_touchdown_and_omni_stays_first(make_model, see):
    model = make_model()
    see(model, 10.0, ball=(1.0, 2.0))
    model.on_ball3d(Ball3dPercept(10.0, 1.05, 2.0, R + 0.02, -1.0, 0.0, 0.0, True))
    state = model.snapshot(10.01)
    assert state.ball.sensor is BallSensor.OMNI
    assert state.flight is not None and not state.flight.in_air and state.flight.touchdown is None
    assert model.snapshot(10.4).flight is None, "older than ball_timeout"


def test_front_ball_before_any_self_localization_is_ignored(make_model, see):
    model = make_model()
    model.on_front_ball(10.0, (0.5, 0.0))
    see(model, 10.01, ball=None)
    assert not model.snapshot(10.02).ball.known


def test_bad_sensor_input_is_refused_or_dropped(make_model, see):
    model = make_model()
    see(model, 10.0, ball=None)
    with pytest.raises(WorldModelError, match="finite"):
        model.on_front_ball(10.0, (math.nan, 0.0))
    with pytest.raises(WorldModelError, match="finite"):
        model.on_ball3d(Ball3dPercept(10.0, 0.0, 0.0, math.inf))
    model.on_ball3d(Ball3dPercept(10.0, 40.0, 0.0, R))  # off the field: a false detection
    model.on_ball3d(Ball3dPercept(10.0, 0.0, 0.0, 50.0))  # far too high
    model.on_front_ball(10.0, (30.0, 0.0))  # 30 m ahead: off the field
    state = model.snapshot(10.01)
    assert not state.ball.known and state.flight is None

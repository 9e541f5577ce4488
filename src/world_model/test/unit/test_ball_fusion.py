"""Unit tests of ball fusion (world_model.ball_fusion): velocity fit, tracks, source choice, confidence."""

import numpy as np
import pytest

from nubot_common.geometry import Pose2D
from nubot_common.percepts import BallPercept
from nubot_common.world_state import BallSource
from world_model.ball_fusion import BallCandidate, BallTrack, ball_confidence, choose_ball, fit_velocity

RATE = 30.0  # vision frames per second


def _noisy_track(velocity, duration, position_std, velocity_std, seed):
    """Observations of a ball rolling at constant ``velocity`` from (1, 2), seen at 30 Hz with Gaussian noise."""
    rng = np.random.default_rng(seed)
    track = BallTrack(keep=5.0)
    for k in range(int(duration * RATE) + 1):
        t = 10.0 + k / RATE
        x, y = 1.0 + velocity[0] * (t - 10.0), 2.0 + velocity[1] * (t - 10.0)
        nx, ny, nvx, nvy = rng.normal(size=4)
        track.add(BallPercept(t, x + position_std * nx, y + position_std * ny,
                                  velocity[0] + velocity_std * nvx, velocity[1] + velocity_std * nvy, True))
    return track


def test_noise_free_positions_give_the_exact_velocity():
    samples = [(t, 1.0 + 2.0 * t, -3.0 - 0.5 * t) for t in np.arange(0.0, 0.3, 1 / RATE)]
    assert fit_velocity(samples, 3) == pytest.approx((2.0, -0.5), abs=1e-9)


@pytest.mark.parametrize("seed", range(5))
def test_velocity_fit_recovers_a_constant_velocity_from_noisy_positions(seed):
    velocity = (1.5, -0.8)
    # The simulator's default noise: 0.05 m on positions; the raw per-frame velocities are far worse here.
    track = _noisy_track(velocity, duration=2.0, position_std=0.05, velocity_std=0.5, seed=seed)
    vx, vy = track.velocity(window=1.0, min_samples=3)
    assert (vx, vy) == pytest.approx(velocity, abs=0.1)
    assert track.latest.velocity_known, "a per-frame velocity was there, and was not used"


def test_the_fit_uses_only_the_window():
    track = BallTrack(keep=5.0)
    for k in range(30):  # at rest for 1 s, then rolling at 2 m/s along x for 0.3 s
        track.add(BallPercept(k / RATE, 0.0, 0.0))
    for k in range(1, 10):
        track.add(BallPercept(1.0 + k / RATE, 2.0 * k / RATE, 0.0))
    assert track.velocity(window=0.25, min_samples=3) == pytest.approx((2.0, 0.0), abs=1e-9)


def test_too_few_or_simultaneous_positions_give_no_velocity():
    assert fit_velocity([(0.0, 0.0, 0.0), (0.1, 1.0, 0.0)], 3) is None
    assert fit_velocity([(0.0, 0.0, 0.0), (0.1, 1.0, 0.0)], 2) == pytest.approx((10.0, 0.0))
    assert fit_velocity([(0.5, 0.0, 0.0)] * 4, 3) is None


def test_track_drops_repeats_keeps_a_short_history_and_restarts_when_the_clock_goes_back():
    track = BallTrack(keep=0.4)
    for k in range(20):
        obs = BallPercept(k * 0.1, float(k), 0.0)
        track.add(obs)
        track.add(obs)  # the relay resends the latest message
    assert len(track) == 5 and track.latest.x == 19.0
    track.add(BallPercept(1.85, 5.0, 5.0))  # late: ignored
    assert track.latest.x == 19.0 and len(track) == 5
    track.add(BallPercept(0.1, 7.0, 7.0))  # the simulation restarted
    assert len(track) == 1 and track.latest.x == 7.0


def _candidate(agent_id, observer, ball, age=0.0, source=BallSource.TEAMMATE):
    return BallCandidate(agent_id, source, BallPercept(10.0 - age, *ball), Pose2D(*observer), age)


def test_own_ball_is_preferred_even_when_a_teammate_is_nearer():
    own = _candidate(1, (-4.0, 0.0), (1.0, 2.0), source=BallSource.OWN)
    mate = _candidate(2, (1.2, 2.0), (1.1, 2.0))
    assert choose_ball(own, [mate]) is own


def test_teammate_fallback_picks_the_teammate_nearest_to_its_ball_then_the_freshest():
    far = _candidate(2, (-3.0, 0.0), (1.0, 2.0))
    near = _candidate(3, (0.0, 2.0), (1.0, 2.1))
    assert choose_ball(None, [far, near]).agent_id == 3
    older = _candidate(4, (0.0, 2.0), (1.0, 2.0), age=0.2)
    newer = _candidate(5, (2.0, 2.0), (1.0, 2.0), age=0.05)
    assert choose_ball(None, [older, newer]).agent_id == 5, "same distance: the fresher report"
    assert choose_ball(None, []) is None


def test_confidence_falls_with_age_and_rises_with_the_robots_seeing_the_ball():
    assert ball_confidence(0.0, 1, 0.3, 0.7) == pytest.approx(0.7)
    assert ball_confidence(0.0, 2, 0.3, 0.7) == pytest.approx(0.91)
    assert ball_confidence(0.15, 1, 0.3, 0.7) == pytest.approx(0.35)
    assert ball_confidence(0.3, 3, 0.3, 0.7) == 0.0
    assert ball_confidence(0.0, 0, 0.3, 0.7) == 0.0
    assert all(0.0 <= ball_confidence(a, n, 0.3, 0.7) <= 1.0 for a in (0.0, 0.1, 1.0) for n in range(6))


def test_the_velocity_fit_is_numpys_least_squares_line():
    import numpy as np

    rng = np.random.default_rng(3)
    for _ in range(50):
        n = int(rng.integers(3, 20))
        t = 100.0 + np.sort(rng.uniform(0.0, 0.5, n))
        xy = rng.normal(0.0, 3.0, 2) + np.outer(t - t[0], rng.normal(0.0, 4.0, 2)) + rng.normal(0.0, 0.05, (n, 2))
        samples = [(float(a), float(b), float(c)) for a, (b, c) in zip(t, xy)]
        slopes = np.polyfit(t - t[-1], xy, 1)[0]
        assert fit_velocity(samples, 3) == pytest.approx(tuple(slopes), rel=1e-9, abs=1e-9)

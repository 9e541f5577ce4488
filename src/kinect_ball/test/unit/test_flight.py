"""Unit tests of kinect_ball.flight: the parabola fitted to the 3-D track, its touchdown, and where a flight
starts (a gap, a kick, a bounce) or rolls."""

import numpy as np
import pytest

from kinect_ball.flight import FlightParams, FlightTracker, Sighting, fit_flight
from nubot_common.ball_flight import GRAVITY, landing

R = 0.11
P = FlightParams()


def lob(t: float, start=(-3.0, 1.0, 0.12), velocity=(-6.0, -0.5, 5.0)) -> np.ndarray:
    x0, v = np.array(start), np.array(velocity)
    p = x0 + v * t
    p[2] += 0.5 * GRAVITY * t * t
    return p


def sightings(times, sigma=0.0, seed=0, **kw) -> list[Sighting]:
    rng = np.random.default_rng(seed)
    out = []
    for t in times:
        p = lob(t, **kw) + rng.normal(0, sigma, 3) if sigma else lob(t, **kw)
        out.append(Sighting(float(t), *map(float, p), max(sigma, 0.002)))
    return out


def test_exact_sightings_give_the_flight_and_its_touchdown():
    tracker = FlightTracker(P, R)
    for s in sightings(np.arange(0.0, 0.5, 1 / 30)):
        percept = tracker.add(s)
    t = percept.stamp
    truth = landing(*lob(t), -6.0, -0.5, 5.0 + GRAVITY * t, R)
    assert percept.velocity_known
    assert np.allclose((percept.vx, percept.vy, percept.vz), (-6.0, -0.5, 5.0 + GRAVITY * t), atol=1e-6)
    down = tracker.touchdown(percept)
    assert abs(down.x - truth.x) < 1e-6 and abs(down.y - truth.y) < 1e-6 and abs(down.t - truth.t) < 1e-6


def test_noisy_sightings_predict_the_touchdown_within_a_few_centimetres():
    tracker = FlightTracker(P, R)
    times = np.arange(0.0, 0.6, 1 / 30)
    for s in sightings(times, sigma=0.01, seed=4):
        percept = tracker.add(s)
    truth = landing(*lob(times[-1]), -6.0, -0.5, 5.0 + GRAVITY * times[-1], R)
    down = tracker.touchdown(percept)
    assert np.hypot(down.x - truth.x, down.y - truth.y) < 0.05


def test_the_velocity_is_unknown_until_enough_sightings():
    tracker = FlightTracker(P, R)
    percepts = [tracker.add(s) for s in sightings(np.arange(0.0, 0.2, 1 / 30))]
    assert [p.velocity_known for p in percepts[:3]] == [False] * 3 and percepts[4].velocity_known
    assert tracker.touchdown(percepts[0]) is None


def test_a_gap_or_a_kick_starts_a_new_flight():
    tracker = FlightTracker(P, R)
    for s in sightings(np.arange(0.0, 0.3, 1 / 30)):
        tracker.add(s)
    assert tracker.flights == 1
    tracker.add(sightings([0.7])[0])  # 0.4 s unseen
    assert tracker.flights == 2 and len(tracker.track) == 1
    later = sightings([0.7 + 1 / 30])[0]
    tracker.add(Sighting(later.stamp, later.x + 1.0, later.y, later.z, later.sigma))  # kicked elsewhere
    assert tracker.flights == 3


def test_a_bounce_starts_a_new_flight():
    """Down to the ground and up again at half the speed: the first parabola would go underground."""
    tracker = FlightTracker(P, R)
    fall = [Sighting(t, -2.0 - 3.0 * t, 0.0, R + 1.0 - 0.5 * 9.8 * t * t + 1e-9, 0.003)
            for t in np.arange(0.0, 0.43, 1 / 30)]
    for s in fall:
        tracker.add(s)
    t0 = 0.4518  # when it reaches the ground
    up = [Sighting(t0 + dt, -2.0 - 3.0 * (t0 + dt), 0.0, R + 2.2 * dt - 4.9 * dt * dt, 0.003)
          for dt in np.arange(0.02, 0.3, 1 / 30)]
    for s in up:
        percept = tracker.add(s)
    assert tracker.flights == 2
    assert percept.velocity_known and abs(percept.vz - (2.2 - 9.8 * (up[-1].stamp - t0))) < 0.05


def test_a_rolling_ball_is_fitted_on_the_ground_and_lands_where_it_is():
    tracker = FlightTracker(P, R)
    for t in np.arange(0.0, 0.3, 1 / 30):
        percept = tracker.add(Sighting(t, 2.0 * t, 0.0, R + 0.005 * np.sin(40 * t), 0.005))
    assert tracker.fit.on_ground and abs(percept.vz) < 0.1 and abs(percept.vx - 2.0) < 0.05
    down = tracker.touchdown(percept)
    assert down.t < 0.05 and abs(down.x - percept.x) < 0.05


def test_time_going_back_starts_over():
    tracker = FlightTracker(P, R)
    for s in sightings(np.arange(0.0, 0.3, 1 / 30)):
        tracker.add(s)
    percept = tracker.add(sightings([0.1])[0])
    assert len(tracker.track) == 1 and not percept.velocity_known


def test_the_fit_weights_the_sightings():
    """A poor sighting (sigma 1 m) hardly moves the fit of good ones."""
    good = sightings(np.arange(0.0, 0.3, 1 / 30))
    bad = Sighting(good[3].stamp, good[3].x + 0.5, good[3].y, good[3].z, 1.0)
    fit = fit_flight(good[:3] + [bad] + good[4:], GRAVITY, R, P.ground_band)
    assert np.linalg.norm(fit.position - lob(good[-1].stamp)) < 0.01


def test_parameters_are_checked():
    with pytest.raises(ValueError, match="gravity must be negative"):
        FlightParams(gravity=9.8)
    with pytest.raises(ValueError, match="min_points"):
        FlightParams(min_points=1)

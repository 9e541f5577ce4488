"""Unit tests of the robot-robot collisions of match_analysis on small hand-made tracks (hull radius: the world's
robot radius, 0.26 m: contact below 0.55 m between centres, separated above 0.62 m)."""

import json

import numpy as np
import pytest

from nubot_common.world_description import RobotBody, WorldDescription
from nubot_match import match_analysis as ma

WORLD = WorldDescription()
RATE = 30.0  # [Hz]
T = np.arange(0, 301) / RATE  # 0-10 s


def still(name, x, y=0.0, t=T):
    return ma.Track(name, t, np.column_stack([np.full(len(t), x), np.full(len(t), y)]))


def along_x(name, waypoints, y=0.0, t=T):
    """A track moving along x through (time, x) waypoints, linear in between."""
    times, xs = zip(*waypoints)
    return ma.Track(name, t, np.column_stack([np.interp(t, times, xs), np.full(len(t), y)]))


def state(t, running):
    return ma.RefereeState(t, ("nubot", "rival"), (0, 0), (1, -1), 1, 0.0, running, "")


def summary(*tracks, referee=(), end=10.0, world=WORLD, **kwargs):
    log = ma.MatchLog(tracks={tr.name: tr for tr in tracks}, referee=list(referee), start=0.0, end=end)
    return ma.analyse(log, world, **kwargs)


def test_robots_in_contact_count_once_and_again_after_separating():
    # rival1 drives into nubot1, stays in contact until 4 s, backs off to 1 m at 5 s, comes back, leaves at 9 s
    rival = along_x("rival1", [(0, 2.0), (2.1, 0.5), (4, 0.5), (5, 1.0), (6.1, 0.5), (8, 0.5), (9, 2.0)])
    found = summary(still("nubot1", 0.0), rival).collisions
    assert [c.robots for c in found] == [("nubot1", "rival1")] * 2
    # centres closer than 0.55 m: after 2.03 s and 5.99 s, at the next 30 Hz samples
    assert [c.t for c in found] == pytest.approx([61 / RATE, 180 / RATE])


def test_jitter_inside_the_hysteresis_band_is_one_collision():
    band = ma.Track("rival1", T, np.column_stack([0.55 + 0.05 * np.sin(2 * np.pi * T), np.zeros(len(T))]))
    beyond = ma.Track("rival1", T, np.column_stack([0.6 + 0.1 * np.sin(2 * np.pi * T), np.zeros(len(T))]))
    assert len(summary(still("nubot1", 0.0), band).collisions) == 1  # 0.50-0.60 m: never separated
    assert len(summary(still("nubot1", 0.0), beyond).collisions) == 10  # 0.50-0.70 m: once per period


def test_contacts_outside_running_time_are_not_counted():
    referee = [state(0.0, True), state(3.0, False), state(6.0, True)]  # stopped 3-6 s
    rival = along_x("rival1", [(0, 2.0), (3.8, 2.0), (4, 0.5), (4.8, 0.5), (5, 2.0),  # touch and go while stopped
                               (5.3, 2.0), (5.5, 0.5), (7, 0.5), (7.5, 2.0),  # touches while stopped, play resumes
                               (8.3, 2.0), (8.5, 0.5)])  # touches in play
    stopped = summary(still("nubot1", 0.0), rival, referee=referee)
    assert [c.t for c in stopped.collisions] == pytest.approx([8.5])
    assert len(summary(still("nubot1", 0.0), rival).collisions) == 3  # all of it running without a referee


def test_collisions_are_split_into_teammates_and_opponents():
    tracks = [still("nubot1", 0.0), along_x("nubot2", [(0, 2.0), (1, 0.5)]),  # teammates at 1 s
              still("rival1", 5.0), along_x("rival2", [(0, 7.0), (2, 5.5)]),  # teammates at 2 s
              along_x("rival3", [(0, -3.0), (3, -0.5)])]  # rival3 meets nubot1 at 3 s, 1 m from nubot2
    s = summary(*tracks)
    assert [(round(c.t), c.robots, c.same_team) for c in s.collisions] == [
        (1, ("nubot1", "nubot2"), True), (2, ("rival1", "rival2"), True), (3, ("nubot1", "rival3"), False)]
    report = s.to_json()["collisions"]
    assert (report["total"], report["same_team"], report["opponents"]) == (3, {"nubot": 1, "rival": 1}, 1)
    assert report["per_minute"] == pytest.approx(18.0)  # 3 in 10 s of running time
    assert report["events"][2] == {"t": 2.967, "robots": ["nubot1", "rival3"]}  # 0.55 m after 2.94 s
    json.dumps(report)


def test_per_minute_uses_running_time_only():
    tracks = [still("nubot1", 0.0), along_x("rival1", [(0, 2.0), (8, 2.0), (9, 0.5)])]
    report = summary(*tracks, referee=[state(0.0, False), state(7.0, True)]).to_json()["collisions"]
    assert report["total"] == 1 and report["per_minute"] == pytest.approx(20.0)  # 1 in 3 s


def test_tracks_with_other_start_times_and_rates_are_compared_only_where_both_exist():
    # nubot1 leaves (0, 0) at 3 s; rival1 appears at 5.02 s (25 Hz) where nubot1 used to be, then drives into it.
    # Holding rival1's first position before its track starts would make a contact at 0-3 s.
    late = 5.02 + np.arange(0, 124) / 25.0
    nubot = along_x("nubot1", [(0, 0.0), (3, 0.0), (4, 3.0)])
    rival = along_x("rival1", [(5.02, 0.3), (6, 0.3), (8, 2.5)], t=late)
    found = summary(nubot, rival).collisions
    assert len(found) == 1 and 7.5 < found[0].t < 8.0


def test_hull_radius_sets_the_contact_distance():
    tracks = [still("nubot1", 0.0), along_x("rival1", [(0, 2.0), (2, 0.5)])]  # closest: 0.5 m
    small = summary(*tracks, hull_radius=0.2)  # contact below 0.43 m
    assert small.collisions == []
    report = small.to_json()
    assert report["hull_radius_m"] == 0.2
    assert (report["collisions"]["contact_distance_m"], report["collisions"]["separation_distance_m"]) == (0.43, 0.5)
    assert summary(*tracks).to_json()["hull_radius_m"] == 0.26
    slim = summary(*tracks, world=WorldDescription(robot=RobotBody(radius=0.2)))  # the world's robots by default
    assert (slim.to_json()["hull_radius_m"], slim.collisions) == (0.2, [])
    assert len(summary(*tracks, contact_tolerance=0.0).collisions) == 1  # 0.5 < 0.52


def test_only_robots_collide():
    tracks = [still("nubot1", 0.0), still("football", 0.1), still("rival1", 3.0)]
    assert summary(*tracks).collisions == []


def test_separation_margin_below_the_contact_tolerance_is_refused():
    with pytest.raises(ValueError, match="separation margin 0.01 m must not be below the contact tolerance"):
        ma.collisions({}, [(0.0, 1.0)], separation_margin=0.01)


def test_interval_index_matches_inside():
    intervals = [(1.0, 5.0), (7.0, 10.0)]
    times = np.array([0.0, 1.0, 4.99, 5.0, 6.0, 7.0, 9.0, 10.0, 11.0])
    assert ma.interval_index(times, intervals).tolist() == [ma.inside(t, intervals) for t in times]
    assert ma.interval_index(times, intervals).tolist() == [-1, 0, 0, -1, -1, 1, 1, 1, -1]
    assert ma.interval_index(times, []).tolist() == [-1] * len(times)


def test_resample_leaves_out_times_a_track_does_not_cover():
    track = ma.Track("nubot1", np.array([1.0, 2.0]), np.array([[0.0, 0.0], [1.0, 2.0]]))
    xy = ma.resample([track], np.array([0.5, 1.0, 1.5, 2.0, 2.5]))
    assert xy.shape == (5, 1, 2)
    assert np.isnan(xy[[0, 4], 0]).all()
    assert xy[1:4, 0].tolist() == [[0.0, 0.0], [0.5, 1.0], [1.0, 2.0]]


@pytest.mark.parametrize("chunk", [1, 7, 60, 100_000])
def test_a_long_match_compared_piece_by_piece_gives_the_same_collisions_and_ball_reaches(monkeypatch, chunk):
    """A whole match is compared a piece of samples at a time (its pairwise arrays would not fit in memory at
    once): a contact that spans two pieces is one collision, and where the pieces fall changes nothing."""
    band = ma.Track("rival1", T, np.column_stack([0.55 + 0.05 * np.sin(2 * np.pi * T), np.zeros(len(T))]))
    beyond = ma.Track("rival2", T, np.column_stack([-0.6 - 0.1 * np.sin(2 * np.pi * T), np.zeros(len(T))]))
    ball = along_x("football", [(0, 3.0), (4, 3.0), (6, 0.8)], y=1.5)
    mover = along_x("nubot2", [(0, -4.0), (5, 2.5)], y=1.5)
    whole = summary(still("nubot1", 0.0), band, beyond, ball, mover)
    monkeypatch.setattr(ma, "_CHUNK", chunk)
    pieces = summary(still("nubot1", 0.0), band, beyond, ball, mover)
    assert [(c.t, c.robots) for c in pieces.collisions] == [(c.t, c.robots) for c in whole.collisions]
    assert len(whole.collisions) == 1 + 10  # rival1 never separates, rival2 once per period
    assert pieces.ball_reaches == whole.ball_reaches and len(whole.ball_reaches) == 1

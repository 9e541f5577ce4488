"""Unit tests of obstacle tracking, fusion and labelling (world_model.obstacles and through the WorldModel)."""

import math
from pathlib import Path

import numpy as np
import pytest

from nubot_common.geometry import Pose2D
from nubot_common.world_state import ObstacleLabel
from world_model.obstacles import ObstacleTracker, label_obstacles
from world_model.params import WorldModelParams

ME = Pose2D(-2.0, 0.0, 0.0)


def test_obstacles_near_a_valid_teammate_are_that_teammate_the_rest_opponents():
    own = [(0.0, 2.1), (0.0, 2.6), (3.0, -1.0)]  # 0.1 m and 0.6 m from teammate 2; far from everyone
    out = label_obstacles(ME, 1, own, {}, {2: (0.0, 2.0), 3: (5.0, 5.0)}, teammate_radius=0.5, merge_radius=0.5)
    assert [(o.label, o.teammate_id) for o in out] == [
        (ObstacleLabel.TEAMMATE, 2), (ObstacleLabel.OPPONENT, 0), (ObstacleLabel.OPPONENT, 0)]
    assert all(o.observer_id == 1 for o in out)


def test_the_nearest_teammate_claims_an_obstacle_between_two():
    out = label_obstacles(ME, 1, [(1.0, 0.0)], {}, {2: (1.4, 0.0), 3: (0.7, 0.0)}, 0.5, 0.5)
    assert out[0].teammate_id == 3


def test_polar_position_is_relative_to_this_robot():
    out = label_obstacles(Pose2D(-2.0, 0.0, math.pi / 2), 1, [(-2.0, 3.0), (-1.0, 0.0)], {}, {}, 0.5, 0.5)
    assert (out[0].angle, out[0].radius) == pytest.approx((0.0, 3.0))
    assert (out[1].angle, out[1].radius) == pytest.approx((-math.pi / 2, 1.0))


def test_teammates_obstacles_add_the_unseen_robots_but_not_this_one_or_known_ones():
    own = [(3.0, -1.0)]
    reported = {2: [(3.1, -1.1),  # the same robot as own obstacle: merged away
                    (-2.1, 0.1),  # this robot, as teammate 2 sees it
                    (6.0, 4.0)]}  # an opponent this robot cannot see
    out = label_obstacles(ME, 1, own, reported, {2: (5.0, 0.0)}, 0.5, 0.5)
    assert [(o.x, o.y, o.observer_id, o.label) for o in out] == [
        (3.0, -1.0, 1, ObstacleLabel.OPPONENT), (6.0, 4.0, 2, ObstacleLabel.OPPONENT)]


def test_world_model_labels_against_valid_teammates_only(make_model, see, mate_view):
    model = make_model(agent_id=1)
    obstacles = ((0.0, 2.1), (4.0, 4.0), (-5.0, -3.0))
    model.on_teammate(10.0, mate_view(10.0, 2, 0.0, 2.0))
    model.on_teammate(10.0, mate_view(10.0, 3, 4.1, 4.0))
    model.on_teammate(10.3, mate_view(10.3, 2, 0.0, 2.0))  # 3 falls silent
    see(model, 10.35, obstacles=obstacles)
    state = model.snapshot(10.35)
    assert [o.label for o in state.obstacles] == [ObstacleLabel.TEAMMATE, ObstacleLabel.OPPONENT,
                                                  ObstacleLabel.OPPONENT]
    assert [(o.x, o.y) for o in state.opponents] == [(4.0, 4.0), (-5.0, -3.0)], "3 is silent: its spot is a threat"


def test_stale_own_vision_gives_no_obstacles(make_model, see):
    model = make_model()
    see(model, 10.0, obstacles=((1.0, 1.0),))
    assert len(model.snapshot(10.29).obstacles) == 1
    assert model.snapshot(10.31).obstacles == ()


def _reference_labels(me, agent_id, own, reported, mates, teammate_radius, merge_radius):
    """The rules of label_obstacles written out plainly (the implementation is tuned for speed)."""
    merged = [(p, agent_id) for p in own]
    for observer in sorted(reported):
        for p in reported[observer]:
            if math.hypot(p[0] - me.x, p[1] - me.y) <= teammate_radius:
                continue
            if not any(math.hypot(p[0] - q[0], p[1] - q[1]) <= merge_radius for q, _ in merged):
                merged.append((p, observer))
    out = []
    for (x, y), observer in merged:
        distances = {aid: math.hypot(x - mx, y - my) for aid, (mx, my) in mates.items() if aid != agent_id}
        near = [aid for aid, d in distances.items() if d <= teammate_radius]
        mate = min(near, key=lambda aid: (distances[aid], aid)) if near else 0
        out.append((x, y, ObstacleLabel.TEAMMATE if mate else ObstacleLabel.OPPONENT, mate, observer))
    return out


def test_labelling_random_scenes_follows_the_rules():
    import random

    rng = random.Random(7)
    for _ in range(300):
        robots = [(rng.uniform(-9, 9), rng.uniform(-6, 6)) for _ in range(10)]
        me = Pose2D(*robots[0], rng.uniform(-3, 3))

        def noisy(points):
            return [(x + rng.gauss(0, 0.2), y + rng.gauss(0, 0.2)) for x, y in points]

        reported = {aid: noisy([r for j, r in enumerate(robots) if j != aid - 1])
                    for aid in range(2, 6) if rng.random() < 0.8}
        mates = {aid: robots[aid - 1] for aid in reversed(list(reported))}
        args = (me, 1, noisy(robots[1:]), reported, mates, 0.5, 0.5)
        out = label_obstacles(*args)
        assert [(o.x, o.y, o.label, o.teammate_id, o.observer_id) for o in out] == _reference_labels(*args)
        assert all(o.radius == pytest.approx(me.distance_to(o.x, o.y)) for o in out)


# --- tracking ---------------------------------------------------------------------------------------------------
FRAME = 1 / 30  # [s] between vision frames
NOISE = 0.05  # [m] per axis, the simulated omni vision's obstacle noise


def tracker(**overrides) -> ObstacleTracker:
    p = WorldModelParams(**overrides)
    return ObstacleTracker(p.obstacle_gate, p.obstacle_position_gain, p.obstacle_velocity_gain, p.obstacle_coast,
                           p.obstacle_max_speed)


def test_a_tracked_robot_is_steadier_than_its_percepts_and_its_velocity_is_known():
    """A robot crossing at (2.0, -1.0) m/s seen with 0.05 m of noise: from a quarter second on the track is nearer
    the truth than the percepts are (0.57 of their error over 20 seeds), and its velocity within 0.4 m/s (0.26 m/s;
    root mean squares)."""
    rng = np.random.default_rng(5)
    track = tracker()
    raw, tracked, velocity = [], [], []
    for k in range(90):
        t = k * FRAME
        truth = np.array([-3.0 + 2.0 * t, 1.0 - 1.0 * t])
        seen = truth + rng.normal(0.0, NOISE, 2)
        track.update(t, [tuple(seen), (5.0, 5.0)])  # and a robot standing
        (mover, standing), (v, rest) = track.estimate(t)
        if t >= 0.25:
            raw.append(np.linalg.norm(seen - truth))
            tracked.append(np.linalg.norm(np.array(mover) - truth))
            velocity.append(np.linalg.norm(np.array(v) - (2.0, -1.0)))
            assert np.linalg.norm(np.array(standing) - (5.0, 5.0)) < 1e-9 and rest == (0.0, 0.0)
    rms = lambda e: math.sqrt(np.mean(np.square(e)))  # noqa: E731
    assert rms(tracked) < 0.75 * rms(raw)
    assert rms(velocity) < 0.4


def test_tracks_follow_their_own_robots_when_two_pass_close():
    """Two robots passing 0.45 m apart at 3 m/s each, in opposite directions: each track keeps its robot."""
    track = tracker()
    for k in range(60):
        t = k * FRAME
        track.update(t, [(-3.0 + 3.0 * t, 0.0), (3.0 - 3.0 * t, 0.45)])
    (a, b), (va, vb) = track.estimate(59 * FRAME)
    assert a[1] == pytest.approx(0.0, abs=1e-6) and va[0] > 2.5
    assert b[1] == pytest.approx(0.45, abs=1e-6) and vb[0] < -2.5


def test_a_track_no_percept_continues_coasts_then_is_dropped_and_a_new_robot_starts_at_rest():
    track = tracker(obstacle_coast=0.1)
    for k in range(30):
        track.update(k * FRAME, [(k * FRAME, 0.0)])  # 1 m/s along x
    (x, _), = track.estimate(29 * FRAME)[0]
    track.update(30 * FRAME, [(4.0, 4.0)])  # hidden now; someone else seen
    (hidden, new), (v_hidden, v_new) = track.estimate(30 * FRAME)
    assert hidden[0] == pytest.approx(x + v_hidden[0] * FRAME) and v_hidden[0] > 0.8, "kept, moving on"
    assert new == (4.0, 4.0) and v_new == (0.0, 0.0)
    track.update(29 * FRAME + 0.11, [(4.0, 4.0)])
    assert track.estimate(29 * FRAME + 0.11)[0] == ((4.0, 4.0),), "dropped after the coast"
    track.update(29 * FRAME + 0.05, [(9.0, 9.0)])
    assert track.estimate(29 * FRAME + 0.11)[0] == ((4.0, 4.0),), "an older frame changes nothing"


def test_a_robot_braking_hard_is_followed_closely():
    """From 3 m/s to rest at 5 m/s^2 (the base's braking), percepts without noise: the track is never more than
    0.1 m off, and at rest again within 0.03 m half a second later."""
    track = tracker()
    worst = 0.0
    for k in range(60):
        t = k * FRAME
        x = 3.0 * t if t < 0.5 else 1.5 + 3.0 * (t - 0.5) - 2.5 * (t - 0.5) ** 2 if t < 1.1 else 2.4
        track.update(t, [(x, 0.0)])
        if t > 0.4:  # the track has found its speed
            worst = max(worst, abs(track.estimate(t)[0][0][0] - x))
    assert worst < 0.1
    assert track.estimate(59 * FRAME)[0][0][0] == pytest.approx(2.4, abs=0.03)


@pytest.mark.parametrize("gains", [(0.0, 0.0), (0.4, 0.4), (1.2, 0.1), (0.4, -0.1)])
def test_gains_that_would_not_settle_are_refused(gains):
    with pytest.raises(ValueError, match="gain"):
        WorldModelParams(obstacle_position_gain=gains[0], obstacle_velocity_gain=gains[1])


def test_the_world_model_s_opponents_are_tracked_moved_on_and_shared_smoothed(make_model, see):
    model = make_model(agent_id=1)
    for k in range(30):
        see(model, 10.0 + k * FRAME, obstacles=((2.0 + 1.5 * k * FRAME, 0.0),))
    last = 10.0 + 29 * FRAME
    state = model.snapshot(last + 0.02)
    (opponent,) = state.opponents
    assert opponent.vx == pytest.approx(1.5, abs=0.1) and opponent.vy == pytest.approx(0.0)
    assert opponent.x == pytest.approx(2.0 + 1.5 * (29 * FRAME + 0.02), abs=0.02), "moved on to the snapshot's time"
    (shared,) = model.own_view(last + 0.02).obstacles
    assert shared[0] == pytest.approx(2.0 + 1.5 * 29 * FRAME, abs=0.02), "shared at the frame's time"


GOLDEN = Path(__file__).resolve().parents[1] / "golden" / "obstacles.npz"


def test_the_compiled_tracker_follows_the_python_tracker_s_golden_trace_exactly():
    """Two robots' trackers of a 30 s seeded lockstep match as the Python implementation ran them
    (``python -m nubot_tools.golden obstacles --seeds 1 --seconds 30 --trackers 2``): all 1800 frames replayed in
    order, every fourth estimate compared. The same arithmetic in the same order: equal to the last bit."""
    with np.load(GOLDEN) as archive:
        trace = dict(archive)  # an archive reads an entry anew at each look
    trackers: dict[int, ObstacleTracker] = {}
    frames = estimates = tracks = 0
    for n, kind in enumerate(trace["kind"]):
        follower = trackers.setdefault(int(trace["tracker"][n]), tracker())
        if kind == 0:
            start, end = trace["percepts_offsets"][frames:frames + 2]
            follower.update(float(trace["time"][n]), [tuple(p) for p in trace["percepts"][start:end]])
            frames += 1
            continue
        start, end = trace["tracks_offsets"][estimates:estimates + 2]
        positions, velocities = follower.estimate(float(trace["time"][n]))
        got = np.column_stack((np.reshape(positions, (-1, 2)), np.reshape(velocities, (-1, 2))))
        np.testing.assert_array_equal(got, trace["tracks"][start:end], err_msg=f"call {n}")
        estimates += 1
        tracks += end - start
    assert frames == 1800 and estimates > 900 and tracks > 3 * estimates


LABELS = Path(__file__).resolve().parents[1] / "golden" / "labels.npz"


def test_the_compiled_labelling_gives_the_python_labelling_s_golden_trace_exactly():
    """600 of the world models' 19,800 labellings in two seeded 30 s lockstep matches, as the Python implementation
    made them (``python -m nubot_tools.golden labels --seeds 2 --seconds 30 --calls 600``, a recorder gone with the
    Python it recorded): the same obstacles in the
    same order, with the same labels, teammates, observers and velocities to the last bit, the bearings and distances
    to 2 units in the last place: C's hypot and Python's own math.hypot differ in the last bit now and then (31 of
    the 10,938 bearings and distances here)."""
    with np.load(LABELS) as archive:
        trace = dict(archive)

    def rows(name: str, n: int) -> np.ndarray:
        start, end = trace[f"{name}_offsets"][n:n + 2]
        return trace[name][start:end]

    merged_from_teammates = teammates = differ = total = 0
    for n, (x, y, theta) in enumerate(trace["me"]):
        reported: dict[int, list[tuple[float, float]]] = {}
        for observer, px, py in rows("reported", n):
            reported.setdefault(int(observer), []).append((px, py))
        mates = {int(aid): (mx, my) for aid, mx, my in rows("mates", n)}
        own = [tuple(p) for p in rows("own", n)]
        got = label_obstacles(Pose2D(x, y, theta), int(trace["agent_id"][n]), own, reported, mates,
                              *trace["radii"][n], [tuple(v) for v in rows("velocities", n)])
        table = np.array([(o.x, o.y, o.label is ObstacleLabel.TEAMMATE, o.teammate_id, o.observer_id, o.angle,
                           o.radius, o.vx, o.vy) for o in got]).reshape(-1, 9)
        want = rows("labelled", n)
        exact = [0, 1, 2, 3, 4, 7, 8]  # all but the bearing and the distance
        np.testing.assert_array_equal(table[:, exact], want[:, exact], err_msg=f"call {n}")
        np.testing.assert_allclose(table[:, 5:7], want[:, 5:7], rtol=4.5e-16, atol=0.0, err_msg=f"call {n}")
        differ += int((table[:, 5:7] != want[:, 5:7]).sum())
        total += 2 * len(want)
        merged_from_teammates += len(got) - len(own)
        teammates += int(table[:, 2].sum())
    assert merged_from_teammates > 0 and teammates > 1000, "the trace holds merges and teammates"
    assert differ <= 0.01 * total, f"{differ} of {total} bearings and distances off in the last bit"

"""Unit tests of obstacle fusion and labelling (world_model.obstacles and through the WorldModel)."""

import math

import pytest

from nubot_common.geometry import Pose2D
from nubot_common.world_state import ObstacleLabel
from world_model.obstacles import label_obstacles

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

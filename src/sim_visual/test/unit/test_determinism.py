"""Two runs of the same seeded scenario give the same trajectory; another seed does not."""

from sim_visual.demo import DemoParams
from sim_visual.episode import run_demo_episode
from sim_visual.params import NoiseParams


def _episode(make_sim, seed):
    sim = make_sim(robots=(("nubot1", -2.0, 0.0, 0.0), ("nubot2", 2.0, 1.0, 3.0)), ball=(1.0, 2.0), seed=seed,
                   noise=NoiseParams(position_std=0.1, velocity_std=0.1, self_position_std=0.05, heading_std=0.02))
    return run_demo_episode(sim, "nubot1", DemoParams(), 20.0)


def test_same_seed_same_trajectory(make_sim):
    first, second = _episode(make_sim, 42), _episode(make_sim, 42)
    assert len(first.robot) > 1000
    assert first.robot == second.robot
    assert first.ball == second.ball
    assert first.transitions == second.transitions


def test_other_seed_other_trajectory(make_sim):
    assert _episode(make_sim, 42).robot != _episode(make_sim, 43).robot

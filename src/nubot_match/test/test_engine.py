"""The lockstep engine: its schedule, one step, a whole refereed match, determinism, and what it refuses."""

import math

import pytest
import yaml

from nubot_common.commands import BodyVelocity, RobotCommand
from nubot_match import NubotMatchError
from nubot_match import match_analysis as ma
from nubot_match.config import TEAMS, load_team, match_config
from nubot_match.engine import LockstepMatch
from nubot_match.record import MatchEvents, MatchListener, MatchLogRecorder


class Counter(MatchListener):
    def __init__(self):
        self.frames, self.cycles, self.states, self.commands = [], [], [], []

    def vision(self, robot, view):
        self.frames.append((view.stamp, robot))

    def robot_step(self, t, robot, step):
        self.cycles.append((t, robot, step.command))

    def model_states(self, t, states):
        self.states.append((t, {n: (s.x, s.y) for n, s in states}))

    def coach(self, t, team, mode, previous):
        self.commands.append((t, team, mode))


def small_teams(tmp_path, robots=2, home_extra=None):
    """Two teams of ``robots`` (goalie first) as YAML files; ``home_extra`` adds keys to the home team."""
    poses = [{"x": -8.4, "y": 0.0}, {"x": -1.0, "y": 0.5}, {"x": -3.0, "y": -2.5}][:robots]
    paths = []
    for prefix, attack, extra in (("nubot", 1, home_extra or {}), ("rival", -1, {})):
        path = tmp_path / f"{prefix}.yaml"
        path.write_text(yaml.safe_dump({"name": prefix, "prefix": prefix, "attack": attack, "goalie": 1,
                                        "robots": poses, **extra}))
        paths.append(path)
    return paths


def test_one_step_is_one_control_cycle_and_the_rates_are_a_ros_match_s(tmp_path):
    home, away = small_teams(tmp_path)
    counter = Counter()
    match = LockstepMatch(match_config(home, away, half_seconds=30), [counter])
    match.reset(0)
    ball3d = []  # the robots asked for the RGB-D cameras' ball
    observe_ball3d = match.sim.observe_ball3d
    match.sim.observe_ball3d = lambda name: ball3d.append(name) or observe_ball3d(name)
    for _ in range(99):  # 3 s at 33 Hz
        before = len(counter.cycles)
        match.step()
        assert len(counter.cycles) - before == 4  # each of the four robots once, none twice
    t = match.time
    assert t == pytest.approx(3.0, abs=0.031)
    assert len(counter.frames) / 4 == pytest.approx(30 * t, abs=1.5)  # omni vision at 30 Hz
    assert set(ball3d) == {"nubot1", "rival1"} and ball3d.count("rival1") == len(counter.frames) / 4, \
        "each team's goalie, with each vision frame"
    assert len(counter.states) == pytest.approx(100 * t, abs=1.5)  # model states at 100 Hz
    assert match.sim.config.physics.step_size <= 0.007
    first = counter.commands[:2]  # the referee's kick-off for the first team, its mirror for the other
    assert {(team, mode.name) for _t, team, mode in first} == {("nubot", "OUR_KICKOFF"), ("rival", "OPP_KICKOFF")}


def test_a_match_is_played_to_full_time_with_both_halves_and_the_ends_changed(tmp_path):
    home, away = small_teams(tmp_path)
    log = MatchLogRecorder()
    match = LockstepMatch(match_config(home, away, half_seconds=5, halves=2), [log])
    match.reset(3)
    final = match.run()
    assert match.done and final.half == 2 and not final.running
    assert final.attack == (-1, 1)  # the teams changed ends at half time
    assert "end of the match" in final.last_event
    summary = ma.analyse(log.finish(), match.config.world)
    assert summary.running_time == pytest.approx(10.0, abs=0.2)  # two halves of 5 s of game time
    assert [s for s in summary.referee_events if "second half begins" in s[1]]
    assert summary.score == dict(zip(final.teams, final.score))


def full_match(seed):
    events = MatchEvents()
    match = LockstepMatch(match_config(half_seconds=4.0, halves=2), [events])
    match.reset(seed)
    match.run()
    final = [(n, round(s.x, 12), round(s.y, 12)) for n, s in match.sim.model_states()]
    return events.events, final, match.state()


def test_a_seed_gives_the_identical_five_vs_five_match_and_another_seed_another():
    first, again, other = full_match(11), full_match(11), full_match(12)
    assert first[0] == again[0] and len(first[0]) > 20  # every event, in order, at the same times
    assert first[1] == again[1]  # every model's final position
    assert first[2] == again[2]
    assert first[1] != other[1] or first[0] != other[0]


def test_external_robots_do_what_the_actions_say_and_the_others_play(tmp_path):
    home, away = small_teams(tmp_path)
    counter = Counter()
    match = LockstepMatch(match_config(home, away, half_seconds=30), [counter], external=["nubot2"])
    match.reset(0)
    start = match.sim.world.robot_state("nubot2")
    go = RobotCommand(BodyVelocity(1.0, 0.0, 0.0))
    for _ in range(66):
        match.step({"nubot2": go})
    end = match.sim.world.robot_state("nubot2")
    assert end.x - start.x == pytest.approx(2.0, abs=0.3)  # 1 m/s forward for 2 s, whatever its agent wanted
    assert {c for _t, r, c in counter.cycles if r == "nubot2"} == {go}  # listeners see what it did
    with pytest.raises(NubotMatchError, match="not external"):
        match.step({"rival2": go})
    with pytest.raises(NubotMatchError, match="do not play"):
        LockstepMatch(match.config, external=["nubot7"])


def test_a_nan_command_is_refused_as_the_simulator_node_refuses_it_and_the_match_plays_on(tmp_path):
    """Once it ended the match with a traceback, where ROS refuses the message and plays on: the robot keeps its last
    good velocity until the simulator's command timeout (0.5 s) stops it, the refusal is reported, the next good
    command drives it again."""
    home, away = small_teams(tmp_path)
    match = LockstepMatch(match_config(home, away, half_seconds=30), external=["nubot2"])
    match.reset(0)
    go, bad = RobotCommand(BodyVelocity(1.0, 0.0, 0.0)), RobotCommand(BodyVelocity(math.nan, 0.0, 0.0))
    for _ in range(33):
        match.step({"nubot2": go})
    before = match.sim.world.robot_state("nubot2")
    steps = [match.step({"nubot2": bad}) for _ in range(33)]
    after = match.sim.world.robot_state("nubot2")
    assert 0.4 < after.x - before.x < 0.8 and math.hypot(after.vx, after.vy) < 0.05  # 1 m/s, then stopped
    assert all(len(s.refused) == 1 for s in steps) and match.refused_commands == 33
    robot, call, reason = steps[0].refused[0]
    assert (robot, call) == ("nubot2", "velocity") and "finite" in reason
    assert not match.done and match.step({"nubot2": go}).refused == []


def test_stepping_before_reset_is_refused():
    with pytest.raises(NubotMatchError, match="reset"):
        LockstepMatch(match_config(half_seconds=10)).step()


STILL = """
from nubot_common.commands import BodyVelocity
from nubot_control.strategy import Strategy


class StandStill(Strategy):
    \"\"\"Plays the built-in strategy's roles but never moves.\"\"\"

    def step(self, state):
        out = super().step(state)
        return type(out)(BodyVelocity(), False, None, *[getattr(out, f) for f in ("role", "action", "target",
                                                                                  "static_pass", "pass_cmd",
                                                                                  "role_of")])
"""


def test_a_team_yaml_names_a_strategy_of_the_user_s_own(tmp_path):
    (tmp_path / "still.py").write_text(STILL)
    home, away = small_teams(tmp_path, home_extra={"strategy": "still.py:StandStill"})
    counter = Counter()
    match = LockstepMatch(match_config(home, away, half_seconds=30), [counter])
    match.reset(0)
    match.run(until=8.0)  # kick-off set-up and play
    moved = {name: math.dist(counter.states[0][1][name], counter.states[-1][1][name]) for name in counter.states[0][1]}
    assert moved["nubot1"] < 0.05 and moved["nubot2"] < 0.05  # the user's strategy: standing still
    assert moved["rival2"] > 0.5  # the built-in one plays
    assert type(match.agents["nubot1"].controller.strategy).__name__ == "StandStill"


@pytest.mark.parametrize("strategy, message", [
    ("missing_module_xyz:Foo", "cannot import module 'missing_module_xyz'"),
    ("nowhere.py:Foo", "no file"),
    ("still.py:Nope", "has no class 'Nope'"),
    ("no colon", "write it as"),
])
def test_a_strategy_that_cannot_be_loaded_is_refused_by_name(tmp_path, strategy, message):
    (tmp_path / "still.py").write_text(STILL)
    home, _away = small_teams(tmp_path, home_extra={"strategy": strategy})
    with pytest.raises(NubotMatchError, match=message) as info:
        load_team(home, match_config().world)
    assert str(home) in str(info.value)


def test_bad_match_options_are_refused_with_a_clear_error(tmp_path):
    with pytest.raises(NubotMatchError, match="half length"):
        match_config(half_seconds=-1)
    with pytest.raises(NubotMatchError, match="halves"):
        match_config(halves=0)
    with pytest.raises(NubotMatchError, match="no world description"):
        match_config(field="30x20")
    with pytest.raises(NubotMatchError, match="tracker"):
        match_config(tracker="pid")
    with pytest.raises(NubotMatchError, match="cannot read"):
        match_config(home=tmp_path / "absent.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: Bad\nprefix: nubot\nattack: 1\ngoalie: 1\nrobots: [{x: 40.0, y: 0.0}]\n")
    with pytest.raises(NubotMatchError, match="off the 18 x 12 m field"):
        match_config(home=bad)
    with pytest.raises(NubotMatchError, match="seed"):
        match_config().with_seed(-1)


def test_a_team_meets_a_variant_of_itself_under_another_prefix_at_the_other_end():
    config = match_config(TEAMS / "nubot.yaml", TEAMS / "nubot.yaml", half_seconds=10)
    a, b = (t.config for t in config.teams)
    assert (a.prefix, a.attack) == ("nubot", 1) and (b.prefix, b.attack) == ("rival", -1)
    swapped = config.swapped()
    assert [(t.config.prefix, t.config.attack) for t in swapped.teams] == [("rival", 1), ("nubot", -1)]

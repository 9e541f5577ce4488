"""Half time over real ROS: after a short first half the referee has the simulator switch ends."""

import math
import time

import pytest

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def short_halves(ros_master, world_launcher, tmp_path_factory):
    launch, stop = world_launcher
    rules = tmp_path_factory.mktemp("rules") / "short.yaml"
    rules.write_text("half_time_break: 2.0\nrestart_timeout: 30.0\n")
    world = launch(ros_master, "half_duration:=4.0", f"config:={rules}")
    yield world
    stop(*world)


def test_at_half_time_the_teams_change_ends_and_each_keeps_its_view(short_halves):
    import rospy

    from nubot_common.msg import OmniVisionInfo

    watcher, sim, referee = short_halves
    seen = {}
    sub = rospy.Subscriber("/nubot1/omnivision/OmniVisionInfo", OmniVisionInfo,
                           lambda m: seen.__setitem__("nubot1", (m.robotinfo[0].pos.x, m.robotinfo[0].pos.y)),
                           queue_size=1)
    try:
        watcher.wait_for(lambda: "nubot1" in seen, timeout=10, what="nubot1's own position")
        before_world, before_team = watcher.states["nubot1"][:2], seen["nubot1"]
        assert before_world == pytest.approx((-2.0, 0.0), abs=0.05)
        assert list(watcher.game.attack) == [1, -1]
        watcher.wait_for(lambda: watcher.game.half == 2, timeout=30, what="the second half")
        assert list(watcher.game.attack) == [-1, 1], "nubot now attacks the goal at -x"
        assert "the teams change ends" in referee.log_text()
        watcher.wait_for(lambda: math.dist(watcher.states["nubot1"][:2], (2.0, 0.0)) < 0.05, timeout=5,
                         what=f"nubot1 turned round the centre spot; states {watcher.states}")
        assert math.dist(watcher.states["rival1"][:2], (-4.0, 3.0)) < 0.05
        time.sleep(0.3)
        assert seen["nubot1"] == pytest.approx(before_team, abs=0.15), "its own team-frame position is unchanged"
        assert "ends switched" in sim.log_text()
    finally:
        sub.unregister()


def test_after_the_change_a_goal_at_minus_x_counts_for_nubot(short_halves):
    watcher, _, _ = short_halves
    watcher.wait_for(lambda: watcher.game.half == 2 and watcher.game.running, timeout=15, what="second-half play")
    before = list(watcher.game.score)
    # rival kicked the second half off, so a ball in the goal at +x would be no goal for rival (RC-8.4.1); one in
    # the goal at -x is nubot's now
    watcher.set_model("football", -9.5, 0.3, z=0.11)
    watcher.wait_for(lambda: list(watcher.game.score) == [before[0] + 1, before[1]], timeout=5,
                     what=f"a goal for nubot; score {list(watcher.game.score)}")
    watcher.wait_for(lambda: (watcher.mode("nubot"), watcher.mode("rival")) == (2, 1), timeout=5,
                     what="the kickoff for rival, who conceded")

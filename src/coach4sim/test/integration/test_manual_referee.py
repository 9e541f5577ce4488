"""The referee node with ~auto false: manual commands only, no simulator needed."""

import time

import pytest

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def manual_referee(ros_master, make_watcher):
    watcher = make_watcher()
    process = ros_master.launch("coach4sim_manual_referee", ["roslaunch", "coach4sim", "referee.launch", "auto:=false"])
    try:
        watcher.wait_for(lambda: watcher.game is not None and watcher.mode("nubot") is not None
                         and watcher.mode("rival") is not None, timeout=30, what="the referee")
    except AssertionError:
        process.stop()
        watcher.close()
        raise AssertionError(f"the referee did not start:\n{process.log_text()[-3000:]}") from None
    yield watcher, process
    watcher.close()
    process.stop()
    time.sleep(0.5)


def test_manual_referee_waits_for_commands_and_mirrors_them(manual_referee, ros_master):
    watcher, process = manual_referee
    assert (watcher.mode("nubot"), watcher.mode("rival")) == (0, 0), "STOPROBOT until told otherwise"
    assert watcher.game.half == 0 and watcher.game.last_event == ""
    assert "/referee" not in ros_master.graph().subscribers.get("/sim_visual/model_states", ()), \
        "no rules without auto"
    response = watcher.command("OUR_FREEKICK", team="rival")
    assert response.accepted and response.message == "OUR_FREEKICK for rival"
    watcher.wait_for(lambda: (watcher.mode("nubot"), watcher.mode("rival")) == (12, 11), timeout=5,
                     what="OPP_FREEKICK for nubot, OUR_FREEKICK for rival")
    refused = watcher.command("OUR_FREEKICK ", team="nubot3")
    assert not refused.accepted and "unknown team 'nubot3'" in refused.message
    time.sleep(0.3)
    assert (watcher.mode("nubot"), watcher.mode("rival")) == (12, 11)
    assert "OUR_FREEKICK for rival" in process.log_text()

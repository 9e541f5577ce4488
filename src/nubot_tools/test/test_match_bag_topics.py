"""What a match's bag leaves out (``nubot_tools.ros.match_runner.UNRECORDED``) and keeps."""

import re

from nubot_tools.ros.match_runner import UNRECORDED


def test_a_match_bag_leaves_tf_and_the_markers_out_and_keeps_what_makes_them():
    left_out = re.compile(UNRECORDED)  # rosbag record -x matches the whole topic name
    for topic in ("/tf", "/match_markers/field", "/match_markers/scene", "/nubot1/camera/image_raw"):
        assert left_out.fullmatch(topic), topic
    for topic in ("/sim_visual/model_states", "/referee/state", "/nubot1/nubotcontrol/path",
                  "/sim_visual/world_description", "/rival3/nubotcontrol/targetinfo"):
        assert not left_out.fullmatch(topic), topic

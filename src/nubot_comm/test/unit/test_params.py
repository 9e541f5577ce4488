"""TeamLinkParams: the robot's side and the coach's, and what each refuses (by name)."""

import pytest

from nubot_comm.codec import DEFAULT_URL
from nubot_comm.params import TeamLinkParams
from nubot_common import NubotCommonError
from nubot_common.params import from_mapping


def test_defaults_serve_nubot1_on_lcms_default_group():
    params = TeamLinkParams()
    assert (params.team_name, params.link_agent, params.lcm_url, params.rate) == ("nubot", 1, DEFAULT_URL, 30.0)


def test_a_robot_speaks_for_its_team_and_agent():
    params = from_mapping(TeamLinkParams, {"robot": "rival4", "team": "rival"})
    assert (params.team_name, params.link_agent) == ("rival", 4)


def test_the_coach_side_serves_its_team_and_sends_as_no_agent():
    params = from_mapping(TeamLinkParams, {"coach": True, "team": "rival"})
    assert (params.team_name, params.link_agent) == ("rival", 0)


@pytest.mark.parametrize(("data", "message"), [
    ({"robot": "nubot2", "team": "rival"}, "team 'rival' is not the team of robot 'nubot2'"),
    ({"robot": "nubot"}, "robot: a robot name is a team prefix and an AgentID"),
    ({"robot": "nubot6"}, "AgentID 6 of nubot6 is beyond team_size 5"),
    ({"robot": "nubot4", "team_size": 3}, "AgentID 4 of nubot4 is beyond team_size 3"),
    ({"team_size": 6}, r"team_size must lie in \[1, 5\], got 6"),
    ({"rate": 0.0}, "rate must be positive, got 0.0"),
    ({"rate": 500.0}, "rate must be at most 200 Hz, got 500.0"),
    ({"max_age": -1.0}, "max_age must be positive"),
    ({"lcm_url": "239.255.76.67:7667"}, "lcm_url must be an LCM URL like udpm://"),
    ({"team": "nu bot", "coach": True}, "a team prefix is 1 to 32 letters"),
    ({"coach": "yes"}, "coach: expected true or false, got 'yes'"),
    ({"rates": 30.0}, "unknown parameter"),
])
def test_bad_parameters_are_refused_by_name(data, message):
    with pytest.raises(NubotCommonError, match=message):
        from_mapping(TeamLinkParams, data, "~")

"""Robot and team names: <team prefix><AgentID>."""

import pytest

from nubot_common import NubotCommonError
from nubot_common.naming import (
    NO_TEAM_COLOUR,
    TEAM_COLOURS,
    RobotName,
    RobotNodeParams,
    RobotSelection,
    check_team_prefix,
    is_robot_name,
    parse_robot_name,
    rgb,
    team_colour,
    team_of,
)
from nubot_common.params import from_mapping


@pytest.mark.parametrize(("name", "team", "agent_id"), [
    ("rival3", "rival", 3), ("nubot1", "nubot", 1), ("my_team12", "my_team", 12), ("Tech5", "Tech", 5)])
def test_a_robot_name_is_its_team_and_its_agent_id(name, team, agent_id):
    parsed = parse_robot_name(name)
    assert (parsed.team, parsed.agent_id) == (team, agent_id)
    assert str(parsed) == name, "and gives the model name back"


@pytest.mark.parametrize("name", ["nubot", "nubot0", "3", "nu bot2", "nubot2a", "", "/nubot2"])
def test_names_that_are_no_robot_are_refused_naming_them(name):
    with pytest.raises(NubotCommonError, match="a robot name is a team prefix and an AgentID from 1"):
        parse_robot_name(name)
    assert not is_robot_name(name)


def test_team_of_a_model_that_is_no_robot_is_its_own_name():
    assert team_of("rival4") == "rival"
    assert team_of("football") == "football"


@pytest.mark.parametrize("prefix", ["nubot2", "", "nu-bot", "nu bot"])
def test_bad_team_prefixes_are_refused(prefix):
    with pytest.raises(NubotCommonError, match="a team prefix is letters and underscores"):
        check_team_prefix(prefix)


def test_robot_names_order_by_team_then_agent_id():
    names = sorted(RobotName(t, k) for t, k in (("rival", 2), ("nubot", 10), ("nubot", 2)))
    assert [str(n) for n in names] == ["nubot2", "nubot10", "rival2"]
    with pytest.raises(NubotCommonError, match="an AgentID is a whole number from 1, got 0"):
        RobotName("nubot", 0)


@pytest.mark.parametrize(("data", "robot", "agent"), [
    ({}, "nubot1", 1), ({"robot": "rival3"}, "rival3", 3), ({"robot": "rival3", "agent_id": 2}, "rival3", 2)])
def test_a_robot_node_plays_as_the_agent_id_in_its_name_unless_told_otherwise(data, robot, agent):
    params = from_mapping(RobotNodeParams, data, "~")
    assert (params.robot, params.name, params.agent) == (robot, parse_robot_name(robot), agent)


@pytest.mark.parametrize(("data", "message"), [
    ({"robot": "nubot1/"}, r"^~: robot: a robot name is a team prefix and an AgentID from 1 .*got 'nubot1/'$"),
    ({"robot": 5}, r"^~\.robot: expected a string, got 5$"),
    ({"agent_id": 2.5}, r"^~\.agent_id: expected an integer, got 2\.5$"),
    ({"agent_id": True}, r"^~\.agent_id: expected an integer, got True$"),
    ({"agent_id": -1}, r"^~: agent_id must be an AgentID from 1 \(0: the one in robot\), got -1$"),
    ({"robt": "nubot2"}, r"^~: unknown parameter\(s\) robt; known: agent_id, robot$"),
])
def test_a_bad_robot_node_parameter_is_refused_by_name(data, message):
    with pytest.raises(NubotCommonError, match=message):
        from_mapping(RobotNodeParams, data, "~")


def test_all_selects_every_robot_whatever_its_name():
    """``all`` selects every robot, of either team, and reads back as ``all``."""
    selection = RobotSelection.parse("all")
    assert selection == RobotSelection(every=True)
    assert "nubot1" in selection and "rival5" in selection
    assert str(selection) == "all"


@pytest.mark.parametrize("text", ["", "   ", ",", " , "])
def test_an_empty_selection_selects_no_robot(text):
    """Nothing (or only separators) selects no robot, and reads back as the empty string."""
    selection = RobotSelection.parse(text)
    assert selection == RobotSelection()
    assert "nubot1" not in selection
    assert str(selection) == ""


@pytest.mark.parametrize("text", ["nubot1,rival2", "rival2, nubot1", "nubot1 rival2", " nubot1,,rival2 ",
                                  "rival2 , nubot1,nubot1"])
def test_names_separated_by_commas_or_spaces_select_those_robots(text):
    """Names separated by commas and/or spaces select exactly those robots; ``str`` lists them sorted, comma
    separated, and parses back to the same selection."""
    selection = RobotSelection.parse(text)
    assert selection.names == frozenset({"nubot1", "rival2"}) and not selection.every
    assert "nubot1" in selection and "rival2" in selection
    assert "nubot2" not in selection and "rival1" not in selection
    assert str(selection) == "nubot1,rival2"
    assert RobotSelection.parse(str(selection)) == selection


@pytest.mark.parametrize(("text", "word"), [("nubot1,coach", "coach"), ("nubot0", "nubot0"),
                                            ("nubot1;rival2", "nubot1;rival2"), ("all,nubot1", "all"),
                                            ("everyone", "everyone"), ("ALL", "ALL")])
def test_a_word_that_is_no_robot_name_is_refused_naming_it(text, word):
    """A word that is neither a robot name nor ``all`` (alone) is refused naming the word and the selection."""
    with pytest.raises(NubotCommonError, match=rf"^robot selection '{text}': '{word}' is not a robot name "
                                               r"\(e\.g\. nubot2\) nor all$"):
        RobotSelection.parse(text)


@pytest.mark.parametrize("text", [None, 3, ["nubot1"]])
def test_a_selection_that_is_no_text_is_refused(text):
    """A selection given as something other than text (a YAML list, a number) is refused showing it."""
    with pytest.raises(NubotCommonError, match=r"a robot selection is all, nothing or names like nubot1,rival2; "
                                               r"got "):
        RobotSelection.parse(text)


def test_a_team_has_one_colour_wherever_it_is_drawn():
    teams = ["nubot", "rival", "guest"]
    assert [team_colour(t, teams) for t in teams] == list(TEAM_COLOURS[:3])
    assert team_colour("rival", ["rival", "nubot"]) == TEAM_COLOURS[0], "the referee's first team is cyan"
    assert team_colour("nobody", teams) == NO_TEAM_COLOUR
    assert rgb("#1ec8e6") == pytest.approx((30 / 255, 200 / 255, 230 / 255))
    with pytest.raises(NubotCommonError, match="#rrggbb"):
        rgb("cyan")

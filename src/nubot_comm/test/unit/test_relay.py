"""Unit tests of the team relay (nubot_comm.relay)."""

import pytest

from nubot_comm.relay import TeamRelay


def test_relays_the_latest_message_of_each_member_in_order():
    relay = TeamRelay("nubot", ("nubot1", "nubot2", "nubot3"))
    relay.put("nubot2", 1.0, "old")
    relay.put("nubot2", 1.5, "new")
    relay.put("nubot1", 1.2, "one")
    assert relay.collect(2.0) == ["one", "new"]


def test_stale_members_are_dropped():
    relay = TeamRelay("nubot", ("nubot1", "nubot2"), max_age=0.5)
    relay.put("nubot1", 1.0, "a")
    relay.put("nubot2", 1.8, "b")
    assert relay.collect(2.0) == ["b"]


def test_never_takes_the_other_teams_messages():
    relay = TeamRelay("nubot", ("nubot1", "nubot2"))
    with pytest.raises(ValueError, match="'rival1' is not a member of team 'nubot'"):
        relay.put("rival1", 1.0, "spy")
    with pytest.raises(ValueError, match="not members of team 'nubot'"):
        TeamRelay("nubot", ("nubot1", "rival2"))

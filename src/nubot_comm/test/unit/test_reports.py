"""What the team link node sends and logs: its robot's own state only while both halves are fresh, and a line about
dropped datagrams at most once a period, a warning only for drops other than another team's channel."""

from nubot_comm.codec import DropReason
from nubot_comm.link import LinkStats
from nubot_comm.reports import DropReport, OwnState


def _stats(**dropped: int) -> LinkStats:
    counts = {reason: dropped.get(reason.name.lower(), 0) for reason in DropReason}
    return LinkStats(sent=0, heard=sum(counts.values()), accepted=0, echoes=0, dropped=counts)


def test_own_state_is_sent_only_with_both_halves_fresh():
    own: OwnState[str, str] = OwnState(max_age=0.5)
    assert own.fresh(0.0) is None
    own.message(1.0, "message")
    assert own.fresh(1.0) is None  # no strategy heard yet
    own.strategy(1.2, "strategy")
    assert own.fresh(1.4) == ("message", "strategy")
    assert own.fresh(1.6) is None  # the message is 0.6 s old: the world model went quiet
    own.message(1.6, "newer")
    assert own.fresh(1.6) == ("newer", "strategy")


def test_drops_are_reported_once_a_period_and_only_faults_warn():
    report = DropReport(_stats(), period=5.0)
    assert report.due(_stats(), 0.0) is None  # nothing dropped
    line = report.due(_stats(foreign_channel=3), 1.0)
    assert line == ("team_link: 3 datagrams dropped since the last report (in all: foreign_channel 3)", False)
    assert report.due(_stats(foreign_channel=3, malformed=2), 2.0) is None  # within the period
    line = report.due(_stats(foreign_channel=3, malformed=2), 6.0)
    assert line is not None and line[0].startswith("team_link: 2 datagrams") and line[1]  # malformed: a fault

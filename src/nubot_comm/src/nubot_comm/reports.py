"""What the team link node decides without ROS: which of its robot's own state is fresh enough to send, and when
the datagrams it dropped are worth a log line.

Requires: a clock in seconds from the caller. Provides: ``OwnState`` (the robot's latest TeamMessage and
StrategyInfo with the time each was heard; both are sent together, or neither once one is older than ``max_age``)
and ``DropReport`` (a line about the datagrams dropped since the last line, at most every ``period`` [s]; a warning
when any was dropped for another reason than belonging to another team's channel, which two teams on one LAN give
as a matter of course).
"""

from __future__ import annotations

import threading
from typing import Generic, TypeVar

from nubot_comm.codec import DropReason
from nubot_comm.link import LinkStats

Message = TypeVar("Message")
Strategy = TypeVar("Strategy")


class OwnState(Generic[Message, Strategy]):
    def __init__(self, max_age: float):
        self.max_age = max_age  # [s]
        self._lock = threading.Lock()
        self._message: tuple[float, Message] | None = None
        self._strategy: tuple[float, Strategy] | None = None

    def message(self, now: float, message: Message) -> None:
        with self._lock:
            self._message = (now, message)

    def strategy(self, now: float, strategy: Strategy) -> None:
        with self._lock:
            self._strategy = (now, strategy)

    def fresh(self, now: float) -> tuple[Message, Strategy] | None:
        """The message and the strategy to send at ``now`` [s]: both heard within ``max_age``, else None."""
        with self._lock:
            message, strategy = self._message, self._strategy
        if message is None or strategy is None or now - message[0] > self.max_age or now - strategy[0] > self.max_age:
            return None
        return message[1], strategy[1]


def drops_text(stats: LinkStats) -> str:
    return ", ".join(f"{reason.value} {count}" for reason, count in stats.dropped.items() if count)


class DropReport:
    def __init__(self, first: LinkStats, period: float):
        self.period = period  # [s] between two lines
        self._logged, self._logged_at = first, -float("inf")  # the counters last logged, and when

    def due(self, stats: LinkStats, now: float) -> tuple[str, bool] | None:
        """The line to log at ``now`` [s] and whether it is a warning, or None."""
        logged = self._logged
        if stats.total_dropped <= logged.total_dropped or now - self._logged_at < self.period:
            return None
        faults = any(n > logged.dropped[r] for r, n in stats.dropped.items() if r is not DropReason.FOREIGN_CHANNEL)
        self._logged, self._logged_at = stats, now
        return (f"team_link: {stats.total_dropped - logged.total_dropped} datagrams dropped since the last report "
                f"(in all: {drops_text(stats)})", faults)

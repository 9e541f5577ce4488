"""Many matches summed up: each figure with its 95 % confidence interval, a table, a verdict and a plot.

Requires: per-match results (``MatchResult``: HOME's and AWAY's goals, passes completed, possession
share, shots, collisions, each from HOME's point of view whatever end it played at).
Provides: ``summarise`` -> ``Summary`` (rows of mean and 95 % CI per team and figure; wins, draws and
losses as shares with Wilson intervals; the goal difference per match with a Student-t interval),
``table_text`` (a Markdown table), ``verdict`` (one line) and ``plot_goal_difference`` (a PNG).
Confidence intervals: means use the t distribution over the per-seed means (the matches of one seed,
one each way round, are a pair and one independent unit: n seeds, n - 1 degrees of freedom); wins,
draws and losses use the Wilson score interval per match (``scipy.stats.binomtest``); with one unit
an interval is unknown (NaN) and said so.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from scipy import stats

LEVEL = 0.95
FIGURES = ("goals", "passes_completed", "possession", "shots", "collisions")  # per team, per match
WORDS = {"goals": "goals", "passes_completed": "passes completed", "possession": "possession (share of play)",
         "shots": "shots", "collisions": "collisions (own team + with opponents)"}


@dataclass(frozen=True)
class MatchResult:
    index: int  # match number, 0-based
    seed: int
    home_attacks: int  # the end HOME attacked in the first half: 1 (+x) or -1 (-x)
    home: dict[str, float]  # FIGURES for HOME
    away: dict[str, float]  # FIGURES for AWAY
    sim_seconds: float  # [s] simulated
    wall_seconds: float  # [s] the match took
    rss_mib: float  # peak resident memory of the process that played it [MiB]
    events: int = 0  # referee events

    def to_json(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class Interval:
    mean: float
    low: float
    high: float

    def text(self, digits: int = 2) -> str:
        if math.isnan(self.low):
            return f"{self.mean:.{digits}f} (CI unknown: one seed)"
        return f"{self.mean:.{digits}f} [{self.low:.{digits}f}, {self.high:.{digits}f}]"


@dataclass(frozen=True)
class Summary:
    matches: int
    home: str
    away: str
    rows: dict[str, tuple[Interval, Interval]]  # figure -> (HOME, AWAY)
    outcomes: dict[str, tuple[int, Interval]]  # wins / draws / losses of HOME: count, share with CI
    goal_difference: Interval  # HOME minus AWAY goals per match

    def to_json(self) -> dict:
        return {"matches": self.matches, "home": self.home, "away": self.away, "confidence": LEVEL,
                "figures": {k: {"home": asdict(h), "away": asdict(a)} for k, (h, a) in self.rows.items()},
                "outcomes": {k: {"count": n, **asdict(i)} for k, (n, i) in self.outcomes.items()},
                "goal_difference": asdict(self.goal_difference)}


def mean_interval(values: Sequence[float]) -> Interval:
    """The mean of ``values`` with its Student-t 95 % interval (NaN bounds for fewer than two values)."""
    x = np.asarray(values, dtype=float)
    if len(x) == 0:
        return Interval(math.nan, math.nan, math.nan)
    mean = float(x.mean())
    if len(x) < 2:
        return Interval(mean, math.nan, math.nan)
    sem = float(x.std(ddof=1)) / math.sqrt(len(x))
    if sem == 0.0:
        return Interval(mean, mean, mean)
    low, high = stats.t.interval(LEVEL, len(x) - 1, loc=mean, scale=sem)
    return Interval(mean, float(low), float(high))


def share_interval(count: int, total: int) -> Interval:
    """``count`` of ``total`` as a share with its Wilson 95 % interval."""
    if total == 0:
        return Interval(math.nan, math.nan, math.nan)
    ci = stats.binomtest(count, total).proportion_ci(confidence_level=LEVEL, method="wilson")
    return Interval(count / total, float(ci.low), float(ci.high))


def per_seed(results: Sequence[MatchResult], value: Callable[[MatchResult], float]) -> list[float]:
    """``value`` averaged over the matches of each seed: the independent units. The two matches of a seed (one
    each way round) are a pair; with identical teams they mirror each other, so counting them as two independent
    matches would halve nothing but the interval."""
    by_seed: dict[int, list[float]] = {}
    for r in results:
        by_seed.setdefault(r.seed, []).append(value(r))
    return [sum(v) / len(v) for v in by_seed.values()]


def _figure(results: Sequence[MatchResult], side: str, figure: str) -> list[float]:
    return per_seed(results, lambda r: getattr(r, side)[figure])


def _goal_difference(r: MatchResult) -> float:
    return r.home["goals"] - r.away["goals"]


def summarise(results: Sequence[MatchResult], home: str = "HOME", away: str = "AWAY") -> Summary:
    rows = {f: (mean_interval(_figure(results, "home", f)), mean_interval(_figure(results, "away", f)))
            for f in FIGURES}
    diff = [_goal_difference(r) for r in results]
    n = len(results)
    wins, draws = sum(d > 0 for d in diff), sum(d == 0 for d in diff)
    outcomes = {"wins": (wins, share_interval(wins, n)), "draws": (draws, share_interval(draws, n)),
                "losses": (n - wins - draws, share_interval(n - wins - draws, n))}
    return Summary(n, home, away, rows, outcomes,
                   mean_interval(per_seed(results, _goal_difference)))


def table_text(s: Summary) -> str:
    """A Markdown table: per match, mean and 95 % CI of each figure for both teams; HOME's outcomes."""
    lines = [f"| per match ({s.matches} matches, 95 % CI over seeds) | {s.home} | {s.away} |", "| --- | --- | --- |"]
    for key, (n, share) in s.outcomes.items():
        other = {"wins": "losses", "losses": "wins", "draws": "draws"}[key]
        m, o = s.outcomes[other]
        lines.append(f"| {key} | {n} ({share.text(2)}) | {m} ({o.text(2)}) |")
    for figure, (h, a) in s.rows.items():
        lines.append(f"| {WORDS[figure]} | {h.text()} | {a.text()} |")
    d = s.goal_difference
    lines.append(f"| goal difference ({s.home} - {s.away}) | {d.text()} | |")
    return "\n".join(lines) + "\n"


def verdict(s: Summary) -> str:
    """One line: which team is better by how many goals per match, or that the matches cannot tell."""
    d = s.goal_difference
    if s.matches == 0:
        return "no match finished: no verdict"
    if math.isnan(d.low):
        return (f"{s.home} - {s.away}: {d.mean:+.1f} goals per match over one seed; play at least 4 matches "
                "(two seeds) for a verdict")
    ci = f"95 % CI [{d.low:+.1f}, {d.high:+.1f}]"
    if d.low > 0:
        return f"{s.home} better than {s.away} by {d.mean:+.1f} goals per match, {ci}"
    if d.high < 0:
        return f"{s.away} better than {s.home} by {-d.mean:+.1f} goals per match, {ci}"
    return (f"no clear difference between {s.home} and {s.away}: {d.mean:+.1f} goals per match, {ci}; "
            f"more matches narrow it")


def plot_goal_difference(results: Sequence[MatchResult], s: Summary, path: Path) -> None:
    """A bar chart of how often each goal difference occurred, with the mean and its CI."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    diff = np.array([r.home["goals"] - r.away["goals"] for r in results], dtype=int)
    fig, ax = plt.subplots(figsize=(7, 4))
    if len(diff):
        values, counts = np.unique(diff, return_counts=True)
        ax.bar(values, counts, width=0.8, color=["tab:green" if v > 0 else "tab:gray" if v == 0 else "tab:red"
                                                 for v in values])
        d = s.goal_difference
        ax.axvline(d.mean, color="k", label=f"mean {d.mean:+.2f}")
        if not math.isnan(d.low):
            ax.axvspan(d.low, d.high, color="k", alpha=0.12, label=f"95 % CI [{d.low:+.2f}, {d.high:+.2f}]")
        ax.legend()
    ax.set_xlabel(f"goal difference per match ({s.home} - {s.away})")
    ax.set_ylabel("matches")
    ax.set_title(f"{s.home} vs {s.away}: {s.matches} matches")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)

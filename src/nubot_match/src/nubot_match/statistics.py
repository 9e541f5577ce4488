"""Many matches summed up: each figure with its 95 % confidence interval, a table, a verdict and a plot.

Requires: per-match results (``MatchResult``: HOME's and AWAY's ``FIGURES`` (goals, shots, passes,
possession, collisions, fouls), each from HOME's point of view whatever end it played at, and the whole
match's ``MATCH_COUNTS``: running and stopped time [s], goals, shots and the shots that scored, passes,
collisions, fouls and goals by kind).
Provides: ``summarise`` -> ``Summary`` (rows of mean and 95 % CI per team and figure; the ``YARDSTICKS``
that say whether the matches play like MSL matches, each with its interval, target and verdict; wins,
draws and losses as shares with Wilson intervals; the goal difference per match with a Student-t
interval), ``table_text`` (Markdown tables), ``verdict`` (one line), ``plot_goal_difference`` (a PNG) and
``rate_interval`` (a count per unit of time with its exact Poisson interval).
Confidence intervals: every match is an independent game (a seed of its own), so figures and yardsticks
use the t distribution over the matches; the goal difference pairs the two matches each way round
(``MatchResult.pair``: one unit, n pairs, n - 1 degrees of freedom), which takes what an end or a
kick-off gives out of the comparison; wins, draws and losses use the Wilson score interval per match
(``scipy.stats.binomtest``); with one unit an interval is unknown (NaN) and said so. Yardsticks are
per MSL match (2 x 15 min on the match clock, which runs through stoppages as the MSL RefBox's game time does;
our referee's half clock runs only while the ball is in play): each match's counts are scaled by its running plus
stopped time within the halves; collisions are per minute of running time.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
from scipy import stats

LEVEL = 0.95
FIGURES = ("goals", "shots", "shots_on_target", "passes_tried", "passes_completed", "possession", "collisions",
           "fouls")  # per team, per match
WORDS = {"goals": "goals", "shots": "shots", "shots_on_target": "shots on target", "passes_tried": "passes tried",
         "passes_completed": "passes completed", "possession": "possession (share of play)",
         "collisions": "collisions (own team + with opponents)", "fouls": "fouls"}
# The whole match's counts behind the yardsticks (besides fouls_<kind> and goals_<cause>, one per kind).
MATCH_COUNTS = ("running_s", "stopped_s", "goals", "shots", "shots_scored", "passes_tried", "passes_completed",
                "collisions")
MATCH_SECONDS = 1800.0  # an MSL match: 2 x 15 min on the RefBox's game clock, stoppages included [s]


@dataclass(frozen=True)
class MatchResult:
    index: int  # match number, 0-based
    seed: int  # the match's own seed
    home_attacks: int  # the end HOME attacked in the first half: 1 (+x) or -1 (-x)
    home: dict[str, float]  # FIGURES for HOME
    away: dict[str, float]  # FIGURES for AWAY
    sim_seconds: float  # [s] simulated
    wall_seconds: float  # [s] the match took
    rss_mib: float  # peak resident memory of the process that played it [MiB]
    events: int = 0  # referee events
    pair: int = -1  # the two matches each way round share a pair (-1: the match is a pair of its own)
    match: dict[str, float] = field(default_factory=dict)  # MATCH_COUNTS, fouls_<kind>, goals_<cause>
    goals: list[dict] = field(default_factory=list)  # each goal explained (``match_shots.ShotReport.to_json``)
    solver_errors: int = 0  # "LCP internal error"s of the physics' solver in the match (``PhysicsWorld.solver_errors``)

    @property
    def unit(self) -> int:
        """The independent unit of the goal difference: the pair, else the match."""
        return self.pair if self.pair >= 0 else -1 - self.index

    def to_json(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class Interval:
    mean: float
    low: float
    high: float

    def text(self, digits: int = 2) -> str:
        if math.isnan(self.mean):
            return "unknown"
        if math.isnan(self.low):
            return f"{self.mean:.{digits}f} (CI unknown: one unit)"
        return f"{self.mean:.{digits}f} [{self.low:.{digits}f}, {self.high:.{digits}f}]"


@dataclass(frozen=True)
class Yardstick:
    """A figure of the whole match that an MSL match keeps within ``low``..``high`` (None: no bound)."""

    name: str
    words: str
    value: Callable[[dict[str, float]], float | None]  # from a match's counts; None when it has no value
    low: float | None = None
    high: float | None = None

    def target(self) -> str:
        if self.low is not None and self.high is not None:
            return f"{self.low:g} to {self.high:g}"
        if self.low is not None:
            return f"at least {self.low:g}"
        return f"at most {self.high:g}" if self.high is not None else "(reported)"

    def met(self, mean: float) -> bool | None:
        """Whether the mean lies within the target; None without a target or a mean."""
        if (self.low is None and self.high is None) or math.isnan(mean):
            return None
        return (self.low is None or mean >= self.low) and (self.high is None or mean <= self.high)


def _per_match(counts: dict[str, float], key: str) -> float | None:
    """``key`` per MSL match: scaled by the match clock (running and stopped time within the halves)."""
    clock = counts.get("running_s", 0.0) + counts.get("stopped_s", 0.0)
    return counts.get(key, 0.0) * MATCH_SECONDS / clock if clock > 0 else None


def _share(numerator: str, denominator: str) -> Callable[[dict[str, float]], float | None]:
    def value(counts: dict[str, float]) -> float | None:
        total = counts.get(denominator, 0.0)
        return counts.get(numerator, 0.0) / total if total > 0 else None
    return value


def _per_minute(key: str) -> Callable[[dict[str, float]], float | None]:
    def value(counts: dict[str, float]) -> float | None:
        running = counts.get("running_s", 0.0)
        return counts.get(key, 0.0) * 60.0 / running if running > 0 else None
    return value


def _running_share(counts: dict[str, float]) -> float | None:
    total = counts.get("running_s", 0.0) + counts.get("stopped_s", 0.0)
    return counts.get("running_s", 0.0) / total if total > 0 else None


YARDSTICKS = (
    Yardstick("goals", "goals per match (2 x 15 min match clock)", lambda c: _per_match(c, "goals"), 3.0, 10.0),
    Yardstick("shots_per_team_half", "shots per team per 15 min half",
              lambda c: (v / 4.0 if (v := _per_match(c, "shots")) is not None else None)),
    Yardstick("scoring_share", "share of shots that score", _share("shots_scored", "shots"), 0.10, 0.30),
    Yardstick("collisions_per_minute", "robot-robot collisions per running minute", _per_minute("collisions"),
              None, 5.0),
    Yardstick("pass_completion", "share of passes completed", _share("passes_completed", "passes_tried"), 0.70),
    Yardstick("running_share", "share of the match the ball is in play", _running_share, 0.60),
)


def kinds_in(results: Sequence[MatchResult], prefix: str) -> list[str]:
    """The kinds counted as ``<prefix><kind>`` in the matches' counts (fouls_, goals_), in order of appearance."""
    kinds: list[str] = []
    for r in results:
        kinds += [k[len(prefix):] for k in r.match if k.startswith(prefix) and k[len(prefix):] not in kinds]
    return kinds


@dataclass(frozen=True)
class Summary:
    matches: int
    home: str
    away: str
    rows: dict[str, tuple[Interval, Interval]]  # figure -> (HOME, AWAY)
    outcomes: dict[str, tuple[int, Interval]]  # wins / draws / losses of HOME: count, share with CI
    goal_difference: Interval  # HOME minus AWAY goals per match
    yardsticks: dict[str, Interval] = field(default_factory=dict)  # YARDSTICKS by name
    fouls: dict[str, Interval] = field(default_factory=dict)  # per match (2 x 15 min match clock), by kind
    causes: dict[str, Interval] = field(default_factory=dict)  # goals per match by what led to them

    def to_json(self) -> dict:
        sticks = {y.name: {**asdict(self.yardsticks[y.name]), "target": y.target(),
                           "met": y.met(self.yardsticks[y.name].mean)} for y in YARDSTICKS if y.name in self.yardsticks}
        return {"matches": self.matches, "home": self.home, "away": self.away, "confidence": LEVEL,
                "figures": {k: {"home": asdict(h), "away": asdict(a)} for k, (h, a) in self.rows.items()},
                "outcomes": {k: {"count": n, **asdict(i)} for k, (n, i) in self.outcomes.items()},
                "goal_difference": asdict(self.goal_difference),
                "yardsticks": sticks, "fouls_per_match": {k: asdict(v) for k, v in self.fouls.items()},
                "goals_per_match_by_cause": {k: asdict(v) for k, v in self.causes.items()}}


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


def rate_interval(count: int, exposure: float) -> Interval:
    """``count`` events in ``exposure`` (e.g. minutes) as a rate with its exact Poisson (Garwood) 95 % interval: the
    counting noise that a handful of events has whatever the spread between matches (no goal in four matches is
    a rate of 0 known to within about 0.3 per running minute of twelve, not 0 +- 0)."""
    if count < 0 or not exposure > 0.0:
        raise ValueError(f"a rate needs a count >= 0 and an exposure > 0, got {count} in {exposure}")
    alpha = 1.0 - LEVEL
    low = 0.0 if count == 0 else float(stats.chi2.ppf(alpha / 2.0, 2 * count)) / 2.0
    high = float(stats.chi2.ppf(1.0 - alpha / 2.0, 2 * count + 2)) / 2.0
    return Interval(count / exposure, low / exposure, high / exposure)


def per_unit(results: Sequence[MatchResult], value: Callable[[MatchResult], float]) -> list[float]:
    """``value`` averaged over the matches of each pair (``MatchResult.unit``): the two matches each way round of a
    comparison are one unit of the goal difference."""
    by_unit: dict[int, list[float]] = {}
    for r in results:
        by_unit.setdefault(r.unit, []).append(value(r))
    return [sum(v) / len(v) for v in by_unit.values()]


def _figure(results: Sequence[MatchResult], side: str, figure: str) -> list[float]:
    return [getattr(r, side).get(figure, 0.0) for r in results]


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
    sticks = {}
    for y in YARDSTICKS:
        values = [v for r in results if (v := y.value(r.match)) is not None]
        sticks[y.name] = mean_interval(values)
    fouls = {k: mean_interval([v for r in results if (v := _per_match(r.match, f"fouls_{k}")) is not None])
             for k in kinds_in(results, "fouls_")}
    causes = {k: mean_interval([v for r in results if (v := _per_match(r.match, f"goals_{k}")) is not None])
              for k in kinds_in(results, "goals_")}
    return Summary(n, home, away, rows, outcomes, mean_interval(per_unit(results, _goal_difference)), sticks, fouls,
                   causes)


def table_text(s: Summary) -> str:
    """Markdown tables: per match, mean and 95 % CI of each figure for both teams and HOME's outcomes; then the
    yardsticks of an MSL match with their targets, the fouls and the goals by what led to them."""
    lines = [f"| per match ({s.matches} matches, 95 % CI) | {s.home} | {s.away} |", "| --- | --- | --- |"]
    for key, (n, share) in s.outcomes.items():
        other = {"wins": "losses", "losses": "wins", "draws": "draws"}[key]
        m, o = s.outcomes[other]
        lines.append(f"| {key} | {n} ({share.text(2)}) | {m} ({o.text(2)}) |")
    for figure, (h, a) in s.rows.items():
        lines.append(f"| {WORDS[figure]} | {h.text()} | {a.text()} |")
    d = s.goal_difference
    lines.append(f"| goal difference ({s.home} - {s.away}; pairs each way round) | {d.text()} | |")
    if s.yardsticks:
        lines += ["", "| an MSL match? (per 2 x 15 min match clock, 95 % CI) | mean | target | met |",
                  "| --- | --- | --- | --- |"]
        for y in YARDSTICKS:
            value = s.yardsticks.get(y.name)
            if value is None:
                continue
            met = y.met(value.mean)
            lines.append(f"| {y.words} | {value.text()} | {y.target()} | "
                         f"{'' if met is None else 'yes' if met else 'NO'} |")
        for kind, value in s.fouls.items():
            lines.append(f"| fouls: {kind} | {value.text()} | (reported) | |")
        for cause, value in s.causes.items():
            lines.append(f"| goals from: {cause} | {value.text()} | (reported) | |")
    return "\n".join(lines) + "\n"


def verdict(s: Summary) -> str:
    """One line: which team is better by how many goals per match, or that the matches cannot tell."""
    d = s.goal_difference
    if s.matches == 0:
        return "no match finished: no verdict"
    if math.isnan(d.low):
        return (f"{s.home} - {s.away}: {d.mean:+.1f} goals per match over one pair; play at least 4 matches "
                "(two pairs) for a verdict")
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

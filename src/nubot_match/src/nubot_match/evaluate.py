"""Compare two teams over many seeded lockstep matches, on every core or on a dask cluster.

    python scripts/evaluate.py --home A.yaml --away B.yaml --matches 40 --half-seconds 300 [--jobs N]
                               [--scheduler tcp://host:8786] [--field 18x12] [--tracker mpc] [--seed 0]
                               [--out DIR [--resume]]

Requires: two team YAMLs (a team may name a strategy class of its own, ``nubot_control.plugins``). With
``--policy FILE`` instead, a trained policy file plays against the scripted striker (``learn.compare``).
Match i is played with seed ``--seed + i``; odd matches swap the sides (AWAY kicks off and each team
starts at the other end), so matches 2k and 2k + 1 are a pair, one each way round, but every match is a
game of its own (the same seed each way round would replay one game mirrored). Matches run in ``--jobs``
worker processes (default: every core) or, with ``--scheduler``, on an existing ``dask.distributed``
cluster (its workers need this workspace on their PYTHONPATH: ``source devel/setup.bash``).
Provides, in ``--out`` (default ``evaluations/<time>/``): ``results.json`` (the options, every finished
match with its goals explained, failures, the summary with 95 % confidence intervals and the yardsticks of
an MSL match, the verdict, the throughput; rewritten after each match, so an interrupted evaluation keeps
what finished), ``table.md`` and ``goal_difference.png``; a progress bar with an ETA on stderr, the table
and the verdict on stdout.
Ctrl-C stops the workers and keeps the finished matches; ``--resume`` with the same ``--out`` and options
plays only the matches its results.json lacks (the interrupted or failed ones, or more of them with a larger
``--matches``) and reports them all together. Exit status: 0, 1 if a match failed or the
evaluation was interrupted, 2 for bad options (a clear message, no traceback).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import signal
import socket
import sys
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass
from datetime import datetime
from pathlib import Path

from nubot_common.json_text import strict_json
from nubot_common.naming import team_of
from nubot_match import NubotMatchError
from nubot_match.config import TEAMS, MatchConfig, match_config
from nubot_match.engine import LockstepMatch
from nubot_match.learn.compare import main as compare_policy
from nubot_match.match_analysis import FOUL_KINDS, MatchSummary, analyse
from nubot_match.match_shots import ShotReport, explain
from nubot_match.record import MatchLogRecorder
from nubot_match.statistics import MatchResult, plot_goal_difference, summarise, table_text, verdict

MAX_MATCHES = 100_000


@dataclass(frozen=True)
class MatchJob:
    """One match to play: everything a worker needs (plain values, so it travels to any process)."""

    index: int
    seed: int  # the match's own
    swapped: bool  # AWAY kicks off and each team starts at the other end
    home: str
    away: str
    field: str
    tracker: str
    half_seconds: float
    halves: int


def jobs_for(home: str, away: str, matches: int, half_seconds: float, halves: int = 2, field: str = "18x12",
             tracker: str = "", seed: int = 0) -> list[MatchJob]:
    if matches < 1 or matches > MAX_MATCHES:
        raise NubotMatchError(f"the number of matches must lie in 1..{MAX_MATCHES}, got {matches}")
    if seed < 0:
        raise NubotMatchError(f"seed must not be negative, got {seed}")
    return [MatchJob(i, seed + i, i % 2 == 1, home, away, field, tracker, half_seconds, halves)
            for i in range(matches)]


def job_config(job: MatchJob) -> MatchConfig:
    config = match_config(job.home, job.away, job.field, job.tracker, job.half_seconds, job.halves)
    return config.swapped() if job.swapped else config


def team_figures(summary: MatchSummary, shots: ShotReport, team: str) -> dict[str, float]:
    """HOME's or AWAY's figures of one match; collisions are those a robot of ``team`` took part in."""
    collisions = sum(1 for c in summary.collisions if any(team_of(r) == team for r in c.robots))
    passes = summary.pass_counts().get(team, {})
    counts = shots.shot_counts().get(team, {})
    return {"goals": float(summary.score.get(team, 0)),
            "shots": float(counts.get("shots", 0)), "shots_on_target": float(counts.get("on_target", 0)),
            "passes_tried": float(passes.get("tried", 0)), "passes_completed": float(passes.get("completed", 0)),
            "possession": float(summary.possession_share().get(team, 0.0)),
            "collisions": float(collisions),
            "fouls": float(sum(n for k, n in summary.foul_counts().get(team, {}).items() if k in FOUL_KINDS))}


def match_counts(summary: MatchSummary, shots: ShotReport) -> dict[str, float]:
    """The whole match's ``statistics.MATCH_COUNTS``, its goals by what led to them (goals_<cause>)."""
    passes = summary.pass_counts().values()
    counts = {"running_s": summary.running_time, "stopped_s": summary.stopped_time,
              "goals": float(sum(summary.score.values())), "shots": float(len(shots.shots)),
              "shots_scored": float(sum(s.outcome == "goal" for s in shots.shots)),
              "passes_tried": float(sum(c["tried"] for c in passes)),
              "passes_completed": float(sum(c["completed"] for c in passes)),
              "collisions": float(len(summary.collisions))}
    counts.update({f"goals_{cause}": float(n) for cause, n in shots.cause_counts().items()})
    for kind in (*FOUL_KINDS, "goal_disallowed", "slow_restart"):
        counts[f"fouls_{kind}"] = float(sum(c.kind == kind for c in summary.calls))
    return {k: round(v, 3) for k, v in counts.items()}


def play_match(job: MatchJob) -> MatchResult:
    """Play one match to full time and measure it (runs in a worker process)."""
    config = job_config(job)
    home_team, away_team = (config.teams[1], config.teams[0]) if job.swapped else config.teams
    recorder = MatchLogRecorder()
    match = LockstepMatch(config, [recorder])
    match.reset(job.seed)
    start = time.perf_counter()
    match.run()
    wall = time.perf_counter() - start
    log = recorder.finish()
    summary = analyse(log, config.world, (config.teams[0].config.prefix, config.teams[0].config.attack))
    shots = explain(summary, log)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    return MatchResult(job.index, job.seed, home_team.config.attack,
                       team_figures(summary, shots, home_team.config.prefix),
                       team_figures(summary, shots, away_team.config.prefix), round(match.time, 3), round(wall, 3),
                       round(rss, 1), len(summary.referee_events), job.index // 2, match_counts(summary, shots),
                       shots.to_json()["goals"], match.sim.world.solver_errors if match.sim is not None else 0)


def _quiet_worker() -> None:
    # Ctrl-C is the parent's to handle: it stops the workers. The worker was forked with SIGINT blocked (see
    # LocalRunner), so a Ctrl-C that reached it before this line is still pending and is dropped here.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


def _play_or_fail(job: MatchJob) -> tuple[MatchJob, MatchResult | None, str]:
    try:
        return job, play_match(job), ""
    except Exception as exc:  # noqa: BLE001 - one failed match is reported and the others go on
        return job, None, f"{type(exc).__name__}: {exc}"


class LocalRunner:
    """Matches in worker processes on this machine."""

    def __init__(self, jobs: int):
        import multiprocessing

        # fork: a spawned worker would import the two-line script as its main module and run it again.
        # The pool forks a new worker after every match from its own threads; they are made here with SIGINT
        # blocked, so that a Ctrl-C arriving while a worker is being forked waits in the new worker until it
        # ignores SIGINT, instead of interrupting Python's after-fork hooks there (a traceback on stderr).
        previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            self.pool = multiprocessing.get_context("fork").Pool(jobs, initializer=_quiet_worker,
                                                                 maxtasksperchild=1)
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, previous)
        self.where = f"{jobs} worker process{'es' if jobs > 1 else ''} on this machine"

    def results(self, jobs: Sequence[MatchJob]) -> Iterator[tuple[MatchJob, MatchResult | None, str]]:
        yield from self.pool.imap_unordered(_play_or_fail, jobs)

    def stop(self) -> None:
        self.pool.terminate()
        self.pool.join()

    def close(self) -> None:
        self.pool.close()
        self.pool.join()


def _check_reachable(scheduler: str) -> None:
    """Refuse at once a TCP scheduler nobody listens at (dask's client would retry for its whole timeout)."""
    from urllib.parse import urlsplit

    if not scheduler.startswith("tcp://"):
        return  # another transport: the client says
    parts = urlsplit(scheduler)
    try:
        port = parts.port
    except ValueError:
        port = None
    if parts.hostname is None or port is None:
        raise NubotMatchError(f"cannot reach the dask scheduler {scheduler}: give it as tcp://host:port")
    try:
        socket.create_connection((parts.hostname, port), timeout=5).close()
    except OSError as exc:
        raise NubotMatchError(f"cannot reach the dask scheduler {scheduler}: {exc}") from None


class DaskRunner:
    """Matches on an existing dask.distributed cluster."""

    def __init__(self, scheduler: str):
        from distributed import Client

        _check_reachable(scheduler)
        try:
            self.client = Client(scheduler, timeout=10)
        except (OSError, TimeoutError) as exc:
            raise NubotMatchError(f"cannot reach the dask scheduler {scheduler}: {exc}") from None
        workers = len(self.client.scheduler_info().get("workers", {}))
        self.where = f"the dask cluster at {scheduler} ({workers} workers)"
        self.futures: list = []

    def results(self, jobs: Sequence[MatchJob]) -> Iterator[tuple[MatchJob, MatchResult | None, str]]:
        from distributed import as_completed

        self.futures = self.client.map(_play_or_fail, list(jobs), pure=False)
        for future in as_completed(self.futures):
            yield future.result()

    def stop(self) -> None:
        self.client.cancel(self.futures)
        self.client.close()

    def close(self) -> None:
        self.client.close()


def _atomic_write(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


RESUME_KEYS = ("home", "away", "half_seconds", "halves", "field", "tracker", "seed")  # what makes the matches


def _same_team(a: str, b: str) -> bool:
    return Path(a).resolve() == Path(b).resolve()


def finished_matches(out: Path, options: dict) -> list[MatchResult]:
    """The matches an earlier evaluation into ``out`` finished, when it played the matches ``options`` ask
    for (same teams, halves, field, tracker and first seed); else a NubotMatchError that says what differs."""
    path = out / "results.json"
    try:
        data = json.loads(path.read_text())
        before, matches = data["options"], data["matches"]
    except FileNotFoundError:
        raise NubotMatchError(f"--resume: no earlier evaluation in {out} (no results.json)") from None
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise NubotMatchError(f"--resume: cannot read {path}: {exc}") from None
    for key in RESUME_KEYS:
        old, new = before.get(key), options[key]
        same = _same_team(old, new) if key in ("home", "away") and isinstance(old, str) else old == new
        if not same:
            raise NubotMatchError(f"--resume: {path} was played with {key} {old!r}, not {new!r}")
    try:
        results = [MatchResult(**m) for m in matches]
    except TypeError as exc:
        raise NubotMatchError(f"--resume: cannot read the matches of {path}: {exc}") from None
    return [r for r in results if r.index < options["matches"]]


class Evaluation:
    """The results so far, written after every match."""

    def __init__(self, out: Path, options: dict, home: str, away: str, earlier: Sequence[MatchResult] = ()):
        self.out, self.options, self.home, self.away = out, options, home, away
        self.results: list[MatchResult] = list(earlier)
        self.resumed = len(self.results)  # of an earlier run: not in this run's throughput
        self.failures: list[dict] = []
        self.start = time.monotonic()
        self.interrupted = False

    def add(self, job: MatchJob, result: MatchResult | None, error: str) -> None:
        if result is None:
            self.failures.append({"job": asdict(job), "error": error})
        else:
            self.results.append(result)
        self.save()

    def save(self) -> None:
        results = sorted(self.results, key=lambda r: r.index)
        summary = summarise(results, self.home, self.away)
        wall = time.monotonic() - self.start
        sim = sum(r.sim_seconds for r in self.results[self.resumed:])
        data = {"options": self.options, "home": self.home, "away": self.away, "interrupted": self.interrupted,
                "finished": len(results), "resumed": self.resumed, "failures": self.failures,
                "verdict": verdict(summary),
                "summary": summary.to_json(),
                "throughput": {"wall_seconds": round(wall, 1), "sim_seconds": round(sim, 1),
                               "sim_seconds_per_wall_second": round(sim / wall, 2) if wall > 0 else None,
                               "rss_mib_max": max((r.rss_mib for r in results), default=None)},
                "solver_errors": sum(r.solver_errors for r in results),  # the physics' "LCP internal error"s
                "matches": [r.to_json() for r in results]}
        _atomic_write(self.out / "results.json", strict_json(data))  # an unknown interval (one match) is null

    def finish(self) -> str:
        results = sorted(self.results, key=lambda r: r.index)
        summary = summarise(results, self.home, self.away)
        self.save()
        _atomic_write(self.out / "table.md", table_text(summary) + "\n" + verdict(summary) + "\n")
        if results:
            plot_goal_difference(results, summary, self.out / "goal_difference.png")
        return table_text(summary) + "\n" + verdict(summary)


def _name(path: str) -> str:
    return Path(path).stem.upper() if Path(path).stem else path


def main(argv: list[str] | None = None) -> int:
    args_given = sys.argv[1:] if argv is None else argv
    if "--policy" in args_given:  # a trained policy file against the scripted striker on its task
        return compare_policy(args_given)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--home", default=str(TEAMS / "nubot.yaml"), help="HOME team YAML")
    parser.add_argument("--away", default=str(TEAMS / "rival.yaml"), help="AWAY team YAML")
    parser.add_argument("--matches", type=int, default=40)
    parser.add_argument("--half-seconds", type=float, default=300.0, help="length of a half [s of game time]")
    parser.add_argument("--halves", type=int, default=2)
    parser.add_argument("--field", default="18x12", help="18x12, 22x14 or a world description YAML")
    parser.add_argument("--tracker", default="", choices=("", "mpc", "baseline"),
                        help="every robot's motion tracker (default: as configured)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the first match")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="worker processes on this machine")
    parser.add_argument("--scheduler", default="", help="a dask.distributed scheduler, e.g. tcp://host:8786")
    parser.add_argument("--out", type=Path, help="folder of the results (default evaluations/<time>)")
    parser.add_argument("--resume", action="store_true",
                        help="keep the matches an earlier evaluation into --out finished; play the others")
    args = parser.parse_args(argv)
    options = {k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items()}
    earlier: list[MatchResult] = []
    try:
        if args.jobs < 1:
            raise NubotMatchError(f"--jobs must be at least 1, got {args.jobs}")
        jobs = jobs_for(args.home, args.away, args.matches, args.half_seconds, args.halves, args.field,
                        args.tracker, args.seed)
        config = job_config(jobs[0])  # refuse bad teams, strategies and options before any worker starts
        if args.resume:
            if args.out is None:
                raise NubotMatchError("--resume needs the --out of the evaluation to resume")
            earlier = finished_matches(args.out, options)
    except NubotMatchError as exc:
        print(f"evaluate: {exc}", file=sys.stderr)
        return 2
    home, away = _name(args.home), _name(args.away)
    if home == away:
        home, away = f"{home} (home)", f"{away} (away)"
    out = args.out or Path("evaluations") / datetime.now().strftime("%Y%m%d-%H%M%S")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        print(f"evaluate: cannot create {out}: {exc.strerror}", file=sys.stderr)
        return 2
    evaluation = Evaluation(out, options, home, away, earlier)
    done = {r.index for r in earlier}
    total, jobs = len(jobs), [j for j in jobs if j.index not in done]
    try:
        runner: LocalRunner | DaskRunner = DaskRunner(args.scheduler) if args.scheduler else \
            LocalRunner(max(1, min(args.jobs, len(jobs))))
    except NubotMatchError as exc:
        print(f"evaluate: {exc}", file=sys.stderr)
        return 2
    print(f"evaluate: {home} vs {away}, {total} matches of {args.halves} x {args.half_seconds:g} s on the "
          f"{config.world.name} field, seeds {args.seed}..{args.seed + total - 1}, sides swapped every other match, "
          f"on {runner.where}; results in {out}"
          + (f"; {len(earlier)} finished before, {len(jobs)} to play" if args.resume else ""), flush=True)
    from tqdm import tqdm

    tqdm.monitor_interval = 0  # no monitor thread in a process that forks workers
    bar = tqdm(total=len(jobs), unit="match", file=sys.stderr, dynamic_ncols=True)
    ctrl_c = CtrlC()
    previous = signal.getsignal(signal.SIGINT)
    if previous is not signal.SIG_IGN:  # a background job ignores Ctrl-C, and so do we then
        signal.signal(signal.SIGINT, ctrl_c)
    try:
        for job, result, error in runner.results(jobs):
            with ctrl_c.held():
                evaluation.add(job, result, error)
                if result is None:
                    bar.write(f"  match {job.index + 1} (seed {job.seed}) failed: {error}")
                else:
                    bar.write(f"  match {job.index + 1:>3} seed {job.seed}{' swapped' if job.swapped else ''}: "
                              f"{home} {result.home['goals']:.0f} - {result.away['goals']:.0f} {away} "
                              f"({result.sim_seconds:.0f} s simulated in {result.wall_seconds:.0f} s)")
                bar.update(1)
        runner.close()
    except KeyboardInterrupt:
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # stopping already: a second Ctrl-C changes nothing
        evaluation.interrupted = True
        bar.write(f"evaluate: interrupted; stopping the workers and keeping the {len(evaluation.results)} "
                  "finished matches")
        runner.stop()
    finally:
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # the last lines and files are written whole
        bar.close()
    print(evaluation.finish(), flush=True)
    print(f"evaluate: {len(evaluation.results)} of {total} matches finished; results in {out}", flush=True)
    if previous is not None:  # None: a handler not set from Python
        signal.signal(signal.SIGINT, previous)
    return 1 if evaluation.failures or evaluation.interrupted else 0


class CtrlC:
    """SIGINT's handler while matches are evaluated: Ctrl-C raises KeyboardInterrupt, except inside ``held()``, whose
    end it then waits for. Raised inside tqdm's write it left tqdm's lock half taken, and the next write (the
    "interrupted" line) failed with a traceback; inside the recording of a result it could lose that result."""

    def __init__(self) -> None:
        self._held = False
        self._pending = False

    def __call__(self, _signum: int, _frame: object) -> None:
        if self._held:
            self._pending = True
        else:
            raise KeyboardInterrupt

    @contextmanager
    def held(self) -> Iterator[None]:
        self._held = True
        try:
            yield
        finally:
            self._held = False
        if self._pending:
            self._pending = False
            raise KeyboardInterrupt

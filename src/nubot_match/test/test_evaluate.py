"""Many-match evaluation: the command line on this machine's cores, Ctrl-C, a dask cluster, bad input, statistics."""

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

from nubot_common.processes import wait_until
from nubot_match.evaluate import jobs_for
from nubot_match.statistics import (
    MatchResult,
    mean_interval,
    rate_interval,
    share_interval,
    summarise,
    table_text,
    verdict,
)

WORKSPACE = Path(__file__).resolve().parents[3]
SCRIPT = WORKSPACE / "scripts" / "evaluate.py"


def teams(tmp_path, robots=2):
    poses = [{"x": -8.4, "y": 0.0}, {"x": -1.0, "y": 0.5}][:robots]
    paths = []
    for prefix, attack in (("nubot", 1), ("rival", -1)):
        path = tmp_path / f"{prefix}.yaml"
        path.write_text(yaml.safe_dump({"name": prefix, "prefix": prefix, "attack": attack, "goalie": 1,
                                        "robots": poses}))
        paths.append(str(path))
    return paths


def evaluate(*args, timeout=300):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True,
                          timeout=timeout)


def result(index, home_goals, away_goals, pair=-1, match=None):
    figures = dict.fromkeys(("passes_completed", "possession", "shots", "collisions"), 0.0)
    return MatchResult(index, index, 1, {**figures, "goals": home_goals}, {**figures, "goals": away_goals}, 1, 1, 1,
                       pair=pair, match=match or {})


def test_the_statistics_give_intervals_and_a_verdict_that_says_who_is_better():
    results = [result(i, g, a) for i, (g, a) in enumerate([(2, 0), (1, 0), (3, 1), (1, 1), (2, 0), (2, 1)])]
    s = summarise(results, "A", "B")
    d = s.goal_difference
    assert d.mean == pytest.approx(8 / 6) and d.low > 0 and d.high > d.mean
    assert verdict(s).startswith("A better than B by +1.3 goals per match, 95 % CI [")
    assert s.outcomes["wins"][0] == 5 and s.outcomes["draws"][0] == 1
    flipped = summarise([result(i, a, g) for i, (g, a) in enumerate([(2, 0), (1, 0), (3, 1)])], "A", "B")
    assert verdict(flipped).startswith("B better than A")
    even = summarise([result(0, 1, 0), result(1, 0, 1)], "A", "B")
    assert verdict(even).startswith("no clear difference between A and B")
    one = mean_interval([2.0])
    assert one.mean == 2.0 and math.isnan(one.low)
    share = share_interval(0, 10)
    assert share.mean == 0.0 and share.low == 0.0 and 0.2 < share.high < 0.35  # Wilson, not 0 +- 0


def test_the_two_matches_of_a_pair_are_one_unit_of_the_goal_difference():
    """Pairs each way round that give +d and -d: two pairs are two units of the goal difference, not four."""
    pairs = [result(0, 3, 0, 0), result(1, 0, 3, 0), result(2, 1, 0, 1), result(3, 0, 1, 1)]
    d = summarise(pairs).goal_difference
    assert (d.mean, d.low, d.high) == (0.0, 0.0, 0.0)  # each pair averages to 0 exactly
    alone = summarise([result(i, g, a) for i, (g, a) in enumerate([(3, 0), (0, 3), (1, 0), (0, 1)])])
    assert alone.goal_difference.high > 1.0  # as four independent matches the interval is wide


def test_every_match_has_a_seed_of_its_own_and_pairs_swap_the_sides():
    jobs = jobs_for("a.yaml", "b.yaml", 5, 60.0, seed=7)
    assert [(j.seed, j.swapped) for j in jobs] == [(7, False), (8, True), (9, False), (10, True), (11, False)]


def test_the_yardsticks_scale_to_two_halves_of_15_min_and_say_whether_they_are_met():
    # two matches of 2 x 5 min of play and 200 s of stoppages: 4 and 2 goals in 800 s on the match clock are 9 and
    # 4.5 per 2 x 15 min; 2 collisions a running minute
    counts = [{"running_s": 600.0, "stopped_s": 200.0, "goals": g, "shots": 20.0, "shots_scored": g,
               "passes_tried": 10.0, "passes_completed": 8.0, "collisions": 20.0, "fouls_pushing": 1.0,
               "goals_turnover": g} for g in (4.0, 2.0)]
    s = summarise([result(0, 2, 2, match=counts[0]), result(1, 1, 1, match=counts[1])])
    assert s.yardsticks["goals"].mean == pytest.approx(6.75)
    assert s.yardsticks["shots_per_team_half"].mean == pytest.approx(11.25)
    assert s.yardsticks["scoring_share"].mean == pytest.approx(0.15)
    assert s.yardsticks["collisions_per_minute"].mean == pytest.approx(2.0)
    assert s.yardsticks["pass_completion"].mean == pytest.approx(0.8)
    assert s.yardsticks["running_share"].mean == pytest.approx(0.75)
    assert s.fouls["pushing"].mean == pytest.approx(2.25) and s.causes["turnover"].mean == pytest.approx(6.75)
    table = table_text(s)
    assert "| goals per match (2 x 15 min match clock) | 6.75 [" in table and "| 3 to 10 | yes |" in table
    assert "| robot-robot collisions per running minute | 2.00 (CI unknown" not in table  # equal: a zero-width CI
    assert "| fouls: pushing | 2.25 " in table and "| goals from: turnover | 6.75 [" in table
    crowded = summarise([result(0, 9, 9, match={**counts[0], "collisions": 600.0})])
    assert "| robot-robot collisions per running minute | 60.00 (CI unknown: one unit) | at most 5 | NO |" in \
        table_text(crowded)


def test_an_evaluation_on_two_cores_prints_its_table_and_verdict_and_keeps_its_files(tmp_path):
    home, away = teams(tmp_path)
    out = tmp_path / "eval"
    done = evaluate("--home", home, "--away", away, "--matches", 2, "--half-seconds", 3, "--halves", 1,
                    "--jobs", 2, "--out", out)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "| goals |" in done.stdout and "95 % CI" in done.stdout
    assert "NUBOT - RIVAL: " in done.stdout and "play at least 4 matches (two pairs) for a verdict" in done.stdout
    assert "match/s" in done.stderr or "s/match" in done.stderr  # the progress bar with its rate and ETA
    data = json.loads((out / "results.json").read_text())
    assert data["finished"] == 2 and not data["interrupted"] and data["failures"] == []
    assert sorted(m["seed"] for m in data["matches"]) == [0, 1] and {m["pair"] for m in data["matches"]} == {0}
    assert {m["home_attacks"] for m in data["matches"]} == {1, -1}  # the sides were swapped once
    assert data["throughput"]["sim_seconds_per_wall_second"] > 0
    assert (out / "table.md").read_text().count("|") > 20 and (out / "goal_difference.png").stat().st_size > 1000


def _not_json(constant: str) -> None:
    raise AssertionError(f"{constant} in a JSON file: not JSON, other readers refuse it")


def test_ctrl_c_stops_the_workers_and_keeps_the_finished_matches(tmp_path):
    home, away = teams(tmp_path)
    out = tmp_path / "eval"
    process = subprocess.Popen([sys.executable, str(SCRIPT), "--home", home, "--away", away, "--matches", "20",
                                "--half-seconds", "2", "--halves", "1", "--jobs", "1", "--out", str(out)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
                               # as in a terminal, even when the tests run as a background job (which ignores
                               # SIGINT, and its children would inherit that)
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        wait_until(lambda: (out / "results.json").exists() and
                   json.loads((out / "results.json").read_text())["finished"] >= 1, 240, "a finished match")
        os.killpg(process.pid, signal.SIGINT)  # what Ctrl-C does: the whole foreground group gets SIGINT
        stdout, stderr = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
    assert process.returncode == 1, stderr[-2000:]
    assert "Traceback" not in stderr
    assert "interrupted; stopping the workers" in stdout and "| goals |" in stdout
    data = json.loads((out / "results.json").read_text(), parse_constant=_not_json)  # strict: no bare NaN
    assert data["interrupted"] and 1 <= data["finished"] < 20
    if data["finished"] == 1:  # one unit: its interval is unknown, written as null
        assert data["summary"]["goal_difference"]["low"] is None
    time.sleep(0.5)
    leftovers = subprocess.run(["pgrep", "-g", str(process.pid)], capture_output=True, text=True).stdout.split()
    assert not leftovers, f"workers left running: {leftovers}"


def test_resume_plays_only_the_matches_the_earlier_run_lacks_and_refuses_other_options(tmp_path):
    home, away = teams(tmp_path)
    out = tmp_path / "eval"
    common = ("--home", home, "--away", away, "--half-seconds", 3, "--halves", 1, "--jobs", 1, "--out", out)
    first = evaluate("--matches", 1, *common)
    assert first.returncode == 0, first.stderr[-2000:]
    before = json.loads((out / "results.json").read_text())["matches"]
    done = evaluate("--matches", 2, "--resume", *common)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "1 finished before, 1 to play" in done.stdout and "2 of 2 matches finished" in done.stdout
    data = json.loads((out / "results.json").read_text())
    assert data["finished"] == 2 and data["resumed"] == 1
    assert [m["seed"] for m in data["matches"]] == [0, 1] and data["matches"][0] == before[0], \
        "the earlier match is kept as it was, the new one has the next seed"
    assert {m["pair"] for m in data["matches"]} == {0}, "with it, the new match makes a pair"
    other = evaluate("--matches", 2, "--resume", *common[:-6], "--halves", 2, *common[-4:])
    assert other.returncode == 2 and "was played with halves 1, not 2" in other.stderr, other.stderr[-2000:]
    nothing = evaluate("--matches", 2, "--resume", *common[:-1], tmp_path / "elsewhere")
    assert nothing.returncode == 2 and "no earlier evaluation in" in nothing.stderr
    assert "Traceback" not in other.stderr + nothing.stderr


@pytest.mark.integration
def test_the_same_evaluation_runs_on_a_local_two_worker_dask_cluster(tmp_path):
    from distributed import LocalCluster

    home, away = teams(tmp_path)
    out = tmp_path / "eval"
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster:
        assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
        done = evaluate("--home", home, "--away", away, "--matches", 2, "--half-seconds", 3, "--halves", 1,
                        "--scheduler", cluster.scheduler_address, "--out", out)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "dask cluster" in done.stdout and "2 workers" in done.stdout
    data = json.loads((out / "results.json").read_text())
    assert data["finished"] == 2


@pytest.mark.parametrize("args, message", [
    (["--matches", "-1"], "number of matches must lie in 1..100000, got -1"),
    (["--jobs", "0"], "--jobs must be at least 1"),
    (["--half-seconds", "0"], "half length"),
    (["--home", "absent.yaml"], "cannot read absent.yaml"),
    (["--scheduler", "tcp://127.0.0.1:9"], "cannot reach the dask scheduler"),
    (["--scheduler", "tcp://127.0.0.1"], "give it as tcp://host:port"),
])
def test_bad_options_get_a_clear_error_and_no_traceback(tmp_path, args, message):
    done = evaluate(*args, "--out", tmp_path / "eval", timeout=120)
    assert done.returncode == 2, done.stdout + done.stderr
    assert message in done.stderr and "Traceback" not in done.stderr


def test_a_team_naming_a_missing_strategy_module_is_refused_before_any_match(tmp_path):
    home, away = teams(tmp_path)
    data = yaml.safe_load(Path(home).read_text())
    Path(home).write_text(yaml.safe_dump({**data, "strategy": "my_missing_strategy:Clever"}))
    done = evaluate("--home", home, "--away", away, "--matches", 2, "--out", tmp_path / "eval")
    assert done.returncode == 2
    assert "cannot import module 'my_missing_strategy'" in done.stderr and "Traceback" not in done.stderr


def test_ctrl_c_inside_a_held_block_waits_for_its_end():
    from nubot_match.evaluate import CtrlC

    ctrl_c = CtrlC()
    previous = signal.signal(signal.SIGINT, ctrl_c)
    done = []
    try:
        with pytest.raises(KeyboardInterrupt):
            with ctrl_c.held():
                signal.raise_signal(signal.SIGINT)  # as if in the middle of writing a line
                done.append("the line")
        assert done == ["the line"], "the block ran to its end first"
        with pytest.raises(KeyboardInterrupt):
            signal.raise_signal(signal.SIGINT)  # outside: at once
        with ctrl_c.held():
            done.append("a later line")  # nothing left pending
    finally:
        signal.signal(signal.SIGINT, previous)
    assert done == ["the line", "a later line"]


def test_a_rate_has_the_exact_poisson_interval_even_when_nothing_happened():
    none = rate_interval(0, 12.0)  # no goal in 12 running minutes
    assert none.mean == 0.0 and none.low == 0.0 and none.high == pytest.approx(3.689 / 12.0, abs=1e-3)
    four = rate_interval(4, 12.0)
    assert four.mean == pytest.approx(1 / 3) and four.low == pytest.approx(1.090 / 12.0, abs=1e-3)
    assert four.high == pytest.approx(10.242 / 12.0, abs=1e-3)
    assert four.low < none.high  # four goals and none in equal time: not told apart by counting alone
    many = rate_interval(400, 1200.0)
    assert many.high - many.low < four.high - four.low  # more time, a narrower interval
    for bad in ((-1, 1.0), (3, 0.0), (3, math.nan)):
        with pytest.raises(ValueError, match="exposure"):
            rate_interval(*bad)

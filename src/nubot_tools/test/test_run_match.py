"""End to end: a short refereed 2 vs 2 match over ROS on the 22 x 14 field, watched and coached in a headless
browser while it plays, recorded, reported from its bag, and replayed in the browser from that bag."""

import contextlib
import json
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from nubot_match.bag_reader import read_match
from nubot_tools.browser import Page

pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[3]
ARTIFACTS = ROOT / "test-artifacts"  # screenshots of the pages (kept out of git)


class Output:
    """A child's stdout, read line by line in the background."""

    def __init__(self, process: subprocess.Popen):
        self.lines: list[str] = []
        self.thread = threading.Thread(target=lambda: self.lines.extend(process.stdout), daemon=True)
        self.thread.start()

    def find(self, pattern: str, timeout: float, process: subprocess.Popen) -> re.Match:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for line in list(self.lines):
                if (m := re.search(pattern, line)) is not None:
                    return m
            if process.poll() is not None:
                break
            time.sleep(0.1)
        raise AssertionError(f"no line matching {pattern!r}:\n{''.join(self.lines)[-3000:]}")

    @property
    def text(self) -> str:
        return "".join(self.lines)


def stop_group(process: subprocess.Popen) -> None:
    """End a child and everything it started: Ctrl-C first (the runner closes its bag and master), then kill."""
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGINT)
        try:
            process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            pass
    with contextlib.suppress(ProcessLookupError):
        os.killpg(process.pid, signal.SIGKILL)
    process.wait(timeout=10)


def watch_and_coach(url: str) -> str:
    """The live page of the running match: robots and ball drawn and moving, the score shown, a click on a coach
    button reaching the referee; returns the referee's decision the click caused."""
    with Page(url) as page:
        page.wait_for(lambda: (page.frame() or {}).get("ball"), 30, "a frame with the ball")
        frame = page.frame()
        assert {r["name"] for r in frame["robots"]} == {"nubot1", "nubot2", "rival1", "rival2"}
        page.wait_for(lambda: page.frame()["referee"]["running"], 60, "the kickoff's STARTROBOT")
        page.wait_for(lambda: page.stats()["moved"] > 20, 20, "robots moving on the page")
        assert re.fullmatch(r"nubot ?\d+ : rival ?\d+", page.text("score")), page.text("score")
        page.select("watch", "nubot2")  # what nubot2 believes, over the truth
        page.wait_for(lambda: (page.frame() or {}).get("belief"), 10, "nubot2's world model")
        assert page.frame()["belief"]["ball"] is not None, "nubot2 knows where the ball is"
        assert page.run("return document.getElementById('team').value") == "nubot", "the referee's first team"
        page.click("button[data-command='DROPBALL']")
        result = page.wait_for(lambda: page.stats()["results"], 10, "the referee's answer")[0]
        assert result["ok"] and result["command"] == "DROPBALL", result
        page.wait_for(lambda: "DROPBALL for nubot" in page.text("events"), 10, "the decision on the page")
        time.sleep(1.0)
        stats = page.stats()
        assert stats["fps"] >= 15, f"the page drew {stats['fps']} frames in the last second"
        page.screenshot(ARTIFACTS / "viewer_live.png")
    return "DROPBALL for nubot"


def replay_and_slide(bag: Path, kickoff: float, tracks: dict) -> None:
    """The replay page over the match's bag: the slider takes the robots where the bag's ``tracks`` have them,
    at the kickoff (``kickoff``, sim time: every robot is on the field by then) and 15 s into play."""

    def where_the_bag_has_them(frame: dict) -> None:
        assert len(frame["robots"]) == 4, f"the robots at {frame['t']:.2f} s: {frame['robots']}"
        for r in frame["robots"]:
            track = tracks[r["name"]]
            x, y = (np.interp(frame["t"], track.t, track.xy[:, k]) for k in (0, 1))
            assert np.hypot(r["x"] - x, r["y"] - y) < 0.1, f"{r['name']} at {frame['t']:.2f} s: page {r}, bag {x, y}"

    process = subprocess.Popen([sys.executable, str(ROOT / "scripts" / "replay.py"), str(bag), "--port", "0",
                                "--paused"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               start_new_session=True)
    output = Output(process)
    try:
        url = output.find(r"open (http://127\.0\.0\.1:\d+/)", 60, process)[1]
        with Page(url) as page:
            page.wait_for(lambda: page.frame(), 20, "the first replayed frame")
            start = page.frame()
            assert start["replay"]["playing"] is False and "DROPBALL for nubot" in page.text("marks")
            # (the robots spawn after the recorder started: the bag's first frames may hold none of them)
            page.slide("slider", kickoff)
            page.wait_for(lambda: abs(page.frame()["t"] - kickoff) < 0.2, 10, "the slider at the kickoff")
            placed = page.frame()
            page.slide("slider", kickoff + 15.0)
            page.wait_for(lambda: abs(page.frame()["t"] - (kickoff + 15.0)) < 0.2, 10, "the slider's time")
            moved = page.frame()
            where_the_bag_has_them(placed)
            where_the_bag_has_them(moved)
            before = {r["name"]: (r["x"], r["y"]) for r in placed["robots"]}
            shifts = [np.hypot(r["x"] - before[r["name"]][0], r["y"] - before[r["name"]][1]) for r in moved["robots"]]
            assert max(shifts) > 0.2, f"the robots stayed where they were: {shifts}"  # two different frames
            page.click("#play")
            page.wait_for(lambda: page.frame()["t"] > moved["t"] + 1.0, 10, "the replay playing on")
            page.screenshot(ARTIFACTS / "viewer_replay.png")
    finally:
        stop_group(process)


def test_short_two_vs_two_match_on_the_22_by_14_field_is_watched_recorded_reported_and_replayed(tmp_path, two_vs_two):
    """``--field 22x14`` reaches every node: the simulator, the robots (the goalie's kickoff spot is on the
    22 x 14 goal line), the referee, the live page, and the report, which reads the field from the bag."""
    scratch = tmp_path / "tmp"  # the match's temporary files, which it must remove
    scratch.mkdir()
    process = subprocess.Popen([sys.executable, str(ROOT / "scripts" / "run_match.py"), "--half-seconds", "20",
                                "--halves", "1", "--field", "22x14", "--out", str(tmp_path / "matches"),
                                "--viewer-port", "0", *two_vs_two],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True,
                               env=dict(os.environ, TMPDIR=str(scratch)))
    output = Output(process)
    try:
        url = output.find(r"watch it at (http://127\.0\.0\.1:\d+/)", 120, process)[1]
        decision = watch_and_coach(url)
        process.wait(timeout=400)
    finally:
        stop_group(process)
    output.thread.join(timeout=10)
    stdout = output.text
    assert process.returncode == 0, stdout[-3000:]
    assert "kickoff for nubot" in stdout, "the referee starts the match"
    assert "on the 22 x 14 m field" in stdout
    assert "end of the match" in stdout
    assert not list(scratch.iterdir()), "the match leaves no temporary files behind"
    folder = next((tmp_path / "matches").iterdir())
    assert (folder / "match.bag").stat().st_size > 100_000
    report = json.loads((folder / "report.json").read_text())
    assert set(report["distance_run_m"]) == {"nubot1", "nubot2", "rival1", "rival2"}
    assert max(report["distance_run_m"].values()) > 5.0, "field players ran"
    assert report["score_agrees"]
    # In 20 s a field player alone with its goalie may carry the ball (3 m at most) without a kick: robots reaching
    # and holding it is the ball played
    assert report["possession"]["nobody"]["share"] < 0.5, "robots reach and play the ball"
    for png in ("heatmap.png", "trajectories.png"):
        assert (folder / png).stat().st_size > 10_000
    assert (report["field"]["length_m"], report["field"]["width_m"], report["field"]["source"]) == (22.0, 14.0, "bag")
    log = read_match(folder / "match.bag")
    kickoff = next(r.t for r in log.referee if r.running)  # STARTROBOT of the first kickoff
    goalie = log.tracks["nubot1"]
    x, y = goalie.xy[np.searchsorted(goalie.t, kickoff)]
    assert (x, y) == pytest.approx((-10.6, 0.0), abs=0.3), "the goalie waited on the 22 x 14 goal line"
    assert any(decision in r.last_event for r in log.referee), "the page's command is in the bag"
    replay_and_slide(folder / "match.bag", kickoff, log.tracks)

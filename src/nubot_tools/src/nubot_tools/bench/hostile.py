"""The hostile-peer probe: what a peer on the network or a page in a browser can throw at the team link, the RefBox
link and the viewer, case by case, with what each answered.

    python scripts/bench_hostile.py [--out bench/results] [--per-case 1000]

Requires: root for the team link's network namespace (without it that surface says so). Nothing leaves loopback.
- Team link: ``nubot_comm.probe`` inside a namespace of its own: ``--per-case`` datagrams of each case (forged,
  badly signed, altered, replayed, oversized, garbage, absurd values, an hour ahead, an hour old; one session forged
  30 s ahead) against a signed and an unsigned team: drop counts per reason, whether the teammate was heard at the
  end, and the longest run of cycles a forged packet stood for it.
- RefBox link: the practice box sends ``--per-case`` messages of each bad kind (a 5000-digit number, JSON nested
  40000 deep, malformed JSON, a JSON list, an unknown command, oversized) to a ``RefboxLink``, then one good
  command: whether the link is still connected on its first connection and took the good command.
- Viewer: ``--per-case`` bad page messages of each kind over one WebSocket, then a good command; a WebSocket from
  another origin and a request for a rebound site name: errors answered, commands executed, refusals.
Provides: ``<out>/hostile.json``: every case with what was sent and what came of it, and the count of cases.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
from dataclasses import replace
from pathlib import Path
from typing import Any

import tornado.httpclient
import tornado.websocket

from coach4sim.refbox import RefboxClientParams
from coach4sim.refbox_link import RefboxLink, TeamPicture
from coach4sim.refbox_server import RefboxServer
from coach4sim.viewer_server import ViewerServer
from nubot_comm import netns
from nubot_comm.probe import CASES, FORGED_X, GENUINE_X, longest_run
from nubot_common.json_text import strict_json
from nubot_common.match_mode import MatchMode
from nubot_tools.workspace import BENCH_RESULTS

REFBOX_CASES = {
    "huge_number": b'{"command": "KICKOFF", "targetTeam": "", "robotID": ' + b"9" * 5000 + b"}\0",
    "deep_nesting": b"[" * 40000 + b"]" * 40000 + b"\0",
    "malformed": b'{"command": "KICKOFF", "targetTeam": \0',
    "not_an_object": b'["KICKOFF"]\0',
    "unknown_command": b'{"command": "DANCE", "targetTeam": ""}\0',
    "oversize": b"x" * 150_000 + b"\0",
}
PAGE_CASES = {
    "malformed": "{not json",
    "deep_nesting": "[" * 8000 + "]" * 8000,
    "huge_number": '{"type": "watch", "robot": ' + "9" * 5000 + "}",
    "nan": '{"type": "replay", "action": "seek", "t": NaN}',
    "unknown_type": '{"type": "dance"}',
    "bad_command": '{"type": "command", "command": "OUR_HATTRICK", "team": "nubot"}',
}


def probe_team_link(per_case: int) -> dict[str, Any]:
    why = netns.unavailable()
    if why is not None:
        return {"skipped": why}
    with netns.NetNamespace("probe") as ns:
        seconds = 3.0 + per_case * len(CASES) * 0.0025
        team = subprocess.Popen(ns.command(sys.executable, "-m", "nubot_comm.probe", "team", f"{seconds:.1f}"),
                                stdout=subprocess.PIPE, text=True)
        try:
            if team.stdout is None or team.stdout.readline().strip() != "up":
                raise RuntimeError("the probed team did not start")
            attacker = subprocess.run(ns.command(sys.executable, "-m", "nubot_comm.probe", "attack", str(per_case)),
                                      capture_output=True, text=True, timeout=seconds + 60, check=True)
            out = json.loads(team.communicate(timeout=seconds + 60)[0].strip().splitlines()[-1])
        finally:
            if team.poll() is None:
                team.kill()
    result: dict[str, Any] = {"cases": list(CASES), "per_case": per_case, "captured_to_replay": int(attacker.stdout)}
    for name, side in (("signed", out["nubot"]), ("unsigned", out["rival"])):
        result[name] = {"dropped": side["dropped"], "teammate_heard_at_the_end": side["heard"][-1] == [GENUINE_X],
                        "longest_forged_run_cycles": longest_run(side["heard"], FORGED_X),
                        "cycles": len(side["heard"])}
    return result


def probe_refbox(per_case: int) -> dict[str, Any]:
    params = replace(RefboxClientParams(), worldstate_rate=20.0, reconnect_initial=0.05, reconnect_max=0.2)
    results: dict[str, Any] = {}
    with RefboxServer(port=0) as box:
        params = replace(params, port=box.port)
        effects: list[Any] = []
        picture = TeamPicture(params)
        link = RefboxLink(params, lambda: picture.worldstate("STOPROBOT", 0.0), effects.append, lambda _l, _t: None,
                          lambda: None)
        thread = threading.Thread(target=link.run, daemon=True)
        thread.start()
        box.wait_for(lambda: box.open_connections() == 1, 10.0, "the link's connection")
        for case, data in REFBOX_CASES.items():
            before = dict(link.status())
            for _ in range(per_case):
                box.send_raw(data)
            box.send("START", params.team_address)
            taken = box.wait_for(lambda: any(e.mode is MatchMode.STARTROBOT for e in effects), 30.0, "START")
            status = link.status()
            results[case] = {"sent": per_case, "malformed_counted": status["malformed"] - before["malformed"],
                             "commands_taken": status["commands"] - before["commands"],
                             "still_connected": bool(status["connected"]) and status["connections"] == 1,
                             "thread_alive": thread.is_alive(), "good_command_after": bool(taken)}
            effects.clear()
        link.shutdown()
        thread.join(timeout=5.0)
    return results


class RecordingBackend:
    """A viewer's backend that draws nothing and records every command it is asked to carry out."""

    def __init__(self) -> None:
        self.commands: list[tuple[Any, str]] = []

    def hello(self) -> dict[str, Any]:
        return {"mode": "live", "field": {}, "teams": ["nubot", "rival"]}

    def frame(self, watch: str) -> str:
        return json.dumps({"type": "frame", "t": 0.0})

    def command(self, command: Any, team: str) -> tuple[bool, str]:
        self.commands.append((command, team))
        return True, "in force"

    def control(self, message: dict[str, Any]) -> None:
        pass


def probe_viewer(per_case: int) -> dict[str, Any]:
    backend = RecordingBackend()
    lines: list[str] = []
    server = ViewerServer(backend, port=0, log=lines.append)

    async def scenario() -> dict[str, Any]:
        urls: list[str] = []
        task = asyncio.create_task(server.run(ready=urls.append))
        while not urls:
            await asyncio.sleep(0.01)
        results: dict[str, Any] = {}
        ws = await tornado.websocket.websocket_connect(f"ws://127.0.0.1:{server.port}/ws")
        await ws.read_message()  # the hello
        for case, text in PAGE_CASES.items():
            errors = 0
            for _ in range(per_case):
                await ws.write_message(text)
                while True:
                    answer = json.loads(await ws.read_message())
                    if answer["type"] != "frame":
                        break
                errors += answer["type"] == "error"
            results[case] = {"sent": per_case, "errors_answered": errors}
        await asyncio.sleep(1.1)  # past the rate limit's second
        await ws.write_message(json.dumps({"type": "command", "command": "STOPROBOT", "team": "nubot"}))
        while json.loads(await ws.read_message())["type"] == "frame":
            pass
        ws.close()
        origin = tornado.httpclient.HTTPRequest(f"ws://127.0.0.1:{server.port}/ws",
                                                headers={"Origin": "http://evil.example"})
        try:
            await tornado.websocket.websocket_connect(origin)
            results["another_origin"] = {"refused": False}
        except tornado.httpclient.HTTPClientError as exc:
            results["another_origin"] = {"refused": exc.code == 403}
        results["rebound_name"] = {"status": await asyncio.to_thread(_get_status, server.port, "evil.test")}
        results["commands_executed"] = [(c.name, t) for c, t in backend.commands]  # only the last, good one
        server.stop()
        await task
        return results

    results = asyncio.run(scenario())
    results["log_lines"] = len(lines)
    return results


def _get_status(port: int, host: str) -> int:
    request = urllib.request.Request(f"http://127.0.0.1:{port}/", headers={"Host": f"{host}:{port}"})
    try:
        with urllib.request.urlopen(request, timeout=5) as answer:
            return int(answer.status)
    except urllib.error.HTTPError as exc:
        return int(exc.code)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--per-case", type=int, default=1000, help="messages or datagrams of each case")
    args = parser.parse_args(argv)
    if not 1 <= args.per_case <= 100_000:
        parser.error("--per-case must lie in 1..100000")
    started = time.monotonic()
    result: dict[str, Any] = {}
    for surface, probe in (("team_link", probe_team_link), ("refbox_link", probe_refbox), ("viewer", probe_viewer)):
        print(f"[bench] hostile peers: {surface}, {args.per_case} of each case ...", flush=True)
        result[surface] = probe(args.per_case)
    result["cases_tried"] = (len(CASES) * 2 + len(REFBOX_CASES) + len(PAGE_CASES) + 2)
    result["seconds"] = round(time.monotonic() - started, 1)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "hostile.json").write_text(strict_json(result))
    print(json.dumps({k: v for k, v in result.items() if k != "viewer"}, indent=1)[:3000])
    print(f"figures: {args.out / 'hostile.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Replay a recorded match in the browser: the live viewer's page over a bag, with play, pause, speed, a time slider
and a jump to each goal and referee decision.

  scripts/replay.py BAG [--port 8080] [--host 127.0.0.1] [--rate 20] [--speed 1]   (or: make replay BAG=...)

Requires: a ROS 1 bag of a ROS match (``make match``) or of a lockstep match (``nubot_match``), read with rosbags
(no ROS master): ``/sim_visual/model_states`` at least; ``/referee/state``, ``/sim_visual/goal``,
``/sim_visual/world_description``, ``/<team>/simulation_interface/teammates``, ``/<robot>/nubotcontrol/strategy``
and ``/<robot>/nubotcontrol/path`` when the bag has them.
Provides: ``load_timeline`` (the match drawn ``rate`` times per second of sim time, with its marks),
``ReplayClock`` (play, pause, seek, speed) and ``ReplayBackend`` for ``coach4sim.viewer_server.ViewerServer``;
``main`` prints the address and serves until Ctrl-C. A bag that cannot be read gives one clear line and exit
status 2. Times are sim time [s].
"""

from __future__ import annotations

import argparse
import asyncio
import bisect
import json
import math
import re
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rosbags.rosbag1 import Reader

from coach4sim import CoachError
from coach4sim.scene import Scene, field_layout, stamp_seconds
from coach4sim.viewer_server import ViewerInputError, ViewerServer
from nubot_common.match_mode import MatchMode
from nubot_common.world_description import WorldDescription
from nubot_match.bag_reader import BAG_FAULTS, MatchBagError, build_typestore, unreadable, world_from_msg

STATES = "/sim_visual/model_states"
REFEREE = "/referee/state"
GOAL = "/sim_visual/goal"
WORLD = "/sim_visual/world_description"
TEAMMATES = re.compile(r"^/(?P<team>[^/]+)/simulation_interface/teammates$")
PER_ROBOT = re.compile(r"^/(?P<robot>[^/]+)/nubotcontrol/(?P<what>strategy|path)$")
SPEEDS = (0.05, 64.0)  # replay speeds allowed [x real time]


@dataclass(frozen=True)
class Mark:
    t: float  # [s]
    kind: str  # "goal" or "referee"
    text: str


@dataclass
class Timeline:
    """The match as drawn frames (JSON texts) at ``times`` [s], with the world and the marks."""

    world: WorldDescription
    times: list[float] = field(default_factory=list)
    frames: list[str] = field(default_factory=list)
    marks: list[Mark] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)  # what the replay had to make do without

    @property
    def start(self) -> float:
        return self.times[0] if self.times else 0.0

    @property
    def end(self) -> float:
        return self.times[-1] if self.times else 0.0

    def at(self, t: float) -> str | None:
        """The frame shown at ``t``: the last one drawn at or before it (the first before the start)."""
        if not self.frames:
            return None
        return self.frames[max(0, bisect.bisect_right(self.times, t) - 1)]


def _wanted(topic: str) -> bool:
    return topic in (STATES, REFEREE, GOAL, WORLD) or bool(TEAMMATES.match(topic) or PER_ROBOT.match(topic))


def _world(reader: Reader, typestore: Any, conns: list[Any]) -> tuple[WorldDescription, list[str]]:
    """The bag's world description, or the default field with a warning: a bag without one (an older bag, a partial
    recording) or with a bad one replays on the chapter's 18 x 12 m field."""
    default = WorldDescription()
    if not conns:  # (an empty selection would make the reader give every message)
        return default, [f"no world description in the bag ({WORLD}): drawing the default {default.name} field"]
    for conn, _, raw in reader.messages(connections=conns):
        try:
            return world_from_msg(typestore.deserialize_ros1(raw, conn.msgtype)), []
        except ValueError as exc:
            return default, [f"ignored {WORLD}: {exc}; drawing the default {default.name} field"]
    return default, [f"no world description in the bag ({WORLD}): drawing the default {default.name} field"]


def load_timeline(bag: Path, rate: float = 20.0,
                  progress: Callable[[float], None] | None = None) -> Timeline:
    """Read ``bag`` into a ``Timeline`` of ``rate`` frames per second of sim time; ``progress(share)`` now and
    then. Raises ``MatchBagError`` for a missing or unreadable bag or one without model states."""
    if not bag.is_file():
        raise MatchBagError(f"no such bag file: {bag}")
    try:
        with Reader(bag) as reader:
            conns = [c for c in reader.connections if _wanted(c.topic)]
            if not any(c.topic == STATES for c in conns):
                found = ", ".join(sorted({c.topic for c in reader.connections})) or "no topics at all"
                raise MatchBagError(f"{bag} has no {STATES}: nothing to draw; it has: {found}")
            typestore = build_typestore(conns)
            world, warnings = _world(reader, typestore, [c for c in conns if c.topic == WORLD])
            timeline = Timeline(world, warnings=warnings)
            scene = Scene(world)
            total = max(1, sum(c.msgcount for c in conns))
            step, due, last_event = 1.0 / rate, -math.inf, ""
            for done, (conn, _, raw) in enumerate(reader.messages(connections=conns), start=1):
                msg = typestore.deserialize_ros1(raw, conn.msgtype)
                topic = conn.topic
                if topic == STATES:
                    scene.on_model_states(msg)
                    t = stamp_seconds(msg.header.stamp)
                    if t >= due:
                        timeline.times.append(t)
                        timeline.frames.append(json.dumps(scene.frame(""), separators=(",", ":")))
                        due = t + step if due == -math.inf else max(due + step, t)
                elif topic == REFEREE:
                    scene.on_referee(msg)
                    if msg.last_event and msg.last_event != last_event:
                        timeline.marks.append(Mark(stamp_seconds(msg.header.stamp), "referee", msg.last_event))
                    last_event = msg.last_event
                elif topic == GOAL:
                    side = "+x" if msg.side > 0 else "-x"
                    touch = f", last touch {msg.last_touch}" if msg.last_touch else ""
                    timeline.marks.append(Mark(stamp_seconds(msg.header.stamp), "goal", f"goal at {side}{touch}"))
                elif (m := TEAMMATES.match(topic)) is not None:
                    scene.on_teammates(m["team"], msg)
                elif (m := PER_ROBOT.match(topic)) is not None:
                    (scene.on_strategy if m["what"] == "strategy" else scene.on_path)(m["robot"], msg)
                if progress is not None and done % 20000 == 0:
                    progress(done / total)
            final = json.dumps(scene.frame(""), separators=(",", ":"))  # what came after the last model states
            if timeline.frames and final != timeline.frames[-1]:
                timeline.times.append(max(scene.t, timeline.times[-1]))
                timeline.frames.append(final)
    except MatchBagError:
        raise
    except BAG_FAULTS as exc:
        raise MatchBagError(unreadable(bag, exc)) from exc
    timeline.marks.sort(key=lambda k: k.t)
    return timeline


class ReplayClock:
    """Where the replay is [s]: moves at ``speed`` x real time while playing; stops at the end."""

    def __init__(self, start: float, end: float, now: Callable[[], float] = time.monotonic):
        self.start, self.end, self._now = start, end, now
        self.speed = 1.0
        self.playing = False
        self._t0, self._wall0 = start, now()

    def t(self) -> float:
        if not self.playing:
            return self._t0
        t = self._t0 + (self._now() - self._wall0) * self.speed
        if t >= self.end:
            self.playing, self._t0 = False, self.end
            return self.end
        return t

    def _rebase(self, t: float) -> None:
        self._t0, self._wall0 = min(max(t, self.start), self.end), self._now()

    def play(self) -> None:
        if self.t() >= self.end:
            self._rebase(self.start)  # from the start again, as a player does
        else:
            self._rebase(self.t())
        self.playing = True

    def pause(self) -> None:
        self._rebase(self.t())
        self.playing = False

    def seek(self, t: float) -> None:
        self._rebase(t)

    def set_speed(self, speed: float) -> None:
        if not SPEEDS[0] <= speed <= SPEEDS[1]:
            raise ViewerInputError(f"a replay speed lies in [{SPEEDS[0]:g}, {SPEEDS[1]:g}], got {speed:g}")
        self._rebase(self.t())
        self.speed = speed


class ReplayBackend:
    """The viewer's backend over a ``Timeline``: frames at the clock's time; no commands."""

    def __init__(self, timeline: Timeline, title: str, clock: ReplayClock | None = None):
        self.timeline, self.title = timeline, title
        self.clock = clock or ReplayClock(timeline.start, timeline.end)

    def hello(self) -> dict[str, Any]:
        tl = self.timeline
        first = json.loads(tl.frames[0]) if tl.frames else {"teams": []}
        return {"mode": "replay", "title": self.title, "field": field_layout(tl.world),
                "teams": [t["name"] for t in first["teams"]],
                "replay": {"start": tl.start, "end": tl.end,
                           "marks": [{"t": m.t, "kind": m.kind, "text": m.text} for m in tl.marks]}}

    def frame(self, watch: str) -> str | None:
        t = self.clock.t()
        text = self.timeline.at(t)
        if text is None:
            return None
        state = json.dumps({"t": round(t, 3), "playing": self.clock.playing, "speed": self.clock.speed})
        return f'{text[:-1]},"replay":{state}}}'

    def command(self, command: MatchMode, team: str) -> tuple[bool, str]:
        return False, "a replay takes no game commands"

    def control(self, message: dict[str, Any]) -> None:
        action = message["action"]
        if action == "play":
            self.clock.play()
        elif action == "pause":
            self.clock.pause()
        elif action == "seek":
            if "t" not in message:
                raise ViewerInputError('a seek needs "t" [s]')
            self.clock.seek(float(message["t"]))
        elif action == "speed":
            if "speed" not in message:
                raise ViewerInputError('a speed change needs "speed"')
            self.clock.set_speed(float(message["speed"]))


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(prog="replay", description="Replay a match bag in the browser.")
    ap.add_argument("bag", type=Path, help="a bag of make match (matches/<time>/match.bag) or of a lockstep match")
    ap.add_argument("--host", default="127.0.0.1", help="address to serve on (default 127.0.0.1)")
    ap.add_argument("--port", type=int, default=8080, help="port (default 8080; 0: any free one)")
    ap.add_argument("--token", default="", help="token the page must present (made when --host is not loopback)")
    ap.add_argument("--rate", type=float, default=20.0, help="frames per second of sim time kept (default 20)")
    ap.add_argument("--speed", type=float, default=1.0, help="replay speed to start with (default 1)")
    ap.add_argument("--paused", action="store_true", help="start paused")
    return ap.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        if not 1.0 <= args.rate <= 100.0:
            raise CoachError(f"--rate must lie in [1, 100] frames per second, got {args.rate:g}")
        print(f"replay: reading {args.bag}", flush=True)
        timeline = load_timeline(args.bag, args.rate,
                                 lambda share: print(f"replay: {100 * share:.0f} % read", flush=True))
        for warning in timeline.warnings:
            print(f"replay: warning: {warning}", file=sys.stderr)
        backend = ReplayBackend(timeline, args.bag.name)
        backend.clock.set_speed(args.speed)
        server = ViewerServer(backend, args.host, args.port, args.token, rate=25.0)
    except (MatchBagError, CoachError) as exc:
        print(f"replay: {exc}", file=sys.stderr)
        return 2
    print(f"replay: {len(timeline.frames)} frames, {timeline.end - timeline.start:.1f} s of match, "
          f"{sum(m.kind == 'goal' for m in timeline.marks)} goals", flush=True)
    if not args.paused:
        backend.clock.play()
    try:
        asyncio.run(server.run(ready=lambda url: print(f"replay: open {url}  (Ctrl-C to stop)", flush=True)))
    except CoachError as exc:
        print(f"replay: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("replay: stopped")
    return 0

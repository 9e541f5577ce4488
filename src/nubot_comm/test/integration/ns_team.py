"""One robot LAN's side of a team link test, run INSIDE a network namespace (``ip netns exec <ns> python ns_team.py``).

It starts a roscore of its own (as each real robot has its own), the team_link nodes of ``--links`` (and a coach's
side with ``--coach``) through team_link.launch, plays the world models and strategies of the ``--feed`` robots at
30 Hz (every stamp = now, wall time), and watches what the links publish: per link (by caller id) and member, the
age (arrival - the member's TeamMessage stamp) of every /<team>/simulation_interface/teammates message, None when a
member expected by ``--expect`` is missing. With ``--fuzz N`` it then sends N malformed, oversized and foreign
datagrams to the group and watches again. Everything it saw goes to ``--out`` (JSON); it exits 0 unless it could not
get the graph up.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import struct
import sys
import tempfile
import threading
import time
import xmlrpc.client
from pathlib import Path

import numpy as np

from nubot_comm.codec import DEFAULT_URL
from nubot_comm.netns import group_of, group_sender
from nubot_common.processes import RosMaster
from nubot_lcm import team_packet_t

RATE = 30.0  # [Hz] the fed world models and strategies, as world_model and nubot_control send them
LCM_SHORT_MAGIC = 0x4C433032  # an LCM datagram carrying one whole message: magic, sequence, channel, NUL, payload
FUZZ_MAX_DATAGRAM = 65_000  # [bytes]
PACE_BYTES, PACE_PAUSE = 100_000, 0.01  # [bytes, s] the fuzzer pauses after sending this much
DATAGRAM_OVERHEAD = 1024  # [bytes] what a datagram costs a receiving socket's buffer beyond its payload


def sign(team: str) -> float:
    """Every fed value of team nubot is positive, of any other team negative: a leak shows in one field."""
    return 1.0 if team == "nubot" else -1.0


def to_plain(msg) -> object:  # noqa: ANN001 - any genpy message, list or value
    if hasattr(msg, "to_nsec"):
        return msg.to_nsec()
    if hasattr(msg, "__slots__") and hasattr(msg, "_slot_types"):
        return {name: to_plain(getattr(msg, name)) for name in msg.__slots__}
    if isinstance(msg, (list, tuple)):
        return [to_plain(v) for v in msg]
    if isinstance(msg, bytes):
        return list(msg)
    return msg


def launch_file(links: list[str], coach: str | None, url: str) -> str:
    lines = ["<launch>"]
    for robot in links:
        lines.append(f'  <include file="$(find nubot_comm)/launch/team_link.launch"><arg name="robot" value="{robot}"/>'
                     f'<arg name="lcm_url" value="{url}"/></include>')
    if coach:
        team, source = coach.split(":")
        lines.append(f'  <include file="$(find nubot_comm)/launch/team_link.launch"><arg name="coach" value="true"/>'
                     f'<arg name="team" value="{team}"/><arg name="coach_input" value="{source}"/>'
                     f'<arg name="lcm_url" value="{url}"/></include>')
    return "\n".join([*lines, "</launch>\n"])


class Watcher:
    """Ages of the members in each link's teammates, what reached the coach topics, and the links' status."""

    def __init__(self, expect: dict[str, list[int]], statuses: list[str]):
        import rospy

        from nubot_common.msg import CoachInfo, TeamLinkStatus, TeamMessages, simulation_strategy

        self.expect = expect
        self.lock = threading.Lock()
        self.recording = False
        self.samples: dict[str, dict[int, list[float | None]]] = {}
        self.last_team: dict[str, object] = {}
        self.last_strategy: dict[str, object] = {}
        self.heard: dict[str, set[int]] = {}  # per link: members in its latest teammates
        self.coach: dict[str, list[object]] = {}
        self.status: dict[str, dict] = {}
        self.subs = []
        for team in expect:
            self.subs += [
                rospy.Subscriber(f"/{team}/simulation_interface/teammates", TeamMessages,
                                 lambda m, t=team: self.on_team(t, m), queue_size=50),
                rospy.Subscriber(f"/{team}/simulation_interface/strategy", simulation_strategy, self.on_strategy,
                                 queue_size=50),
                rospy.Subscriber(f"/{team}/receive_from_coach", CoachInfo, self.on_coach, queue_size=50)]
        for topic in statuses:
            self.subs.append(rospy.Subscriber(topic, TeamLinkStatus, lambda m, t=topic: self.on_status(t, m),
                                              queue_size=10))

    def on_team(self, team: str, msg) -> None:  # noqa: ANN001
        now = time.time()
        link = msg._connection_header["callerid"]
        ages = {m.robot.AgentID: now - m.header.stamp.to_sec() for m in msg.messages}
        with self.lock:
            self.heard[link] = set(ages)
            self.last_team[link] = to_plain(msg)
            if self.recording:
                per_member = self.samples.setdefault(link, {})
                for agent in self.expect[team]:
                    per_member.setdefault(agent, []).append(ages.get(agent))

    def on_strategy(self, msg) -> None:  # noqa: ANN001
        with self.lock:
            self.last_strategy[msg._connection_header["callerid"]] = to_plain(msg)

    def on_coach(self, msg) -> None:  # noqa: ANN001
        with self.lock:
            self.coach.setdefault(msg._connection_header["callerid"], []).append(to_plain(msg))

    def on_status(self, topic: str, msg) -> None:  # noqa: ANN001
        with self.lock:
            self.status[topic] = to_plain(msg)

    def everyone_heard(self, links: list[str]) -> bool:
        with self.lock:
            return all(set(self.expect[team_of(link)]) <= self.heard.get(f"/{link}/team_link", set())
                       for link in links)

    def record(self, seconds: float) -> dict:
        with self.lock:
            self.samples, self.recording = {}, True
        time.sleep(seconds)
        with self.lock:
            self.recording = False
            return {link: {str(agent): ages for agent, ages in members.items()}
                    for link, members in self.samples.items()}


def team_of(robot: str) -> str:
    return robot.rstrip("0123456789")


class Feeder:
    """Plays the world model and strategy of each ``robots`` at RATE Hz, every stamp the time of sending."""

    def __init__(self, robots: list[str], coach_topic: str | None):
        import rospy

        from nubot_common.msg import CoachInfo, StrategyInfo, TeamMessage
        from nubot_common.node_io import publisher

        self.rospy = rospy
        self.types = (TeamMessage, StrategyInfo, CoachInfo)
        self.robots = robots
        self.pubs = {r: (publisher(f"/{r}/worldmodel/teammessage", TeamMessage),
                         publisher(f"/{r}/nubotcontrol/strategy", StrategyInfo)) for r in robots}
        self.coach_pub = publisher(coach_topic, CoachInfo) if coach_topic else None
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self) -> None:
        TeamMessage, StrategyInfo, CoachInfo = self.types
        period, tick = 1.0 / RATE, 0
        while not self.stop.is_set():
            start = time.monotonic()
            stamp = self.rospy.Time.from_sec(time.time())
            for robot, (message_pub, strategy_pub) in self.pubs.items():
                team, agent = team_of(robot), int(robot[len(team_of(robot)):])
                s = sign(team)
                msg = TeamMessage()
                msg.header.stamp = msg.robot.header.stamp = msg.ball.header.stamp = stamp
                msg.robot.AgentID, msg.robot.isvalid, msg.robot.current_role = agent, True, agent
                msg.robot.pos.x, msg.robot.pos.y, msg.robot.heading.theta = s * (agent + 0.25), s * 1.5, 0.1 * agent
                msg.ball.pos.x, msg.ball.pos.y, msg.ball.pos_known = s * agent, s * 2.0, True
                msg.obstacles.pos = [type(msg.robot.pos)(s * (agent + k), s * 3.0) for k in range(3)]
                msg.obstacles.polar_pos = [type(msg.ball.real_pos)(0.1 * k, s * (4.0 + k)) for k in range(3)]
                strategy = StrategyInfo(AgentID=agent, role=agent, action=tick % 7, role_time=s * 0.5)
                strategy.header.stamp = stamp
                strategy.pass_cmd.catch_id, strategy.pass_cmd.catch_pt.x = agent, s * 6.0
                message_pub.publish(msg)
                strategy_pub.publish(strategy)
            if self.coach_pub is not None and tick % 3 == 0:
                command = CoachInfo(MatchMode=10, MatchType=0, angleA=-45, kickforce=7)
                command.pointA.x = 1.5
                command.header.stamp = stamp
                self.coach_pub.publish(command)
            tick += 1
            self.stop.wait(max(period - (time.monotonic() - start), 0.0))

    def close(self) -> None:
        self.stop.set()
        self.thread.join(timeout=2.0)


def datagram(channel: str, payload: bytes, seq: int) -> bytes:
    return struct.pack(">II", LCM_SHORT_MAGIC, seq) + channel.encode() + b"\0" + payload


CONTENT_KINDS = ("random", "fingerprint_garbage", "truncated", "invalid", "oversize", "coach_garbage")


def fuzz(count: int, url: str, teams: list[str], seed: int = 0) -> dict[str, dict[str, int]]:
    """Send ``count`` datagrams to the group that no link may take, of every kind, in turn to each team's channels.

    Returns how many of each kind, and per team how many of CONTENT_KINDS went to its channels: the datagrams its
    links must count as oversize, foreign_type, malformed or invalid (the others are foreign_channel, or not LCM's)."""
    rng = np.random.default_rng(seed)
    group, port = group_of(url)
    sock = group_sender()
    valid = team_packet_t()
    valid.team, valid.agent_id, valid.session, valid.robot.AgentID, valid.strategy.AgentID = teams[0], 1, 1, 1, 1
    good = valid.encode()
    fingerprint = team_packet_t._get_packed_fingerprint()
    kinds = ["random", "fingerprint_garbage", "truncated", "invalid", "oversize", "coach_garbage", "other_channel",
             "not_lcm"]
    sent = dict.fromkeys(kinds, 0)
    to_team = dict.fromkeys(teams, 0)
    unpaced = largest = 0
    for i in range(count):
        kind = kinds[i % len(kinds)]
        team = teams[(i // len(kinds)) % len(teams)]
        to_team[team] += kind in CONTENT_KINDS
        channel = f"NUBOT_TEAM_{team}"
        if kind == "random":
            payload = rng.bytes(int(rng.integers(0, 1500)))
        elif kind == "fingerprint_garbage":
            payload = fingerprint + rng.bytes(int(rng.integers(0, 1500)))
        elif kind == "truncated":
            payload = good[:int(rng.integers(8, len(good)))]
        elif kind == "invalid":
            bad = team_packet_t.decode(good)
            bad.team, bad.seq = team, 10**9 + i
            bad.robot.pos.x = float("nan") if i % 2 else 0.0
            bad.agent_id = 1 if i % 2 else 9
            payload = bad.encode()
        elif kind == "oversize":
            size = int(rng.integers(3000, FUZZ_MAX_DATAGRAM - 8 - len(channel) - 1))
            payload = fingerprint + rng.bytes(size - len(fingerprint))
        elif kind == "coach_garbage":
            channel, payload = f"NUBOT_COACH_{team}", rng.bytes(int(rng.integers(0, 300)))
        elif kind == "other_channel":
            channel, payload = f"FUZZ_{i % 13}", rng.bytes(int(rng.integers(0, 300)))
        else:
            channel, payload = "", b""
        data = datagram(channel, payload, i) if channel else rng.bytes(int(rng.integers(1, 1500)))
        sock.sendto(data, (group, port))
        sent[kind] += 1
        largest = max(largest, len(data))
        # Paced so that no receiver's socket buffer (about 200 kB) overflows while the links keep up: a datagram takes
        # its bytes there and the kernel's bookkeeping, about a kB more. What a busy machine drops all the same is in
        # kernel_drops.
        unpaced += len(data) + DATAGRAM_OVERHEAD
        if unpaced > PACE_BYTES:
            time.sleep(PACE_PAUSE)
            unpaced = 0
    sock.close()
    return {"by_kind": sent, "content_by_team": to_team, "largest": largest}


def kernel_drops(master_uri: str, statuses: list[str]) -> dict[str, int]:
    """Per status topic, the datagrams the kernel dropped at its link's UDP sockets (a full receive buffer, e.g. when
    a busy machine does not run the link for a while): the drops column of this namespace's /proc/net/udp, for the
    sockets the link's process holds. A link cannot count what it never received."""
    dropped_at = {}
    for line in Path("/proc/net/udp").read_text().splitlines()[1:]:
        fields = line.split()
        dropped_at[fields[9]] = int(fields[12])  # inode -> drops
    master = xmlrpc.client.ServerProxy(master_uri)
    _code, _msg, (published, _subs, _srvs) = master.getSystemState("/ns_team")  # now: the coach's link comes last
    publishers = dict(published)
    counts = {}
    for topic in statuses:
        if topic not in publishers:
            raise RuntimeError(f"nobody publishes {topic}")
        node = publishers[topic][0]
        _code, _msg, api = master.lookupNode("/ns_team", node)
        _code, _msg, pid = xmlrpc.client.ServerProxy(api).getPid("/ns_team")
        inodes = set()
        for fd in Path(f"/proc/{pid}/fd").iterdir():
            try:
                target = os.readlink(fd)
            except OSError:
                continue  # closed meanwhile
            if target.startswith("socket:["):
                inodes.add(target[len("socket:["):-1])
        udp = inodes & dropped_at.keys()
        if not udp:
            raise RuntimeError(f"{node} (pid {pid}) holds no UDP socket in /proc/net/udp")
        counts[topic] = sum(dropped_at[i] for i in udp)
    return counts


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--links", default="", help="robots whose team_link runs here, e.g. nubot1,nubot2")
    parser.add_argument("--coach", default=None, help="TEAM:TOPIC: the coach's side of TEAM, reading TOPIC")
    parser.add_argument("--feed", default="", help="robots whose world model and strategy this plays")
    parser.add_argument("--expect", required=True, help="members each team's links must hear: nubot=1,2,3;rival=1")
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--fuzz", type=int, default=0)
    parser.add_argument("--ready-timeout", type=float, default=40.0)
    parser.add_argument("--url", default=DEFAULT_URL)
    args = parser.parse_args()
    links = [r for r in args.links.split(",") if r]
    expect = {team: [int(a) for a in agents.split(",")]
              for team, agents in (part.split("=") for part in args.expect.split(";"))}
    coach_team, coach_topic = args.coach.split(":") if args.coach else (None, None)
    statuses = [f"/{r}/team_link/status" for r in links] + ([f"/{coach_team}/team_link/status"] if coach_team else [])
    result: dict = {"links": links, "expect": expect}
    logs = Path(tempfile.mkdtemp(prefix="ns_team_"))
    with RosMaster(logs) as master:
        master.use_in_this_process()
        import rospy

        rospy.init_node("ns_team_driver", anonymous=True, disable_signals=True)
        launch = logs / "links.launch"
        launch.write_text(launch_file(links, args.coach, args.url))
        nodes = master.launch("team_links", ["roslaunch", "--skip-log-check", str(launch)])
        watcher = Watcher(expect, statuses)
        feeder = Feeder([r for r in args.feed.split(",") if r], coach_topic)
        start = time.monotonic()
        try:
            while not watcher.everyone_heard(links):
                if time.monotonic() - start > args.ready_timeout or not nodes.alive():
                    raise RuntimeError("the links did not hear their teams")
                time.sleep(0.05)
            result["ready_after"] = time.monotonic() - start
            result["publishers"] = {topic: sorted(nodes) for topic, nodes in master.graph().publishers.items()}
            result["measure"] = watcher.record(args.seconds)
            result["status"] = dict(watcher.status)
            if args.fuzz:
                result["kernel_drops"] = kernel_drops(master.uri, statuses)
                fuzz_start = time.monotonic()
                result["fuzz_sent"] = fuzz(args.fuzz, args.url, list(expect))
                result["fuzz_seconds"] = time.monotonic() - fuzz_start
                time.sleep(1.5)  # every link has handled what it got, and published its status
                result["after_fuzz"] = watcher.record(2.0)
                result["status_after_fuzz"] = dict(watcher.status)
                result["kernel_drops_after_fuzz"] = kernel_drops(master.uri, statuses)
            result["alive"] = nodes.alive()
        except RuntimeError as exc:
            result["error"] = str(exc)
        finally:
            feeder.close()
            with watcher.lock:
                result["last_team"], result["last_strategy"] = watcher.last_team, watcher.last_strategy
                result["coach"] = {k: v[-5:] for k, v in watcher.coach.items()}
                result["coach_count"] = {k: len(v) for k, v in watcher.coach.items()}
            rospy.signal_shutdown("done")
            master.stop()
            result["log"] = nodes.log_text()[-20000:]
    shutil.rmtree(logs, ignore_errors=True)  # what the test needs of it is in the result
    args.out.write_text(json.dumps(result))
    return 0 if "error" not in result else 1


if __name__ == "__main__":
    sys.exit(main())

"""One real robot's software against the simulator (``real_robot.launch backend:=sim``), run INSIDE a network
namespace (its LCM team link multicasts): ``ip netns exec <ns> python -m nubot_tools.ros.real_robot_run ...``.

Scenarios (``--scenario``):
- ``figure``: no nubot_control; a figure eight (2 m/s, turning +-1.2 rad/s, every 5 s the other way) on
  /nubotcontrol/velcmd for ``UP_TO_SPEED`` and then ``--seconds`` of sim time (whole figure eights: 10 s each). It
  integrates /nubotdriver/odoinfo as a user of the odometry would (body velocities at their stamps) over those
  ``--seconds`` and compares the pose change with the simulator's truth (/sim_visual/model_states): the drift per
  10 m travelled. The span starts and ends turning the same way, at speed: over ROS the simulated drive's encoders
  run ahead of the simulator's robot by the WheelSpeeds' delivery (a real drive's are on its motors), a lead that
  cancels between such ends; from a standstill to the other turn the heading error reached 0.06 rad on a loaded
  machine, against 0.03 now. That lead grows with the delivery's delay in sim time, which a loaded machine
  lengthens (0.45 m per 10 m once, in a clean clone's test run beside the unit tests): ``--real-time-factor``
  below 1 runs the simulator slower than the wall clock, so the same wall delay is less sim time. It also keeps
  nubot_hwcontrol's loop period (nubotdriver/status) and every node's CPU.
- ``loop``: nubot_hwcontrol alone on wall time (as on the robot; its simulated drive has no simulator to move,
  so its wheels read as blocked): the control loop's period without the simulator's /clock ticks.
- ``score``: the whole robot; the coach's STARTROBOT reaches it through a coach's team link (LCM) and the
  robot's own; the robot must score in the goal at +x within ``--seconds`` of sim time.
Writes ``--out`` (JSON); exits 0 unless the graph did not come up.
"""

from __future__ import annotations

import argparse
import math
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import rosgraph
import rospy
from std_msgs.msg import Bool

from nubot_common.json_text import strict_json
from nubot_common.msg import CoachInfo, GoalEvent, HardwareStatus, ModelStates, OdoInfo, VelCmd
from nubot_common.packages import package_path
from nubot_common.processes import RosMaster
from nubot_tools.bench.hwcontrol import figure_command
from nubot_tools.resources import ResourceLog

URL = "udpm://239.255.76.67:7667?ttl=0"
ROBOT = 2
UP_TO_SPEED = 2.5  # [s] of the figure before the odometry is compared: moving, a quarter figure into the left turn


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenario", choices=("figure", "loop", "score"), required=True)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--real-time-factor", type=float, default=1.0,
                    help="the simulator's pace against the wall clock (below 1: slower, for a loaded machine)")
    ap.add_argument("--out", type=Path, required=True)
    args = ap.parse_args()
    if not 0.0 < args.real_time_factor <= 1.0:
        ap.error(f"--real-time-factor must lie in (0, 1], got {args.real_time_factor}")
    result: dict = {"scenario": args.scenario}
    logs = Path(tempfile.mkdtemp(prefix="real_robot_"))
    try:
        run(args, result, logs)
    except Exception as exc:  # noqa: BLE001 - reported to the test with the launch's log
        result["error"] = f"{type(exc).__name__}: {exc}"
        log = logs / "robot.log"
        result["log"] = log.read_text()[-6000:] if log.exists() else ""
    finally:
        shutil.rmtree(logs, ignore_errors=True)  # what is wanted of it is in the result
    args.out.write_text(strict_json(result, indent=1))
    return 0


def run(args: argparse.Namespace, result: dict, logs: Path) -> None:
    with RosMaster(logs) as master:
        master.use_in_this_process()
        if args.scenario == "loop":
            loop(master, args.seconds, result)
            return
        figure = args.scenario == "figure"
        # the driver's clock is the simulator's, as the launched nodes' (set before any node starts)
        subprocess.run(["rosparam", "set", "/use_sim_time", "true"], env=master.env, check=True)
        launch = ["roslaunch", "--skip-log-check", "nubot_hwcontrol", "real_robot.launch", f"robot:={ROBOT}",
                  "backend:=sim", "referee:=false", f"lcm_url:={URL}", "x:=-1.0", "y:=0.0"]
        launch += ["control:=false", "ball_x:=3.0", "ball_y:=4.0"] if figure else ["ball_x:=2.0", "ball_y:=0.5"]
        if args.real_time_factor != 1.0:
            pace = logs / "pace.yaml"
            pace.write_text(f"real_time_factor: {args.real_time_factor}\n")
            launch.append(f"sim_config:={pace}")
        robot = master.launch("robot", launch)
        if not figure:
            master.launch("coach", ["roslaunch", "--skip-log-check", "nubot_comm", "team_link.launch", "coach:=true",
                                    "team:=nubot", "coach_input:=/coach/nubot/receive_from_coach",
                                    f"lcm_url:={URL}", "output:=log"])
        rospy.init_node("real_robot_run", anonymous=True, disable_signals=True)
        name = f"nubot{ROBOT}"
        truth: list[tuple[float, float, float, float]] = []
        odo: list[tuple[float, float, float, float]] = []
        statuses: list[HardwareStatus] = []
        goals: list[GoalEvent] = []
        holding: list[bool] = []

        def on_states(msg: ModelStates) -> None:
            if name in msg.name:
                p = msg.pose[msg.name.index(name)]
                yaw = 2.0 * math.atan2(p.orientation.z, p.orientation.w)
                truth.append((msg.header.stamp.to_sec(), p.position.x, p.position.y, yaw))

        rospy.Subscriber("/sim_visual/model_states", ModelStates, on_states, queue_size=50)
        rospy.Subscriber("/nubotdriver/odoinfo", OdoInfo,
                         lambda m: odo.append((m.header.stamp.to_sec(), m.Vx, m.Vy, m.w)), queue_size=200)
        rospy.Subscriber("/nubotdriver/status", HardwareStatus, statuses.append, queue_size=10)
        rospy.Subscriber("/nubotdriver/ballholding", Bool, lambda m: holding.append(m.data), queue_size=200)
        rospy.Subscriber("/sim_visual/goal", GoalEvent, goals.append, queue_size=10)
        velcmd = rospy.Publisher("/nubotcontrol/velcmd", VelCmd, queue_size=1)
        coach = rospy.Publisher("/coach/nubot/receive_from_coach", CoachInfo, queue_size=1)
        deadline = time.monotonic() + 60.0
        while not (odo and truth and rospy.get_time() > 0.0):  # the simulator, the drive and the odometry are up
            if time.monotonic() > deadline or not robot.alive():
                raise RuntimeError("real_robot.launch did not come up (no odometry or no model states)")
            time.sleep(0.1)
        sampler = ResourceLog(lambda: [robot.process.pid], rospy.get_time)
        start = rospy.get_time()
        start_truth, start_odo = len(truth), len(odo)
        next_sample = 0.0
        wall_deadline = time.monotonic() + 3.0 * args.seconds / args.real_time_factor + 30.0
        drive = args.seconds + (UP_TO_SPEED if figure else 0.0)
        while rospy.get_time() - start < drive and time.monotonic() < wall_deadline:
            t = rospy.get_time() - start
            if figure:
                vx, vy, w = figure_command(t)
                velcmd.publish(VelCmd(Vx=vx, Vy=vy, w=w))
            else:
                coach.publish(CoachInfo(MatchMode=15, MatchType=0))
                if goals:
                    break
            if time.monotonic() >= next_sample:
                sampler.sample(time.monotonic())
                next_sample = time.monotonic() + 2.0
            time.sleep(0.03)
        elapsed = rospy.get_time() - start
        sampler.sample(time.monotonic())  # a last look: a goal scored within seconds still gives every node a figure
        result["graph"] = drive_graph()
        result.update(sim_seconds=elapsed, goals=[{"side": g.side, "last_touch": g.last_touch,
                                                   "time": g.header.stamp.to_sec() - start} for g in goals],
                      ever_held=any(holding))
        cpu: dict[str, list[float]] = {}
        looked: set[int] = set()
        for s in sampler.samples:
            if s.pid not in looked:  # psutil's CPU needs two looks at a process: the first gives nothing
                looked.add(s.pid)
                continue
            cpu.setdefault(s.process, []).append(s.cpu_cores)
        result["cpu_cores"] = {k: round(sum(v) / len(v), 3) for k, v in cpu.items() if v}
        result.update(loop_figures(statuses))
        if figure:
            result.update(drift([s for s in truth[start_truth:] if s[0] >= start + UP_TO_SPEED], odo[start_odo:]))


def drive_graph() -> dict[str, dict[str, list[str]]]:
    """Return the publishers and subscribers of the topics between the simulated drive and the simulator."""
    publishers, subscribers, _services = rosgraph.Master("/real_robot_run").getSystemState()
    graph: dict[str, dict[str, list[str]]] = {}
    for kind, table in (("publishers", publishers), ("subscribers", subscribers)):
        for topic, nodes in table:
            if topic.endswith(("/wheel_speeds", "/drive_feedback")):
                graph.setdefault(topic, {"publishers": [], "subscribers": []})[kind] = sorted(nodes)
    return graph


def loop_figures(statuses: list) -> dict:
    """The control loop's period: the median of the per-second medians, and the worst per-second p99."""
    if not statuses:
        return {}
    p50 = sorted(s.loop_period_p50 for s in statuses)
    return {"loop_period_p50": p50[len(p50) // 2], "loop_period_p99": max(s.loop_period_p99 for s in statuses),
            "loop_overruns": statuses[-1].overruns, "loop_windows": len(statuses)}


def loop(master: RosMaster, seconds: float, result: dict) -> None:
    config = package_path("nubot_hwcontrol") / "config" / "nubot_hwcontrol.yaml"
    subprocess.run(["rosparam", "load", str(config), "/nubot_hwcontrol"], env=master.env, check=True)
    node = master.launch("hwcontrol", ["rosrun", "nubot_hwcontrol", "nubot_hwcontrol_node"])
    rospy.init_node("real_robot_run", anonymous=True, disable_signals=True)
    statuses: list[HardwareStatus] = []
    rospy.Subscriber("/nubotdriver/status", HardwareStatus, statuses.append, queue_size=10)
    sampler = ResourceLog(lambda: [node.process.pid], time.monotonic)
    end = time.monotonic() + seconds + 3.0
    while time.monotonic() < end:
        if not node.alive():
            raise RuntimeError(f"nubot_hwcontrol exited:\n{node.log_text()[-3000:]}")
        sampler.sample(time.monotonic())
        time.sleep(1.0)
    result.update(loop_figures(statuses[2:]))  # the first seconds include the start
    per_look: dict[float, float] = {}  # rosrun and the node's interpreter, summed per look
    for s in sampler.samples:
        per_look[s.wall] = per_look.get(s.wall, 0.0) + s.cpu_cores
    cpu = list(per_look.values())[2:]
    result["cpu_cores"] = {"/nubot_hwcontrol": round(sum(cpu) / len(cpu), 3) if cpu else None}


def drift(truth: list[tuple[float, float, float, float]], odo: list[tuple[float, float, float, float]]) -> dict:
    """Integrate the odometry's body velocities over the truth's time span; compare the pose change.

    A message's velocities are those of the period it ends (since the one before), so each counts from the previous
    stamp to its own, clipped to the span: the first after the span's start covers it from the start, and the first
    at or after its end covers it up to the end (at 50 Hz and 1.3 rad/s, dropping those ends cost up to 0.05 rad).
    """
    t0, x0, y0, th0 = truth[0]
    t1, x1, y1, th1 = truth[-1]
    x = y = 0.0
    th, covered = th0, t0
    for stamp, vx, vy, w in sorted(odo):
        if stamp <= t0:
            continue
        end = min(stamp, t1)
        dt = end - covered
        mid = th + 0.5 * w * dt
        x += (vx * math.cos(mid) - vy * math.sin(mid)) * dt
        y += (vx * math.sin(mid) + vy * math.cos(mid)) * dt
        th += w * dt
        covered = end
        if stamp >= t1:
            break
    travelled = sum(math.dist(a[1:3], b[1:3]) for a, b in zip(truth, truth[1:]))
    error = math.hypot(x - (x1 - x0), y - (y1 - y0))
    heading = math.remainder(th - th1, 2.0 * math.pi)
    return {"travelled": travelled, "position_error": error, "heading_error": heading,
            "drift_per_10m": error / travelled * 10.0 if travelled > 0 else None,
            "odometry_rate": len([o for o in odo if t0 < o[0] <= t1]) / max(t1 - t0, 1e-9)}


if __name__ == "__main__":
    sys.exit(main())

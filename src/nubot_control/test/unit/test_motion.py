"""Unit tests of the motion layer (both trackers) on a kinematic robot: targets, limits, obstacles, waypoints."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D, rotate
from nubot_common.percepts import RobotReport
from nubot_common.world_description import WorldDescription
from nubot_common.world_state import FusedBall, GameState, LabelledObstacle, ObstacleLabel, Teammate, WorldState
from nubot_control.motion import MotionController, keep_clear, obstacle_table, sub_target
from nubot_control.params import MotionParams
from nubot_control.team_state import MAX_PREDICTION, team_state

P = MotionParams()
ROBOT_RADIUS = WorldDescription().robot.radius  # [m]
DT = 1 / 33
IN_THE_WAY = P.clearance - P.contact_margin  # the guard's margin beside a robot, as the motion layer sets it [m]
TRACKERS = ["mpc", "baseline"]


def drive(start, target, obstacles, seconds=8.0, tracker="mpc", holding=False, waypoints=None, **params):
    """Integrate the commands kinematically; return the path and the controller."""
    ctl = MotionController(MotionParams(tracker=tracker, **params), WorldDescription(), DT)
    pose, path = start, [start]
    for _ in range(int(seconds / DT)):
        if waypoints is None:
            bx, by, w = ctl.command(pose, target, obstacles, DT, holding=holding)
        else:
            bx, by, w = ctl.follow(pose, waypoints, target.theta, obstacles, DT)
        vx, vy = rotate(bx, by, pose.theta)
        pose = Pose2D(pose.x + vx * DT, pose.y + vy * DT, pose.theta + w * DT)
        path.append(pose)
    return path, ctl


def speeds_and_accels(path):
    xy = np.array([(p.x, p.y) for p in path])
    v = np.diff(xy, axis=0) / DT
    return np.linalg.norm(v, axis=1), np.linalg.norm(np.diff(v, axis=0), axis=1) / DT


@pytest.mark.parametrize("tracker", TRACKERS)
def test_reaches_the_target_pose(tracker):
    path, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(4.0, -2.0, 1.5), [], tracker=tracker)
    end = path[-1]
    assert (end.x, end.y, end.theta) == pytest.approx((4.0, -2.0, 1.5), abs=0.03)


@pytest.mark.parametrize("tracker", TRACKERS)
def test_speed_and_acceleration_stay_within_limits(tracker):
    path, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(8.0, 3.0, 0.0), [(4.0, 1.6)], seconds=6.0, tracker=tracker)
    speeds, accels = speeds_and_accels(path)
    assert speeds.max() <= P.max_speed + 1e-6
    assert accels.max() <= P.max_accel + 1e-6
    assert speeds.max() > 0.9 * P.max_speed, "it does use the speed it has"


@pytest.mark.parametrize("tracker", TRACKERS)
def test_a_robot_holding_the_ball_keeps_the_dribbling_limits(tracker):
    path, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(6.0, 2.0, 0.0), [], seconds=6.0, tracker=tracker, holding=True)
    speeds, accels = speeds_and_accels(path)
    assert speeds.max() <= P.dribble_speed + 1e-6
    assert accels.max() <= max(P.dribble_accel, P.max_accel if tracker == "mpc" else 0.0) + 1e-6
    assert np.percentile(accels, 90) <= P.dribble_accel + 1e-6, "the plan itself speeds up gently"
    assert math.dist((path[-1].x, path[-1].y), (6.0, 2.0)) < 0.05


@pytest.mark.parametrize("tracker", TRACKERS)
@pytest.mark.parametrize("offset", [0.0, 0.2, -0.3])
def test_never_drives_through_an_obstacle(tracker, offset):
    obstacles = [(3.0, offset), (5.0, -offset)]
    path, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(8.0, 0.0, 0.0), obstacles, seconds=10.0, tracker=tracker)
    closest = min(math.hypot(p.x - ox, p.y - oy) for p in path for ox, oy in obstacles)
    assert closest > 2 * ROBOT_RADIUS, "the hulls never touch"
    assert path[-1].x == pytest.approx(8.0, abs=0.05)


def test_mpc_follows_waypoints_in_order_around_two_robots():
    """The Fig. 13 scene on a kinematic robot: via p1 and p2 to p3, clear of both obstacles."""
    waypoints = [(-2.0, 2.0), (2.0, -2.0), (6.0, 2.0)]
    obstacles = [(-4.0, 0.0), (0.0, 0.0)]
    path, ctl = drive(Pose2D(-6.0, -3.0, 0.0), Pose2D(6.0, 2.0, 0.0), obstacles, seconds=14.0,
                      waypoints=waypoints, max_speed=3.25)
    xy = np.array([(p.x, p.y) for p in path])
    passes = [int(np.argmin(np.linalg.norm(xy - w, axis=1))) for w in waypoints]
    assert passes == sorted(passes), "p1, then p2, then p3"
    assert all(np.linalg.norm(xy - w, axis=1).min() < 0.1 for w in waypoints)
    gaps = [np.linalg.norm(xy - o, axis=1).min() - 2 * ROBOT_RADIUS for o in obstacles]
    assert min(gaps) > 0.1
    assert np.linalg.norm(xy[-1] - waypoints[-1]) < 0.03


def test_a_robot_pushed_off_its_route_goes_on_to_the_waypoints_still_ahead():
    """Past p1, the robot is pushed 0.6 m off its plan (a collision, a base that lags): the new plan starts from the
    robot and goes on to p2 and p3, not back to p1."""
    waypoints = [(-2.0, 2.0), (2.0, -2.0), (6.0, 2.0)]
    ctl = MotionController(MotionParams(), WorldDescription(), DT)
    pose = Pose2D(-6.0, -3.0, 0.0)
    for _ in range(int(8.0 / DT)):
        bx, by, w = ctl.follow(pose, waypoints, 0.0, [], DT)
        vx, vy = rotate(bx, by, pose.theta)
        pose = Pose2D(pose.x + vx * DT, pose.y + vy * DT, pose.theta + w * DT)
        if ctl.waypoints[0] == waypoints[1] and pose.x > -1.0:
            break
    assert ctl.waypoints[0] == waypoints[1], "p1 passed"
    pushed = Pose2D(pose.x, pose.y + 0.6, pose.theta)
    ctl.follow(pushed, waypoints, 0.0, [], DT)
    assert waypoints[0] not in ctl.waypoints and ctl.trajectory.via[0] == pytest.approx((pushed.x, pushed.y))


def test_mpc_reference_moves_on_smoothly_from_cycle_to_cycle():
    ctl = MotionController(MotionParams(), WorldDescription(), DT)
    pose, refs = Pose2D(0.0, 0.0, 0.0), []
    for _ in range(120):
        bx, by, w = ctl.command(pose, Pose2D(7.0, 3.0, 0.0), [(3.5, 1.4)], DT)
        refs.append(ctl.reference[0])
        vx, vy = rotate(bx, by, pose.theta)
        pose = Pose2D(pose.x + vx * DT, pose.y + vy * DT, pose.theta + w * DT)
    steps = np.linalg.norm(np.diff(np.array(refs), axis=0), axis=1)
    assert steps.max() <= P.max_speed * DT * 1.3, "no jump: each cycle replans from where the last plan was"


def test_an_unknown_tracker_is_refused():
    with pytest.raises(ValueError, match="tracker must be one of mpc, baseline"):
        MotionParams(tracker="pid")


def test_sub_target_is_the_goal_when_the_way_is_free():
    assert sub_target((0.0, 0.0), (5.0, 0.0), [(2.0, 3.0)], 0.8) == (5.0, 0.0)
    aside = sub_target((0.0, 0.0), (5.0, 0.0), [(2.5, 0.1)], 0.8)
    assert aside != (5.0, 0.0) and abs(aside[1] - 0.1) >= 0.8


def _step(ctl, pose, target, obstacles=(), holding=False):
    """One cycle on a kinematic robot; the new pose."""
    bx, by, w = ctl.command(pose, target, list(obstacles), DT, holding=holding)
    vx, vy = rotate(bx, by, pose.theta)
    return Pose2D(pose.x + vx * DT, pose.y + vy * DT, pose.theta + w * DT)


def _settled(cycles=20, **params):
    """A controller 20 cycles into a drive from rest at the origin towards (6, 0) on a free field."""
    ctl = MotionController(MotionParams(**params), WorldDescription(), DT)
    pose = Pose2D(0.0, 0.0, 0.0)
    for _ in range(cycles):
        pose = _step(ctl, pose, Pose2D(6.0, 0.0, 0.0))
    return ctl, pose


def test_a_plan_that_holds_is_kept_and_renewed_after_keep_plan_time():
    ctl, pose = _settled()
    plans = []
    for _ in range(40):
        pose = _step(ctl, pose, Pose2D(6.0, 0.0, 0.0))
        plans.append(id(ctl.trajectory))
    renewals = sum(a != b for a, b in zip(plans, plans[1:]))
    assert 1 <= renewals <= 40 * DT / P.keep_plan_time + 1, "kept, and replanned only as it grows old"


def test_a_plan_made_at_the_limits_themselves_is_kept():
    """plan_share 1: the plan's acceleration is the limit to within rounding, which is within it (the robot may
    follow it), so it is kept while the robot stays near it instead of being replaced every cycle."""
    ctl = MotionController(MotionParams(plan_share=1.0, keep_plan_deviation=0.5), WorldDescription(), DT)
    pose, plans = Pose2D(0.0, 0.0, 0.0), []
    for _ in range(10):
        pose = _step(ctl, pose, Pose2D(6.0, 0.0, 0.0))
        plans.append(id(ctl.trajectory))
    assert len(set(plans)) == 1


def test_keep_plan_time_zero_replans_every_cycle():
    ctl, pose = _settled(keep_plan_time=0.0)
    plans = []
    for _ in range(10):
        pose = _step(ctl, pose, Pose2D(6.0, 0.0, 0.0))
        plans.append(ctl.trajectory)
    assert len({id(t) for t in plans}) == 10


def test_a_plan_is_replaced_when_the_target_moves_beyond_the_tolerance():
    ctl, pose = _settled()
    kept = ctl.trajectory
    pose = _step(ctl, pose, Pose2D(6.0, 0.02, 0.0))  # within keep_plan_goal_shift
    assert ctl.trajectory is kept
    pose = _step(ctl, pose, Pose2D(6.0, 1.5, 0.0))
    assert ctl.trajectory is not kept
    assert ctl.trajectory.xy[-1] == pytest.approx((6.0, 1.5))


def test_a_plan_is_replaced_when_an_obstacle_steps_onto_its_path():
    ctl, pose = _settled()
    kept = ctl.trajectory
    pose = _step(ctl, pose, Pose2D(6.0, 0.0, 0.0), obstacles=[(5.0, 3.0)])  # far off the path
    assert ctl.trajectory is kept
    _step(ctl, pose, Pose2D(6.0, 0.0, 0.0), obstacles=[(3.5, 0.1)])
    assert ctl.trajectory is not kept
    gap = np.linalg.norm(ctl.trajectory.xy - (3.5, 0.1), axis=1).min()
    assert gap > 2 * ROBOT_RADIUS + P.clearance - 0.01, "the new plan goes round it"


def test_a_plan_is_replaced_when_the_robot_is_pushed_off_it_or_its_limits_change():
    ctl, pose = _settled()
    kept = ctl.trajectory
    pose = _step(ctl, Pose2D(pose.x, pose.y + 2 * P.keep_plan_deviation, pose.theta), Pose2D(6.0, 0.0, 0.0))
    assert ctl.trajectory is not kept
    kept = ctl.trajectory
    _step(ctl, pose, Pose2D(6.0, 0.0, 0.0), holding=True)  # the dribbling limits
    assert ctl.trajectory is not kept


def test_keeping_plans_drives_like_replanning_every_cycle():
    """The same drive round an obstacle, plans kept or made every cycle: the same route within centimetres, the
    same clearance within 3 cm (the planner's own difference: the contact guard leaves a path that keeps the planner's
    clearance alone), the goal reached as soon (a kept plan's speed profile differs a little on the way)."""
    obstacles = [(3.0, 0.2)]
    kept, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(6.0, 1.0, 0.0), obstacles, seconds=5.0)
    every, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(6.0, 1.0, 0.0), obstacles, seconds=5.0, keep_plan_time=0.0)
    a, b = (np.array([(p.x, p.y) for p in path]) for path in (kept, every))
    assert max(np.linalg.norm(b - point, axis=1).min() for point in a) < 0.1
    gaps = [np.linalg.norm(xy - obstacles[0], axis=1).min() for xy in (a, b)]
    assert gaps[0] == pytest.approx(gaps[1], abs=0.03)
    arrivals = [int(np.argmax(np.linalg.norm(xy - (6.0, 1.0), axis=1) < 0.05)) for xy in (a, b)]
    assert abs(arrivals[0] - arrivals[1]) <= 3
    assert np.linalg.norm(a[-1] - b[-1]) < 0.02


@pytest.mark.parametrize("name", ["keep_plan_deviation", "keep_plan_goal_shift", "keep_plan_goal_share",
                                  "keep_plan_time"])
def test_a_negative_keep_plan_parameter_is_refused(name):
    with pytest.raises(ValueError, match=name):
        MotionParams(**{name: -0.1})


def test_the_guard_leaves_a_plan_that_passes_a_robot_at_the_planners_clearance_alone():
    """The mpc plan round a standing robot keeps the planner's clearance: the contact guard, whose margin is narrower,
    does not bend it (the drive is the same with the guard off), so the tracker follows its reference."""
    obstacles = [(3.0, 0.2)]
    guarded, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(6.0, 1.0, 0.0), obstacles, seconds=5.0)
    unguarded, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(6.0, 1.0, 0.0), obstacles, seconds=5.0, contact_margin=0.0)
    a, b = (np.array([(p.x, p.y) for p in path]) for path in (guarded, unguarded))
    assert np.linalg.norm(a - b, axis=1).max() < 1e-9
    assert np.linalg.norm(a - obstacles[0], axis=1).min() > 2 * ROBOT_RADIUS + P.clearance - 0.01


@pytest.mark.parametrize("tracker", TRACKERS)
def test_a_robot_sent_onto_another_stops_short_of_contact(tracker):
    """The target is the other robot's own spot: the contact guard stops it ``contact_margin`` short of the hull."""
    other = (3.0, 0.0)
    path, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(*other, 0.0), [other], seconds=5.0, tracker=tracker)
    closest = min(math.dist((p.x, p.y), other) for p in path)
    assert closest > 2 * ROBOT_RADIUS + 0.5 * P.contact_margin
    assert closest < 2 * ROBOT_RADIUS + P.contact_margin + 0.1, "it does press up to the margin"
    loose, _ = drive(Pose2D(0.0, 0.0, 0.0), Pose2D(*other, 0.0), [other], seconds=5.0, tracker=tracker,
                     contact_margin=0.0)
    assert min(math.dist((p.x, p.y), other) for p in loose) < 2 * ROBOT_RADIUS, "without the guard it drives in"


def test_two_robots_driving_at_each_other_both_brake_and_never_touch():
    """Each guards only its own command; together they brake in time, then slide past each other sideways."""
    gap = 2 * ROBOT_RADIUS + P.contact_margin
    a, b = np.array([0.0, 0.0]), np.array([6.0, 0.1])
    va, vb = np.zeros(2), np.zeros(2)
    closest, slowest = math.inf, math.inf
    for _ in range(int(4.0 / DT)):
        want_a = keep_clear(tuple(a), (3.0, 0.0), [tuple(b)], gap, P.contact_brake, P.contact_latency, IN_THE_WAY)
        want_b = keep_clear(tuple(b), (-3.0, 0.0), [tuple(a)], gap, P.contact_brake, P.contact_latency, IN_THE_WAY)
        for v, want in ((va, want_a), (vb, want_b)):  # the base: accelerates at 3, brakes at 5 m/s^2
            dv = np.array(want) - v
            limit = (5.0 if np.linalg.norm(want) < np.linalg.norm(v) else 3.0) * DT
            v += dv * min(1.0, limit / max(np.linalg.norm(dv), 1e-12))
        a, b = a + va * DT, b + vb * DT
        closest, slowest = min(closest, float(np.linalg.norm(a - b))), min(slowest, float(np.linalg.norm(va)))
    assert closest > 2 * ROBOT_RADIUS
    assert slowest < 0.5, "they braked before meeting"


@pytest.mark.parametrize("moved_on", [False, True])
def test_teammates_sprinting_at_each_other_on_packets_four_cycles_old_keep_apart_only_when_moved_on(moved_on):
    """A teammate's packet is 50-70 ms old over ROS when control acts on it (its world model's frame, the team link,
    this robot's world model), and more over a busy team network; a command acts a cycle later. Closing at 6 m/s on
    packets 120 ms old, each sees the other farther than it is by more than the guard's margin, brakes too late and
    they touch. Moved on at its reported velocity for the packet's age (``RobotReport.moved_on``, as ``team_state``
    does), the other is where it is: they stop apart."""
    lag = 4  # cycles, about 120 ms
    gap = 2 * ROBOT_RADIUS + P.contact_margin
    pos, vel = [np.array([0.0, 0.0]), np.array([6.0, 0.05])], [np.zeros(2), np.zeros(2)]
    history: list[tuple[np.ndarray, ...]] = []
    commands = [[np.zeros(2)], [np.zeros(2)]]
    closest, substeps = math.inf, 10
    for _ in range(int(4.0 / DT)):
        history.append(tuple(np.copy(x) for x in (*pos, *vel)))
        seen = history[max(0, len(history) - 1 - lag)]
        age = min(lag, len(history) - 1) * DT
        for me, other, sign in ((0, 1, 1.0), (1, 0, -1.0)):
            report = RobotReport(other + 1, Pose2D(*seen[other]), *seen[2 + other])
            if moved_on:
                report = report.moved_on(age)
            commands[me].append(np.array(keep_clear(tuple(pos[me]), (sign * 3.0, 0.0), [(report.pose.x, report.pose.y)],
                                                    gap, P.contact_brake, P.contact_latency, IN_THE_WAY)))
        for _ in range(substeps):  # the base follows the command of a cycle ago: accelerates at 3.5, brakes at 5 m/s^2
            for v, p, command in zip(vel, pos, commands):
                dv = command[-2] - v
                limit = (5.0 if np.linalg.norm(command[-2]) < np.linalg.norm(v) else 3.5) * DT / substeps
                v += dv * min(1.0, limit / max(np.linalg.norm(dv), 1e-12))
                p += v * DT / substeps
            closest = min(closest, float(np.linalg.norm(pos[0] - pos[1])))
    contact = 2 * ROBOT_RADIUS + 0.03  # what the match report counts as a collision
    if moved_on:
        assert closest > contact
    else:
        assert closest < contact, "the old packets alone let them touch (else this test shows nothing)"


def test_a_teammate_is_moved_on_to_the_control_time_by_its_packet_age():
    me = Teammate(1, True, 0.01, RobotReport(1, Pose2D(0.0, 0.0, 0.0)))
    mate = Teammate(2, True, 0.05, RobotReport(2, Pose2D(2.0, 1.0, 3.1), vx=-2.0, vy=1.0, w=2.0))
    stale = Teammate(3, True, 0.29, RobotReport(3, Pose2D(-2.0, 0.0, 0.0), vx=1.0))
    world = WorldState(10.0, 1, (me, mate, stale), FusedBall(0.0, 0.0), (None,) * 3, (), GameState(), None)
    state = team_state(world, 10.02, 1, FieldGeometry())
    moved, capped = state.mates
    assert (moved.pose.x, moved.pose.y) == pytest.approx((2.0 - 2.0 * 0.07, 1.0 + 0.07))
    assert moved.pose.theta == pytest.approx(3.1 + 0.14 - 2 * math.pi), "heading moved on and wrapped"
    assert capped.pose.x == pytest.approx(-2.0 + MAX_PREDICTION), "moved on by at most MAX_PREDICTION"
    assert state.me.pose == me.report.pose, "this robot's own pose is its world model's"


def test_opponents_are_moved_on_from_the_world_model_s_time_at_their_tracked_velocity():
    me = Teammate(1, True, 0.01, RobotReport(1, Pose2D(0.0, 0.0, 0.0)))
    running = LabelledObstacle(3.0, 1.0, ObstacleLabel.OPPONENT, vx=-2.0, vy=0.5)
    reported = LabelledObstacle(-4.0, 2.0, ObstacleLabel.OPPONENT)  # a teammate's obstacle: no velocity
    mate = LabelledObstacle(1.0, 1.0, ObstacleLabel.TEAMMATE, teammate_id=2, vx=1.0)
    world = WorldState(10.0, 1, (me,), FusedBall(0.0, 0.0), (None,), (running, mate, reported), GameState(), None)
    moved, still = team_state(world, 10.05, 1, FieldGeometry()).opponents
    assert moved == pytest.approx((2.9, 1.025)) and still == (-4.0, 2.0)
    far = team_state(world, 12.0, 1, FieldGeometry()).opponents[0]
    assert far == pytest.approx((3.0 - 2.0 * MAX_PREDICTION, 1.0 + 0.5 * MAX_PREDICTION)), "at most MAX_PREDICTION"


def test_the_guard_leaves_sideways_passing_and_robots_behind_alone():
    gap, brake, latency = 0.6, P.contact_brake, P.contact_latency
    assert keep_clear((0.0, 0.0), (0.0, 2.0), [(0.7, 0.0)], gap, brake, latency, IN_THE_WAY) == (0.0, 2.0)  # sideways
    assert keep_clear((0.0, 0.0), (3.0, 0.0), [(-0.7, 0.0)], gap, brake, latency, IN_THE_WAY) == (3.0, 0.0)  # behind
    wide = keep_clear((0.0, 0.0), (3.0, 0.0), [(2.0, 1.0)], gap, brake, latency, IN_THE_WAY)
    assert wide == (3.0, 0.0)  # the line passes wide
    vx, vy = keep_clear((0.0, 0.0), (3.0, 1.0), [(0.8, 0.0)], gap, brake, latency, IN_THE_WAY)  # 0.2 m of room
    assert vx == pytest.approx(-brake * latency + math.sqrt((brake * latency) ** 2 + 2 * brake * 0.2))
    assert vy == 1.0


def test_an_urgent_step_goes_straight_at_full_acceleration_with_either_tracker_and_the_mpc_plans_anew_after():
    """The goalie stepping into a shot: no plan to make, the whole acceleration limit from the first cycle on."""
    me, target = Pose2D(-8.6, 0.0, 0.0), Pose2D(-8.6, 1.0, 0.0)
    firsts = {}
    for tracker in TRACKERS:
        ctl = MotionController(MotionParams(tracker=tracker), WorldDescription(), DT)
        velocity = ctl.command(me, target, [], DT, urgent=True)
        assert ctl.trajectory is None
        firsts[tracker] = rotate(velocity[0], velocity[1], me.theta)
        if tracker == "mpc":
            ctl.command(me, target, [], DT)
            assert ctl.trajectory is not None, "a plan again once the step is over"
    assert firsts["mpc"] == pytest.approx(firsts["baseline"])
    assert firsts["mpc"] == pytest.approx((0.0, P.max_accel * DT))
    planned = MotionController(MotionParams(tracker="mpc"), WorldDescription(), DT).command(me, target, [], DT)
    assert planned[1] < firsts["mpc"][1], "the plan's first step is the gentler one"


def test_a_robot_beside_its_own_goal_behind_the_line_goes_round_the_goal_not_through_its_net():
    """A robot behind the goal line beside its own goal (where one stayed trapped against the side net for the rest
    of a match, its plan running through the net) reaches a target on the goal's other side round the goal. (The
    baseline tracker heads for its target past robots only: it knows neither posts nor nets.)"""
    field = WorldDescription().field
    start, target = Pose2D(-9.74, 1.56, 0.0), Pose2D(-6.4, -1.66, 0.0)
    path, _ = drive(start, target, [], seconds=10.0)
    back = field.half_length + field.goal_depth + field.post_radius
    side = field.goal_width / 2.0 + field.post_radius
    inside = [p for p in path if field.half_length - ROBOT_RADIUS < -p.x < back + ROBOT_RADIUS
              and abs(p.y) < side + ROBOT_RADIUS]  # the hull across the side net's line
    assert not inside, f"through the goal at {inside[0]}"
    assert math.hypot(path[-1].x - target.x, path[-1].y - target.y) < 0.1


def test_the_goal_frame_is_points_along_the_posts_and_nets_closer_than_the_spacing():
    field = FieldGeometry()
    for side in (1, -1):
        frame = field.goal_frame(side, spacing=0.26)
        assert set(field.goal_posts(side)) <= set(frame)
        assert max(math.dist(a, b) for a, b in zip(frame, frame[1:])) <= 0.26 + 1e-12
        assert all(field.half_length < side * x <= field.half_length + field.goal_depth + field.post_radius + 1e-12
                   for x, _ in frame)
    with pytest.raises(ValueError, match="spacing must be positive"):
        field.goal_frame(1, 0.0)


TABLE_GOLDEN = Path(__file__).resolve().parents[1] / "golden" / "table.npz"


def test_the_compiled_obstacle_table_gives_its_golden_tables():
    """The planner's obstacles as the motion layer made them in 3 seeded lockstep matches of 30 s, recorded by
    ``nubot_tools.golden`` from the Python implementation the compiled one replaced: the same rows in the same order,
    exactly (the same arithmetic)."""
    with np.load(TABLE_GOLDEN) as archive:
        trace = dict(archive)

    def rows(name, i):
        offsets = trace[f"{name}_offsets"]
        return trace[name][offsets[i]:offsets[i + 1]]

    kept_rows = 0
    for i, (mx, my, radius, clearance, planning_range) in enumerate(trace["scalars"]):
        given = [(x, y, keep) if kept else (x, y) for x, y, keep, kept in rows("obstacles", i).tolist()]
        kept_rows += sum(len(o) == 3 for o in given)
        table = obstacle_table((mx, my), given, rows("goals", i), radius, clearance, planning_range)
        np.testing.assert_array_equal(table, rows("table", i), err_msg=f"table {i}")
    assert kept_rows > 0, "the trace must hold obstacles with a distance of their own"


def test_the_obstacle_table_refuses_what_is_no_obstacle():
    goals = np.zeros((0, 3))
    table = obstacle_table((0.0, 0.0), [(1.0, 0.0), (2.0, 0.0, 1.0)], goals, 0.26, 0.25, 8.0)
    np.testing.assert_allclose(table, [[1.0, 0.0, 0.26], [2.0, 0.0, 0.49]], atol=1e-12)  # a robot; a kept distance
    assert obstacle_table((0.0, 0.0), [(9.0, 0.0)], goals, 0.26, 0.25, 8.0).shape == (0, 3), "beyond the range"
    with pytest.raises(ValueError, match="obstacle y must be finite, got nan"):
        obstacle_table((0.0, 0.0), [(1.0, math.nan)], goals, 0.26, 0.25, 8.0)
    with pytest.raises(ValueError, match="obstacle radius must be finite, got inf"):
        obstacle_table((0.0, 0.0), [(1.0, 0.0, math.inf)], goals, 0.26, 0.25, 8.0)
    for bad in ([(1.0,)], [3.0], [("a", 1.0)]):
        with pytest.raises(ValueError, match=r"an obstacle is \(x, y\) or \(x, y, keep\) in numbers"):
            obstacle_table((0.0, 0.0), bad, goals, 0.26, 0.25, 8.0)


GOLDEN = Path(__file__).resolve().parents[1] / "golden"


@pytest.mark.parametrize("name", ["follow.npz", "follow_baseline.npz"])
def test_the_motion_layer_drives_its_golden_sequences_cycle_after_cycle(name):
    """Robots' motion layers over seeded lockstep matches (``python -m nubot_tools.golden follow``: three MPC robots
    over 40 s, one that stepped urgently into a shot, one that held the ball; two baseline robots over 30 s), every
    cycle's inputs replayed in order into a new motion layer: the same commands, references and new plans, cycle
    after cycle, to 1e-9 (a decision taken the other way would part the sequences at once). The compiled cycle, held
    to these sequences recorded from the Python it replaced, differs in the last bit now and then (C's hypot against
    CPython's own): in 8 % of the MPC's cycles, by 8e-15 m/s at most."""
    with np.load(GOLDEN / name) as archive:
        trace = dict(archive)

    def rows(name, i):
        offsets = trace[f"{name}_offsets"]
        return trace[name][offsets[i]:offsets[i + 1]]

    # dt is the MPC's control period; a baseline motion layer has none (NaN in the trace) and takes each cycle's
    layers = [MotionController(MotionParams(**json.loads(str(p))), WorldDescription(), 1 / 33 if math.isnan(dt) else dt)
              for p, dt in zip(trace["params"], trace["dt"].tolist())]
    replans = 0
    for i, (which, kind) in enumerate(zip(trace["tracker"], trace["kind"])):
        ctl = layers[which]
        if kind:
            ctl.reset()
            continue
        x, y, theta, heading, dt, limit, holding, urgent, _ = trace["scalars"][i]
        before = ctl.trajectory
        obstacles = [(ox, oy, keep) if kept else (ox, oy) for ox, oy, keep, kept in rows("obstacles", i).tolist()]
        command = ctl.follow(Pose2D(x, y, theta), [tuple(w) for w in rows("waypoints", i).tolist()], heading,
                             obstacles, dt, None if math.isnan(limit) else limit, bool(holding),
                             [tuple(r) for r in rows("no_go", i).tolist()], bool(urgent))
        answer = trace["answers"][i]
        np.testing.assert_allclose(command, answer[:3], rtol=0.0, atol=1e-9, err_msg=f"cycle {i}: the command")
        reference = (*ctl.reference[0], *ctl.reference[1])
        np.testing.assert_allclose(reference, answer[3:7], rtol=0.0, atol=1e-9, err_msg=f"cycle {i}: the reference")
        new = ctl.trajectory is not None and ctl.trajectory is not before
        assert new == bool(answer[7]), f"cycle {i}: a new plan or not"
        replans += new
    mpc = not math.isnan(trace["dt"][0])
    assert 0.2 * len(trace["kind"]) < replans < 0.8 * len(trace["kind"]) if mpc else replans == 0, "plans made, kept"
    assert trace["scalars"][:, 7].sum() > 0 and trace["scalars"][:, 6].sum() > 0, "urgent steps and a ball held"


@pytest.mark.parametrize("tracker", TRACKERS)
def test_bad_input_to_a_cycle_is_refused_by_name_and_changes_nothing(tracker):
    ctl = MotionController(MotionParams(tracker=tracker), WorldDescription(), DT)
    me, goal = Pose2D(0.0, 0.0, 0.0), [(3.0, 1.0)]
    first = ctl.follow(me, goal, 0.0, [(1.5, 0.5)], DT)
    cases = [
        (dict(me=Pose2D(math.nan, 0.0, 0.0)), "pose x must be finite, got nan"),
        (dict(me=Pose2D(0.0, 0.0, math.inf)), "pose theta must be finite, got inf"),
        (dict(heading=math.nan), "heading must be finite, got nan"),
        (dict(dt=math.inf), "dt must be finite, got inf"),
        (dict(waypoints=[]), "waypoints must not be empty"),
        (dict(waypoints=[(math.inf, 0.0)]), r"waypoints must be finite, got \(inf, 0.0\)"),
        (dict(waypoints=[(1.0,)]), r"waypoints\[0\] must be a point \(x, y\)"),
        (dict(obstacles=[(1.0,)]), r"an obstacle is \(x, y\) or \(x, y, keep\) in numbers"),
        (dict(no_go=[(0.0, 1.0)]), r"an area is \(x0, x1, y0, y1\) in numbers"),
        (dict(obstacles=[(1.0, math.nan)]), "obstacle y must be finite, got nan"),
        (dict(obstacles=[(1.0, 2.0, math.inf)]), "obstacle keep must be finite, got inf"),
        (dict(speed_limit=-1.0), "speed_limit must be positive, got -1.0"),
    ]
    for change, message in cases:
        given = dict(me=me, waypoints=goal, heading=0.0, obstacles=[(1.5, 0.5)], dt=DT) | change
        with pytest.raises(ValueError, match=message):
            ctl.follow(**given)
    again = MotionController(MotionParams(tracker=tracker), WorldDescription(), DT)
    again.follow(me, goal, 0.0, [(1.5, 0.5)], DT)
    assert ctl.follow(me, goal, 0.0, [(1.5, 0.5)], DT) == again.follow(me, goal, 0.0, [(1.5, 0.5)], DT)
    assert first != (0.0, 0.0, 0.0)


def test_a_reset_forgets_the_plan_the_route_and_the_last_command():
    ctl = MotionController(MotionParams(), WorldDescription(), DT)
    for _ in range(10):
        ctl.follow(Pose2D(0.0, 0.0, 0.0), [(3.0, 1.0), (5.0, 0.0)], 1.0, [], DT)
    assert ctl.trajectory is not None and ctl.velocity != (0.0, 0.0) and ctl.w != 0.0 and ctl.waypoints
    ctl.reset()
    assert ctl.trajectory is None and ctl.velocity == (0.0, 0.0) and ctl.w == 0.0 and ctl.waypoints == ()
    assert ctl.position is None and ctl.plan_age == 0.0
    fresh = MotionController(MotionParams(), WorldDescription(), DT)
    pose = Pose2D(1.0, 2.0, 0.5)
    assert ctl.follow(pose, [(4.0, -1.0)], 0.0, [(2.0, 0.0)], DT) == fresh.follow(pose, [(4.0, -1.0)], 0.0,
                                                                                    [(2.0, 0.0)], DT)

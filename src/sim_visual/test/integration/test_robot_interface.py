"""The chapter's robot interface over real ROS: velcmd, BallHandle, Shoot, OmniVisionInfo, world services."""

import math

import pytest

pytestmark = pytest.mark.integration


def test_velocity_command_moves_the_robot_the_expected_distance(sim):
    x0, y0, *_ = sim.state("nubot1")
    sim.wait_sim(0.6, command=(1.5, 0.0, 0.0))  # speed up (one step) and settle
    xa, _, _, _, vxa, *_ = sim.state("nubot1")
    ta = sim.states_clock
    sim.wait_sim(2.0, command=(1.5, 0.0, 0.0))
    xb, yb, *_ = sim.state("nubot1")
    tb = sim.states_clock
    assert vxa == pytest.approx(1.5, abs=0.01)
    assert xb - xa == pytest.approx(1.5 * (tb - ta), abs=0.05)
    assert yb == pytest.approx(y0, abs=0.01)
    sim.wait_sim(1.0)  # no more commands: the 0.5 s command timeout stops the robot
    assert sim.state("nubot1")[4] == pytest.approx(0.0, abs=1e-6)
    assert sim.state("nubot1")[0] > x0 + 3.0


def test_commands_beyond_the_limits_are_clamped(sim):
    sim.wait_sim(0.5, command=(30.0, 40.0, 0.0))
    _, _, _, _, vx, vy, _, _ = sim.state("nubot1")
    assert math.hypot(vx, vy) == pytest.approx(3.5 * 0.5, abs=0.15), "the base speeds up at 3.5 m/s^2"
    assert vy / vx == pytest.approx(40.0 / 30.0, rel=1e-3), "in the commanded direction"
    sim.wait_sim(1.2, command=(30.0, 40.0, 0.0))
    _, _, _, _, vx, vy, _, _ = sim.state("nubot1")
    assert math.hypot(vx, vy) == pytest.approx(5.0, abs=0.01)


def test_nan_command_is_rejected_and_the_robot_keeps_the_last_good_one(sim, sim_launch):
    process, _ = sim_launch
    sim.wait_sim(0.3, command=(1.0, 0.0, 0.0))
    sim.wait_sim(0.2, command=(float("nan"), 0.0, 0.0))
    assert sim.state("nubot1")[4] == pytest.approx(1.0, abs=1e-6), "NaN is ignored: the last good command holds"
    sim.wait_sim(0.6, command=(float("nan"), 0.0, 0.0))
    assert sim.state("nubot1")[4] == pytest.approx(0.0, abs=1e-6), "NaN never refreshes it: the timeout stops it"
    assert all(math.isfinite(v) for v in sim.state("nubot1"))
    sim.wait_for(lambda: "velocity command rejected" in process.log_text(), timeout=5, what="the warning")


def test_ball_handle_refuses_a_far_ball_and_holds_a_near_one_through_a_turn(sim):
    from nubot_common.srv import BallHandle

    ball_handle = sim.service("/nubot1/BallHandle", BallHandle)
    assert ball_handle(1).BallIsHolding == 0, "the ball starts 4 m away"
    ball_handle(0)
    sim.set_model("football", -2.0 + 0.45, 0.05, z=0.11)
    assert ball_handle(1).BallIsHolding == 1
    sim.wait_sim(2.0, command=(0.5, 0.0, 2.0))
    rx, ry, _, ryaw, *_ = sim.state("nubot1")
    bx, by, bz, *_ = sim.state("football")
    assert abs(ryaw) > 0.5, "the robot turned"
    assert (bx, by) == pytest.approx((rx + 0.43 * math.cos(ryaw), ry + 0.43 * math.sin(ryaw)), abs=0.05)
    assert ball_handle(0).BallIsHolding == 0


def test_ground_pass_reaches_the_commanded_speed(sim):
    from nubot_common.srv import BallHandle, Shoot

    sim.set_model("football", -2.0 + 0.45, 0.0, z=0.11)
    assert sim.service("/nubot1/BallHandle", BallHandle)(1).BallIsHolding == 1
    assert sim.service("/nubot1/Shoot", Shoot)(5, -1).ShootIsDone == 1
    sim.wait_sim(0.1)
    _, _, z, _, vx, vy, *_ = sim.state("football")
    assert vy == pytest.approx(0.0, abs=1e-3), "straight ahead"
    assert math.hypot(vx, vy) == pytest.approx(5.0, abs=0.15)
    assert z == pytest.approx(0.11, abs=0.01)
    assert sim.service("/nubot1/Shoot", Shoot)(5, -1).ShootIsDone == 0, "nothing left to kick"


def test_lob_shot_from_six_metres_lands_in_the_goal(sim):
    from nubot_common.srv import BallHandle, Shoot

    sim.set_model("nubot1", 3.0 - 0.43, 0.3)
    sim.set_model("football", 3.0, 0.3, z=0.11)
    assert sim.service("/nubot1/BallHandle", BallHandle)(1).BallIsHolding == 1
    kicked_at = sim.clock
    assert sim.service("/nubot1/Shoot", Shoot)(0, 1).ShootIsDone == 1
    peak = sim.wait_for(lambda: sim.state("football")[2] > 1.0 and sim.state("football")[2], timeout=10,
                        what="the ball in the air")
    assert peak > 1.0
    goal = sim.wait_for(lambda: sim.goals and sim.goals[0], timeout=10, what="a goal")
    assert goal.side == 1 and goal.last_touch == "nubot1"
    assert goal.header.stamp.to_sec() - kicked_at < 3.0


def test_omnivision_info_at_30_hz_near_the_truth(sim):
    sim.set_model("football", 0.0, -1.0, z=0.11)
    sim.vision.clear()
    start = sim.clock
    sim.wait_sim(2.0)
    frames = [m for t, m in sim.vision if t > start + 0.05]
    stamps = [m.header.stamp.to_sec() for m in frames]
    rate = (len(stamps) - 1) / (stamps[-1] - stamps[0])
    assert rate == pytest.approx(30.0, rel=0.05)
    last = frames[-1]
    me = last.robotinfo[0]
    assert me.AgentID == 1 and me.isvalid and not me.isdribble
    assert (me.pos.x, me.pos.y) == pytest.approx((-2.0, 0.0), abs=0.15)
    assert last.ballinfo.pos_known
    assert (last.ballinfo.pos.x, last.ballinfo.pos.y) == pytest.approx((0.0, -1.0), abs=0.4)
    assert last.ballinfo.real_pos.radius == pytest.approx(math.hypot(2.0, 1.0), abs=0.4)
    xs = [m.ballinfo.pos.x for m in frames]
    assert max(xs) - min(xs) > 0.01, "Gaussian noise is on by default"


def test_reset_world_restores_the_initial_state(sim):
    from std_srvs.srv import Empty

    sim.set_model("football", 5.0, 5.0, z=0.11)
    sim.wait_sim(1.0, command=(2.0, 1.0, 1.0))
    sim.service("/sim_visual/reset_world", Empty)()
    sim.wait_sim(0.1)
    x, y, _, yaw, vx, vy, _, w = sim.state("nubot1")
    assert (x, y, yaw, vx, vy, w) == pytest.approx((-2.0, 0.0, 0.0, 0.0, 0.0, 0.0), abs=1e-3)
    bx, by, bz, _, bvx, bvy, *_ = sim.state("football")
    assert (bx, by, bvx, bvy) == pytest.approx((1.0, 2.0, 0.0, 0.0), abs=1e-3)


def test_pause_stops_the_clock_and_unpause_resumes_it(sim):
    from std_srvs.srv import Empty

    sim.service("/sim_visual/pause", Empty)()
    sim.wait_for(lambda: True)
    before = sim.clock
    import time

    time.sleep(0.5)
    assert sim.clock == pytest.approx(before, abs=0.02)
    sim.service("/sim_visual/unpause", Empty)()
    sim.wait_sim(0.3)
    assert sim.clock > before + 0.25


def test_set_model_state_refuses_unknown_models(sim):
    from nubot_common.msg import ModelState
    from nubot_common.srv import SetModelState

    response = sim.service("/sim_visual/set_model_state", SetModelState)(ModelState(model_name="nubot9"))
    assert not response.success and "no robot named 'nubot9'" in response.status_message


def test_dynamic_reconfigure_changes_the_dribble_distance(sim):
    import dynamic_reconfigure.client

    from nubot_common.srv import BallHandle

    client = dynamic_reconfigure.client.Client("/sim_visual", timeout=10)
    try:
        client.update_configuration({"dribble_distance": 0.40})
        sim.set_model("football", -2.0 + 0.45, 0.0, z=0.11)
        assert sim.service("/nubot1/BallHandle", BallHandle)(1).BallIsHolding == 0
        client.update_configuration({"dribble_distance": 0.50})
        assert sim.service("/nubot1/BallHandle", BallHandle)(1).BallIsHolding == 1
    finally:
        client.update_configuration({"dribble_distance": 0.50})
        client.close()


def test_every_node_uses_sim_time(sim):
    import rospy

    assert rospy.get_param("/use_sim_time") is True
    start = sim.clock
    sim.wait_sim(0.5)
    assert sim.clock >= start + 0.5


def test_spawn_and_delete_a_robot_with_its_prefixed_interface(sim):
    import rospy
    from geometry_msgs.msg import Pose

    from nubot_common.msg import OmniVisionInfo, VelCmd
    from nubot_common.srv import DeleteModel, SpawnModel

    pose = Pose()
    pose.position.x, pose.position.y = 4.0, -2.0
    pose.orientation.z, pose.orientation.w = 1.0, 0.0  # facing -x
    spawn = sim.service("/sim_visual/spawn_model", SpawnModel)
    assert spawn("rival2", pose, -1).success
    duplicate = spawn("rival2", pose, -1)
    assert not duplicate.success and "already exists" in duplicate.status_message
    frame = rospy.wait_for_message("/rival2/omnivision/OmniVisionInfo", OmniVisionInfo, timeout=10)
    me = frame.robotinfo[0]
    assert (me.pos.x, me.pos.y) == pytest.approx((-4.0, 2.0), abs=0.15), "the rival team sees its own frame"
    pub = rospy.Publisher("/rival2/nubotcontrol/velcmd", VelCmd, queue_size=1)
    try:
        sim.wait_for(lambda: pub.get_num_connections() > 0, timeout=10, what="the simulator to subscribe")
        end = sim.clock + 1.0
        while sim.clock < end:
            pub.publish(VelCmd(1.0, 0.0, 0.0))
            sim.wait_sim(0.03)
        assert sim.state("rival2")[0] < 3.3, "forward for rival2 is towards -x"
    finally:
        pub.unregister()
    assert sim.service("/sim_visual/delete_model", DeleteModel)("rival2").success
    with sim.lock:
        sim.states.clear()
    sim.wait_sim(0.2)
    assert "rival2" not in sim.states
    assert not sim.service("/sim_visual/delete_model", DeleteModel)("rival2").success


def test_ball_touches_are_published(sim):
    import rospy

    from nubot_common.msg import BallTouch
    from nubot_common.srv import BallHandle

    touches = []
    sub = rospy.Subscriber("/sim_visual/ball_touch", BallTouch, touches.append, queue_size=10)
    try:
        sim.wait_sim(0.3)
        sim.set_model("football", -2.0 + 0.45, 0.0, z=0.11)
        assert sim.service("/nubot1/BallHandle", BallHandle)(1).BallIsHolding == 1
        sim.wait_for(lambda: touches, timeout=5, what="a touch message")
        assert touches[0].robot == "nubot1"
    finally:
        sub.unregister()

// The simulator's physics, the per-step work of it: the compiled core of sim_visual.world.PhysicsWorld (its docstring
// states the model). An ODE world (Debian's libode) with the field's static geometry, the ball and robot cylinders;
// Python describes the field and the surfaces once, this drives the robots, finds the contacts and steps.
// World frame; units SI: m, s, m/s, rad.
#pragma once

#include <ode/ode.h>

#include <array>
#include <chrono>
#include <limits>
#include <utility>
#include <vector>

namespace sim_visual {

// Kinds of geometry (the Python names' order in sim_visual.world._KINDS).
enum Kind : int { kGround = 0, kPost = 1, kNet = 2, kWall = 3, kRobot = 4, kBall = 5, kKinds = 6 };
// What a contact between two kinds is reported as.
enum Pair : int { kOther = 0, kBallRobot = 1, kBallNet = 2 };

// Contact properties of a pair of kinds: friction coefficient, restitution (0: none given), what it reports.
struct Surface {
  bool contacts = false;  // false: the pair never makes contacts
  double mu = 0.0, bounce = 0.0;
  int pair = kOther;
};

struct BallParams {
  double mass, radius, rolling_decel, net_keep, bounce_min_speed, on_ground_tolerance;
};

// The base's limits: linear acceleration and braking [m/s^2], angular acceleration [rad/s^2].
struct DriveLimits {
  double linear_accel, linear_brake, angular_accel;
};

// The base's velocity (vx, vy [m/s], world frame; w [rad/s]) one step of dt [s] after current on its way to wanted:
// the linear change at most linear_brake * dt while the speed falls, else linear_accel * dt; the turn rate's change
// at most angular_accel * dt (sim_visual.rules.limit_drive).
std::array<double, 3> limit_drive(const std::array<double, 3>& current, const std::array<double, 3>& wanted, double dt,
                                  const DriveLimits& limits);

// A robot's stuck detection (the simulator's RobotInfo.isstuck): its ground velocity, low-passed from its displacement
// between updates (a robot pressed against an obstacle keeps its commanded velocity), and since when it has moved at
// less than half a command of at least min_command.
struct StuckState {
  bool has_last = false;
  double last_x = 0.0, last_y = 0.0;        // where it was at the previous update [m]
  double ground_vx = 0.0, ground_vy = 0.0;  // [m/s]
  bool slow = false;
  double slow_since = 0.0;  // [s], when slow
  bool stuck = false;
};

struct StuckParams {
  double min_command;  // commands slower than this never count as stuck [m/s]
  double filter_time;  // time constant of the ground velocity [s]
  double stuck_time;   // slow this long: stuck [s]
};

// The detector one update on: the robot at (x, y) [m] at time [s], dt [s] after the previous update, commanded
// (vx, vy) [m/s] in its body frame.
void update_stuck(StuckState& state, double command_vx, double command_vy, double x, double y, double dt, double time,
                  const StuckParams& params);

// The ball handler (sim_visual.params.PluginParams): how near and how far off its front a robot takes the ball
// (dribble_distance [m], dribble_half_angle [rad]), where a held ball sits (hold_distance [m] ahead), the body
// velocities its grip keeps the ball at (forward, backward, sideways [m/s], turn rate [rad/s]), how long it may move
// faster before the ball slips (hold_slip_time [s]), how long after losing it it cannot take it again
// (kick_recapture_delay [s]), and the ball's radius [m].
struct HandlerParams {
  double dribble_distance, dribble_half_angle, hold_distance;
  double hold_forward_speed, hold_backward_speed, hold_sideways_speed, hold_turn_rate;
  double hold_slip_time, kick_recapture_delay, ball_radius;
};

// Whether the grip keeps the ball at body velocity (vx ahead, vy left [m/s], w [rad/s]) (sim_visual.rules.grip_holds).
bool grip_holds(double vx, double vy, double w, const HandlerParams& params);
// Whether a robot at pose (x, y, theta) can take the ball at (bx, by, bz): low, near and in front enough
// (sim_visual.rules.dribble_condition).
bool dribble_condition(double x, double y, double theta, double bx, double by, double bz, const HandlerParams& params);
// Where the ball a robot at pose (x, y, theta) moving at (vx, vy [m/s] world frame, w [rad/s]) holds sits and how it
// moves: x, y [m], vx, vy [m/s] (sim_visual.rules.held_ball_position, held_ball_velocity).
std::array<double, 4> held_ball(double x, double y, double theta, double vx, double vy, double w,
                                double hold_distance);

// What a robot's base has been told and gives: the last velocity command (body frame) and when it came, what the base
// gives now (world frame), whether its wheels drive it (their own model gives their dynamics: no base limits), and its
// stuck detection.
struct Base {
  std::array<double, 3> command{};  // vx, vy [m/s], w [rad/s]
  double command_time = -std::numeric_limits<double>::infinity();
  std::array<double, 3> drive{};
  bool by_wheels = false;
  StuckState stuck;
  // The ball handler: on or off, when the robot may take the ball again, since when its grip has been slipping.
  bool dribbling = false;
  double no_capture_until = 0.0;
  bool slipping = false;
  double slipping_since = 0.0;
};

// How the bases step: commands older than timeout [s] (0: never) are a stop; the stuck detection runs every
// stuck_every steps (over stuck_every * dt).
struct BaseParams {
  double timeout;
  int stuck_every;
  StuckParams stuck;
  DriveLimits limits;
};

// A body as ODE holds it: position, orientation (w, x, y, z), linear and angular velocity.
using BodyRow = std::array<double, 13>;

class Physics {
 public:
  Physics(double gravity, double erp, double cfm, const BallParams& ball);
  ~Physics();
  Physics(const Physics&) = delete;
  Physics& operator=(const Physics&) = delete;

  // Construction: static geometry (category and collide bits as ODE's), the surface table, then the ball.
  void add_plane(int kind, unsigned category, unsigned collide);
  void add_box(int kind, unsigned category, unsigned collide, const std::array<double, 3>& size,
               const std::array<double, 3>& centre);
  void add_cylinder(int kind, unsigned category, unsigned collide, double radius, double length,
                    const std::array<double, 3>& centre);
  void set_surface(int kind_a, int kind_b, const Surface& surface);
  void add_ball(unsigned category, unsigned collide);

  // Robots: a handle per robot, kept until it is removed.
  int add_robot(double mass, double inertia_zz, double radius, double height, unsigned category, unsigned collide);
  void remove_robot(int robot);
  std::array<double, 6> robot_state(int robot) const;  // x, y, heading, vx, vy, yaw rate
  // Every robot's state, by handle in the order they were added.
  std::vector<std::pair<int, std::array<double, 6>>> robot_states() const;
  void set_robot_state(int robot, const std::array<double, 6>& state);
  double heading(int robot) const;
  void drive(int robot, double vx, double vy, double w, bool world_frame);
  // The robots' bases (what the simulator's model plugin drives): each robot's own, made at rest with add_robot.
  Base& base(int robot);
  const Base& base(int robot) const { return const_cast<Physics*>(this)->base(robot); }
  // Every robot's base one step of dt [s] on at time [s] (steps before: steps): its command (a stop once older than
  // the timeout), the stuck detection when due, the command turned into the world frame by the robot's heading now and
  // reached within the limits from what the base gives now (unless its wheels drive it), then driven.
  void drive_robots(double dt, double time, long steps, const BaseParams& params);

  // The ball handler's parameters, for the calls below.
  void set_handler(const HandlerParams& params) { handler_ = params; }
  // The holder one step of dt [s] on at time [s]: whether its grip lost the ball (it moved faster than the grip keeps
  // it for the slip time): then it cannot take it again for the recapture delay.
  bool grip_slips(int holder, double dt, double time);
  // Whether the robot can take the ball now: its handler on, its recapture delay over, the ball in reach.
  bool can_capture(int robot, double time) const;
  // The first robot, by handle, that can take the ball now; -1: none.
  int first_capture(double time) const;
  // The ball where the holder holds it, moving with it, on the carpet.
  void carry_ball(int holder);

  std::array<double, 9> ball_state() const;  // position, velocity, spin
  void set_ball_state(const std::array<double, 9>& state);
  bool ball_on_ground() const;
  void set_ball_holder(int robot);  // -1: none

  // One step of dt [s]: the robots that touched the ball, by handle, in the order their contacts were found.
  std::vector<int> step(double dt);
  // The wall time [s] spent in step since the world was made: ODE's own part of the simulator's work.
  double step_seconds() const { return step_seconds_; }
  // How often ODE's solver reported "LCP internal error" in this world's steps since it was made (a contact problem
  // it could not solve exactly; ODE prints the message and goes on with what it had).
  long solver_errors() const { return solver_errors_; }
  void note_solver_error() { ++solver_errors_; }

  // What one step of the simulator did to the ball: the robots that touched it (step), whether the holder's grip
  // lost it before the step, the robot that took it after the step (-1: none).
  struct Advance {
    std::vector<int> touched;
    bool slipped = false;
    int captured = -1;
  };
  // One step of the simulator's world, steps steps after the start, at time [s] (= steps * dt): every base driven
  // (drive_robots, with set_base_params' parameters), the holder's grip checked (grip_slips; the ball let go when it
  // slips), the ball's contacts with the holder ignored, the step, then, with no holder, the first robot that can take
  // the ball takes it, and the holder carries it (carry_ball). holder: the robot holding the ball before the step, -1
  // none.
  Advance advance(double dt, double time, long steps, int holder);
  // How advance drives the bases (until set: an error).
  void set_base_params(const BaseParams& params);
  // Whether the ball lies short of both goal lines (|x| < goal_line [m]; set_goal_line, by default everywhere).
  bool ball_short_of_goal_lines() const;
  void set_goal_line(double x);

  BodyRow body(int robot) const;  // -1: the ball
  void set_body(int robot, const BodyRow& row);
  // How often each pair of kinds reached the contact callback since the world was made.
  const std::array<std::array<long, kKinds>, kKinds>& pairs_offered() const { return offered_; }

 private:
  struct Robot {
    dBodyID body = nullptr;
    dGeomID holder = nullptr, cylinder = nullptr;
    Base base;
  };
  struct GeomInfo {
    int kind, robot;
  };
  dGeomID classify(dGeomID geom, int kind, int robot, unsigned category, unsigned collide);
  const Robot& robot_at(int robot) const;
  dBodyID body_at(int robot) const;
  static void near_callback(void* data, dGeomID a, dGeomID b);
  void near(dGeomID a, dGeomID b);
  void absorb_in_net();
  void apply_rolling_resistance(double dt);

  dWorldID world_;
  dSpaceID space_;
  dJointGroupID contacts_;
  BallParams ball_params_;
  dBodyID ball_ = nullptr;
  dGeomID ball_geom_ = nullptr;
  std::vector<dGeomID> static_;
  std::vector<Robot> robots_;
  std::vector<GeomInfo> infos_;  // a geom's data is its index here
  std::array<std::array<Surface, kKinds>, kKinds> surfaces_{};
  std::array<std::array<long, kKinds>, kKinds> offered_{};
  int holder_ = -1;
  HandlerParams handler_{};
  double step_seconds_ = 0.0;
  long solver_errors_ = 0;
  BaseParams base_params_{};
  bool base_params_set_ = false;
  double goal_line_ = std::numeric_limits<double>::infinity();
  bool ball_in_net_ = false;
  std::vector<int> touched_;
};

}  // namespace sim_visual

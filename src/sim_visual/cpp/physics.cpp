// The simulator's physics: see sim_visual/physics.hpp and sim_visual.world.
#include "sim_visual/physics.hpp"

#include "sim_visual/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

namespace sim_visual {

namespace {

constexpr int kMaxContacts = 150;  // contact points asked of one pair

// A contact's surface as the world has always made them: ODE's bounce mode with restitution 0.1 and no threshold
// where the table gives none, the table's restitution above bounce_min_speed where it does.
dContact make_contact(const dContactGeom& geom, const Surface& surface, double bounce_min_speed) {
  dContact contact{};
  contact.surface.mode = dContactBounce;
  contact.surface.mu = surface.mu;
  contact.surface.bounce = 0.1;
  if (surface.bounce > 0.0) {
    contact.surface.bounce = surface.bounce;
    contact.surface.bounce_vel = bounce_min_speed;
  }
  contact.geom = geom;
  return contact;
}

double yaw_of(const dReal* q) {  // ODE's order: w, x, y, z
  return std::atan2(2.0 * (q[0] * q[3] + q[1] * q[2]), 1.0 - 2.0 * (q[2] * q[2] + q[3] * q[3]));
}

// A robot's contacts with one other robot or static body as one: at their mean point, along the deepest one's normal,
// as deep. An upright cylinder meets a box's face or another cylinder along a vertical line, which ODE gives as its
// two ends with one normal; two such contacts are one constraint twice, and a robot pressed between another robot
// and a wall (or into a net's corner) made a system ODE's exact solver could not factor ("LCP internal error").
// Robots are kept upright on the carpet, so the one contact stops them as the two did.
int merge_contacts(dContactGeom* found, int n) {
  dContactGeom merged = found[0];
  for (int i = 1; i < n; ++i) {
    for (int k = 0; k < 3; ++k) merged.pos[k] += found[i].pos[k];
    if (found[i].depth > merged.depth) {
      merged.depth = found[i].depth;
      for (int k = 0; k < 3; ++k) merged.normal[k] = found[i].normal[k];
    }
  }
  for (int k = 0; k < 3; ++k) merged.pos[k] /= n;
  found[0] = merged;
  return 1;
}

// The world whose step is running on this thread (ODE's messages carry no world).
thread_local Physics* stepping = nullptr;

// ODE's messages, printed as its own handler prints them; an "LCP internal error" in a step is counted by the world
// that was stepping.
void on_ode_message(int number, const char* format, va_list args) {
  char text[512];
  std::vsnprintf(text, sizeof text, format, args);
  if (stepping != nullptr && std::strstr(text, "LCP internal error") != nullptr) stepping->note_solver_error();
  std::fprintf(stderr, "ODE Message %d: %s\n", number, text);
}

void check_kind(int kind) {
  if (kind < 0 || kind >= kKinds) throw std::invalid_argument("unknown kind of geometry " + std::to_string(kind));
}

}  // namespace

std::array<double, 3> limit_drive(const std::array<double, 3>& current, const std::array<double, 3>& wanted, double dt,
                                  const DriveLimits& limits) {
  const double vx = current[0], vy = current[1], w = current[2];
  double dvx = wanted[0] - vx, dvy = wanted[1] - vy;
  const double change = std::hypot(dvx, dvy);
  const bool slowing = std::hypot(wanted[0], wanted[1]) < std::hypot(vx, vy);
  const double step = (slowing ? limits.linear_brake : limits.linear_accel) * dt;
  if (change > step) {
    dvx = dvx * step / change;
    dvy = dvy * step / change;
  }
  const double turn = limits.angular_accel * dt;
  return {vx + dvx, vy + dvy, w + std::max(-turn, std::min(turn, wanted[2] - w))};
}

void update_stuck(StuckState& state, double command_vx, double command_vy, double x, double y, double dt, double time,
                  const StuckParams& params) {
  const bool had_last = state.has_last;
  const double last_x = state.last_x, last_y = state.last_y;
  state.has_last = true;
  state.last_x = x;
  state.last_y = y;
  if (!had_last) return;
  const double gain = std::min(1.0, dt / params.filter_time);  // contacts make the position jitter from step to step
  state.ground_vx += gain * ((x - last_x) / dt - state.ground_vx);
  state.ground_vy += gain * ((y - last_y) / dt - state.ground_vy);
  const double wanted = std::hypot(command_vx, command_vy);
  const double actual = std::hypot(state.ground_vx, state.ground_vy);
  if (wanted > params.min_command && actual < 0.5 * wanted) {
    if (!state.slow) {
      state.slow = true;
      state.slow_since = time;
    }
    state.stuck = time - state.slow_since >= params.stuck_time;
  } else {
    state.slow = false;
    state.stuck = false;
  }
}

Physics::Physics(double gravity, double erp, double cfm, const BallParams& ball) : ball_params_(ball) {
  dInitODE2(0);
  dSetMessageHandler(on_ode_message);
  world_ = dWorldCreate();
  dWorldSetGravity(world_, 0.0, 0.0, gravity);
  dWorldSetERP(world_, erp);
  dWorldSetCFM(world_, cfm);
  space_ = dHashSpaceCreate(nullptr);
  contacts_ = dJointGroupCreate(0);
}

Physics::~Physics() {
  dJointGroupDestroy(contacts_);
  for (const Robot& r : robots_) {
    if (r.body == nullptr) continue;
    dGeomDestroy(r.holder);
    dGeomDestroy(r.cylinder);
    dBodyDestroy(r.body);
  }
  dSpaceDestroy(space_);  // destroys the static geometry and the ball's geom with it
  dWorldDestroy(world_);
  dCloseODE();
}

dGeomID Physics::classify(dGeomID geom, int kind, int robot, unsigned category, unsigned collide) {
  check_kind(kind);
  dGeomSetData(geom, reinterpret_cast<void*>(static_cast<std::intptr_t>(infos_.size())));
  infos_.push_back({kind, robot});
  dGeomSetCategoryBits(geom, category);
  dGeomSetCollideBits(geom, collide);
  return geom;
}

void Physics::add_plane(int kind, unsigned category, unsigned collide) {
  static_.push_back(classify(dCreatePlane(space_, 0.0, 0.0, 1.0, 0.0), kind, -1, category, collide));
}

void Physics::add_box(int kind, unsigned category, unsigned collide, const std::array<double, 3>& size,
                      const std::array<double, 3>& centre) {
  dGeomID box = dCreateBox(space_, size[0], size[1], size[2]);
  dGeomSetPosition(box, centre[0], centre[1], centre[2]);
  static_.push_back(classify(box, kind, -1, category, collide));
}

void Physics::add_cylinder(int kind, unsigned category, unsigned collide, double radius, double length,
                           const std::array<double, 3>& centre) {
  dGeomID cylinder = dCreateCylinder(space_, radius, length);
  dGeomSetPosition(cylinder, centre[0], centre[1], centre[2]);
  static_.push_back(classify(cylinder, kind, -1, category, collide));
}

void Physics::set_surface(int kind_a, int kind_b, const Surface& surface) {
  check_kind(kind_a);
  check_kind(kind_b);
  surfaces_[static_cast<std::size_t>(kind_a)][static_cast<std::size_t>(kind_b)] = surface;
}

void Physics::add_ball(unsigned category, unsigned collide) {
  if (ball_ != nullptr) throw std::logic_error("the world has its ball already");
  ball_ = dBodyCreate(world_);
  dMass mass;
  dMassSetZero(&mass);
  dMassSetSphereTotal(&mass, ball_params_.mass, ball_params_.radius);
  dBodySetMass(ball_, &mass);
  ball_geom_ = classify(dCreateSphere(space_, ball_params_.radius), kBall, -1, category, collide);
  dGeomSetBody(ball_geom_, ball_);
}

int Physics::add_robot(double mass_kg, double inertia_zz, double radius, double height, unsigned category,
                       unsigned collide) {
  Robot r;
  r.body = dBodyCreate(world_);
  dMass mass;
  dMassSetZero(&mass);
  // Roll and pitch are set back every step (drive); only I_zz matters.
  dMassSetParameters(&mass, mass_kg, 0.0, 0.0, 0.0, inertia_zz, inertia_zz, inertia_zz, 0.0, 0.0, 0.0);
  dBodySetMass(r.body, &mass);
  dBodySetGravityMode(r.body, 0);
  // The cylinder stands on the carpet inside a transform geom, as in the recorded golden trace (ODE marks transforms
  // deprecated in favour of geom offsets; moving to those is a change of the physics to be measured on its own).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
  r.holder = dCreateGeomTransform(space_);
  dGeomTransformSetCleanup(r.holder, 0);
  r.cylinder = dCreateCylinder(nullptr, radius, height);
  dGeomTransformSetGeom(r.holder, r.cylinder);
#pragma GCC diagnostic pop
  dGeomSetPosition(r.cylinder, 0.0, 0.0, height / 2.0);
  dGeomSetBody(r.holder, r.body);
  const int handle = static_cast<int>(robots_.size());
  classify(r.holder, kRobot, handle, category, collide);
  robots_.push_back(r);
  return handle;
}

const Physics::Robot& Physics::robot_at(int robot) const {
  if (robot < 0 || robot >= static_cast<int>(robots_.size()) ||
      robots_[static_cast<std::size_t>(robot)].body == nullptr) {
    throw std::out_of_range("no robot with handle " + std::to_string(robot));
  }
  return robots_[static_cast<std::size_t>(robot)];
}

dBodyID Physics::body_at(int robot) const {
  if (robot == -1) {
    if (ball_ == nullptr) throw std::logic_error("the world has no ball yet");
    return ball_;
  }
  return robot_at(robot).body;
}

void Physics::remove_robot(int robot) {
  robot_at(robot);
  Robot& r = robots_[static_cast<std::size_t>(robot)];
  if (holder_ == robot) holder_ = -1;
  dGeomDestroy(r.holder);  // leaves its space
  dGeomDestroy(r.cylinder);
  dBodyDestroy(r.body);
  r = Robot{};
}

std::array<double, 6> Physics::robot_state(int robot) const {
  const dBodyID body = robot_at(robot).body;
  const dReal* p = dBodyGetPosition(body);
  const dReal* v = dBodyGetLinearVel(body);
  return {p[0], p[1], yaw_of(dBodyGetQuaternion(body)), v[0], v[1], dBodyGetAngularVel(body)[2]};
}

std::vector<std::pair<int, std::array<double, 6>>> Physics::robot_states() const {
  std::vector<std::pair<int, std::array<double, 6>>> out;
  out.reserve(robots_.size());
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    if (robots_[i].body != nullptr) out.emplace_back(static_cast<int>(i), robot_state(static_cast<int>(i)));
  }
  return out;
}

void Physics::set_robot_state(int robot, const std::array<double, 6>& s) {
  const dBodyID body = robot_at(robot).body;
  dBodySetPosition(body, s[0], s[1], 0.0);
  const dQuaternion q = {std::cos(s[2] / 2.0), 0.0, 0.0, std::sin(s[2] / 2.0)};
  dBodySetQuaternion(body, q);
  dBodySetLinearVel(body, s[3], s[4], 0.0);
  dBodySetAngularVel(body, 0.0, 0.0, s[5]);
}

double Physics::heading(int robot) const { return yaw_of(dBodyGetQuaternion(robot_at(robot).body)); }

void Physics::drive(int robot, double vx, double vy, double w, bool world_frame) {
  const dBodyID body = robot_at(robot).body;
  const dReal* q = dBodyGetQuaternion(body);
  const double yaw = yaw_of(q);
  const double c = std::cos(yaw), s = std::sin(yaw);
  if (q[1] != 0.0 || q[2] != 0.0) {  // a contact tipped it: set it upright
    const dQuaternion upright = {std::cos(yaw / 2.0), 0.0, 0.0, std::sin(yaw / 2.0)};
    dBodySetQuaternion(body, upright);
  }
  const dReal* p = dBodyGetPosition(body);
  if (p[2] != 0.0) dBodySetPosition(body, p[0], p[1], 0.0);  // a contact lifted it: back on the carpet
  if (world_frame) {
    dBodySetLinearVel(body, vx, vy, 0.0);
  } else {
    dBodySetLinearVel(body, c * vx - s * vy, s * vx + c * vy, 0.0);
  }
  dBodySetAngularVel(body, 0.0, 0.0, w);
}

bool grip_holds(double vx, double vy, double w, const HandlerParams& p) {
  return -p.hold_backward_speed <= vx && vx <= p.hold_forward_speed && std::abs(vy) <= p.hold_sideways_speed &&
         std::abs(w) <= p.hold_turn_rate;
}

bool dribble_condition(double x, double y, double theta, double bx, double by, double bz, const HandlerParams& p) {
  if (bz > 2.0 * p.ball_radius) return false;
  if (std::hypot(bx - x, by - y) > p.dribble_distance) return false;
  return std::abs(wrap_angle(std::atan2(by - y, bx - x) - theta)) <= p.dribble_half_angle;
}

std::array<double, 4> held_ball(double x, double y, double theta, double vx, double vy, double w,
                                double hold_distance) {
  const auto at = rotate(hold_distance, 0.0, theta);
  return {x + at[0], y + at[1], vx - w * at[1], vy + w * at[0]};
}

bool Physics::grip_slips(int holder, double dt, double time) {
  Base& b = base(holder);
  const auto body = rotate(b.drive[0], b.drive[1], -heading(holder));
  if (grip_holds(body[0], body[1], b.drive[2], handler_)) {
    b.slipping = false;
    return false;
  }
  if (!b.slipping) {
    b.slipping = true;
    b.slipping_since = time;
  }
  if (time + dt - b.slipping_since < handler_.hold_slip_time - 1e-9) return false;
  b.slipping = false;
  b.no_capture_until = time + handler_.kick_recapture_delay;
  return true;
}

bool Physics::can_capture(int robot, double time) const {
  const Base& b = base(robot);
  if (time < b.no_capture_until) return false;
  const auto r = robot_state(robot);
  const dReal* p = dBodyGetPosition(body_at(-1));
  return dribble_condition(r[0], r[1], r[2], p[0], p[1], p[2], handler_);
}

int Physics::first_capture(double time) const {
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    if (robots_[i].body != nullptr && robots_[i].base.dribbling && can_capture(static_cast<int>(i), time)) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

void Physics::carry_ball(int holder) {
  const auto r = robot_state(holder);
  const auto held = held_ball(r[0], r[1], r[2], r[3], r[4], r[5], handler_.hold_distance);
  set_ball_state({held[0], held[1], handler_.ball_radius, held[2], held[3], 0.0, 0.0, 0.0, 0.0});
}

Base& Physics::base(int robot) {
  robot_at(robot);
  return robots_[static_cast<std::size_t>(robot)].base;
}

void Physics::drive_robots(double dt, double time, long steps, const BaseParams& params) {
  if (params.stuck_every < 1) throw std::invalid_argument("stuck_every must be at least 1");
  const bool stuck_due = steps % params.stuck_every == 0;
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    Robot& r = robots_[i];
    if (r.body == nullptr) continue;
    Base& b = r.base;
    std::array<double, 3> command = b.command;
    if (params.timeout > 0.0 && time - b.command_time > params.timeout) command = {0.0, 0.0, 0.0};
    if (stuck_due) {
      const dReal* p = dBodyGetPosition(r.body);
      update_stuck(b.stuck, command[0], command[1], p[0], p[1], params.stuck_every * dt, time, params.stuck);
    }
    const auto turned = rotate(command[0], command[1], yaw_of(dBodyGetQuaternion(r.body)));
    const std::array<double, 3> wanted = {turned[0], turned[1], command[2]};
    b.drive = b.by_wheels ? wanted : limit_drive(b.drive, wanted, dt, params.limits);
    drive(static_cast<int>(i), b.drive[0], b.drive[1], b.drive[2], true);
  }
}

std::array<double, 9> Physics::ball_state() const {
  const dBodyID ball = body_at(-1);
  const dReal* p = dBodyGetPosition(ball);
  const dReal* v = dBodyGetLinearVel(ball);
  const dReal* w = dBodyGetAngularVel(ball);
  return {p[0], p[1], p[2], v[0], v[1], v[2], w[0], w[1], w[2]};
}

void Physics::set_ball_state(const std::array<double, 9>& s) {
  const dBodyID ball = body_at(-1);
  dBodySetPosition(ball, s[0], s[1], std::max(s[2], ball_params_.radius));
  dBodySetLinearVel(ball, s[3], s[4], s[5]);
  dBodySetAngularVel(ball, s[6], s[7], s[8]);
  const dQuaternion level = {1.0, 0.0, 0.0, 0.0};
  dBodySetQuaternion(ball, level);
}

bool Physics::ball_on_ground() const {
  const dBodyID ball = body_at(-1);
  const bool low = dBodyGetPosition(ball)[2] <= ball_params_.radius + ball_params_.on_ground_tolerance;
  return low && std::abs(dBodyGetLinearVel(ball)[2]) < ball_params_.bounce_min_speed;
}

void Physics::set_ball_holder(int robot) {
  if (robot != -1) robot_at(robot);
  holder_ = robot;
}

std::vector<int> Physics::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw std::invalid_argument("a step must last a positive time");
  body_at(-1);
  const auto start = std::chrono::steady_clock::now();
  touched_.clear();
  ball_in_net_ = false;
  dSpaceCollide(space_, this, &Physics::near_callback);
  stepping = this;
  dWorldStep(world_, dt);  // the exact solver: quickStep reorders constraints with a process-global RNG
  stepping = nullptr;
  dJointGroupEmpty(contacts_);
  if (ball_in_net_) absorb_in_net();
  apply_rolling_resistance(dt);
  step_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return touched_;
}

void Physics::set_base_params(const BaseParams& params) {
  if (params.stuck_every < 1) throw std::invalid_argument("stuck_every must be at least 1");
  base_params_ = params;
  base_params_set_ = true;
}

void Physics::set_goal_line(double x) {
  if (!(x > 0.0)) throw std::invalid_argument("the goal line must lie at a positive x");
  goal_line_ = x;
}

bool Physics::ball_short_of_goal_lines() const { return std::abs(dBodyGetPosition(body_at(-1))[0]) < goal_line_; }

Physics::Advance Physics::advance(double dt, double time, long steps, int holder) {
  if (!base_params_set_) throw std::logic_error("advance needs the bases' parameters first (set_base_params)");
  if (holder >= 0) robot_at(holder);
  Advance out;
  drive_robots(dt, time, steps, base_params_);
  if (holder >= 0 && grip_slips(holder, dt, time)) {
    out.slipped = true;
    holder = -1;
  }
  set_ball_holder(holder);
  out.touched = step(dt);
  if (holder < 0) {
    out.captured = first_capture(static_cast<double>(steps + 1) * dt);  // the time after the step
    holder = out.captured;
  }
  if (holder >= 0) carry_ball(holder);
  return out;
}

void Physics::near_callback(void* data, dGeomID a, dGeomID b) { static_cast<Physics*>(data)->near(a, b); }

void Physics::near(dGeomID a, dGeomID b) {
  const GeomInfo& info_a = infos_[static_cast<std::size_t>(reinterpret_cast<std::intptr_t>(dGeomGetData(a)))];
  const GeomInfo& info_b = infos_[static_cast<std::size_t>(reinterpret_cast<std::intptr_t>(dGeomGetData(b)))];
  ++offered_[static_cast<std::size_t>(info_a.kind)][static_cast<std::size_t>(info_b.kind)];
  const Surface& surface = surfaces_[static_cast<std::size_t>(info_a.kind)][static_cast<std::size_t>(info_b.kind)];
  if (!surface.contacts) return;
  int robot = -1;
  if (surface.pair == kBallRobot) {
    robot = info_a.kind == kRobot ? info_a.robot : info_b.robot;
    if (robot == holder_) return;
  }
  dContactGeom found[kMaxContacts];
  int n = dCollide(a, b, kMaxContacts, found, sizeof(dContactGeom));
  if (n <= 0) return;
  if (n > 1 && info_a.kind != kBall && info_b.kind != kBall) n = merge_contacts(found, n);
  for (int i = 0; i < n; ++i) {
    const dContact contact = make_contact(found[i], surface, ball_params_.bounce_min_speed);
    const dJointID joint = dJointCreateContact(world_, contacts_, &contact);
    dJointAttach(joint, dGeomGetBody(a), dGeomGetBody(b));
  }
  if (robot != -1) {
    if (std::find(touched_.begin(), touched_.end(), robot) == touched_.end()) touched_.push_back(robot);
  } else if (surface.pair == kBallNet) {
    ball_in_net_ = true;
  }
}

void Physics::absorb_in_net() {
  const double keep = ball_params_.net_keep;
  const dReal* v = dBodyGetLinearVel(ball_);
  const dReal* w = dBodyGetAngularVel(ball_);
  const double vz = v[2], wx = w[0], wy = w[1], wz = w[2];
  dBodySetLinearVel(ball_, v[0] * keep, v[1] * keep, vz);
  dBodySetAngularVel(ball_, wx * keep, wy * keep, wz * keep);
}

void Physics::apply_rolling_resistance(double dt) {
  if (!ball_on_ground()) return;
  const dReal* v = dBodyGetLinearVel(ball_);
  const double vx = v[0], vy = v[1], vz = v[2];
  const double speed = std::hypot(vx, vy);
  const double decel = ball_params_.rolling_decel;
  if (speed <= decel * dt) {
    dBodySetLinearVel(ball_, 0.0, 0.0, vz);
    dBodySetAngularVel(ball_, 0.0, 0.0, 0.0);
    return;
  }
  const double scale = (speed - decel * dt) / speed;
  const dReal* w = dBodyGetAngularVel(ball_);
  const double wx = w[0], wy = w[1], wz = w[2];
  dBodySetLinearVel(ball_, vx * scale, vy * scale, vz);
  dBodySetAngularVel(ball_, wx * scale, wy * scale, wz * scale);
}

BodyRow Physics::body(int robot) const {
  const dBodyID body = body_at(robot);
  const dReal* p = dBodyGetPosition(body);
  const dReal* q = dBodyGetQuaternion(body);
  const dReal* v = dBodyGetLinearVel(body);
  const dReal* w = dBodyGetAngularVel(body);
  return {p[0], p[1], p[2], q[0], q[1], q[2], q[3], v[0], v[1], v[2], w[0], w[1], w[2]};
}

void Physics::set_body(int robot, const BodyRow& r) {
  const dBodyID body = body_at(robot);
  dBodySetPosition(body, r[0], r[1], r[2]);
  const dQuaternion q = {r[3], r[4], r[5], r[6]};
  dBodySetQuaternion(body, q);
  dBodySetLinearVel(body, r[7], r[8], r[9]);
  dBodySetAngularVel(body, r[10], r[11], r[12]);
}

}  // namespace sim_visual

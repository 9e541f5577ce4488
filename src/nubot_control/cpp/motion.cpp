// The motion layer's cycle (see include/nubot_control/motion.hpp and nubot_control/motion.py).
#include "nubot_control/motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "nubot_control/format.hpp"
#include "nubot_control/trajectory.hpp"

namespace nubot_control {
namespace {

constexpr int kMaxDetours = 3;           // sub_target: obstacles passed one after the other at most
constexpr double kPassed = 0.3;          // the baseline drops a waypoint this close [m]
constexpr double kNear = 4.0;            // the baseline heeds obstacles this close [m]
constexpr double kPush = 3.0;            // the baseline's push from an obstacle already too close [1/s]
constexpr double kExitSpeed = 0.8;       // stay_out: out of an area at least this fast [m/s] (areas._EXIT_SPEED)
constexpr double kAheadClose = 0.1;      // a waypoint this close is passed [m]
constexpr double kAheadBehind = 1.0;     // ... and one this close behind [m]
constexpr double kPi = 3.14159265358979323846;

double wrap_angle(double angle) {
  double wrapped = std::fmod(angle + kPi, 2.0 * kPi);
  if (wrapped <= 0.0) wrapped += 2.0 * kPi;
  return wrapped - kPi;
}

// (x, y) rotated counter-clockwise by angle.
Vec2 rotate(double x, double y, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * x - s * y, s * x + c * y};
}

// Distance from P to segment AB, and the position (0..1) of the closest point along AB.
std::pair<double, double> segment_distance(double px, double py, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay;
  const double length2 = dx * dx + dy * dy;
  const double t = length2 < 1e-12 ? 0.0 : std::max(0.0, std::min(1.0, ((px - ax) * dx + (py - ay) * dy) / length2));
  return {std::hypot(ax + t * dx - px, ay + t * dy - py), t};
}

void require_finite(double value, const char* name) {
  if (!std::isfinite(value)) throw std::invalid_argument(std::string(name) + " must be finite, got " + format_float(value));
}

void require_positive(double value, const char* name) {
  if (!(value > 0.0)) throw std::invalid_argument(std::string(name) + " must be positive, got " + format_float(value));
}

// The waypoints not yet passed from start moving at velocity: passed within kAheadClose, or within kAheadBehind and
// behind.
std::vector<Vec2> ahead(const Vec2& start, const Vec2& velocity, std::vector<Vec2>::const_iterator first,
                        std::vector<Vec2>::const_iterator last) {
  while (first != last) {
    const double gx = first->x(), gy = first->y();
    const double close = std::hypot(gx - start.x(), gy - start.y());
    const bool behind = (gx - start.x()) * velocity.x() + (gy - start.y()) * velocity.y() < 0.0;
    if (!(close < kAheadClose || (behind && close < kAheadBehind))) break;
    ++first;
  }
  return {first, last};
}

}  // namespace

void obstacle_table(double mx, double my, const Eigen::Ref<const Rows3>& goals, const std::vector<Sighting>& sightings,
                    double robot_radius, double clearance, double planning_range, std::vector<double>& out) {
  const auto add = [&](double x, double y, double radius) {
    if (std::hypot(x - mx, y - my) < planning_range) out.insert(out.end(), {x, y, radius});
  };
  for (Eigen::Index i = 0; i < goals.rows(); ++i) add(goals(i, 0), goals(i, 1), goals(i, 2));
  for (const Sighting& s : sightings) {
    // std::max(0.0, nan) is 0.0, as Python's max(0.0, nan) is: a kept distance that is NaN asks for no clearance
    const double radius = s.kept ? std::max(0.0, s.keep - robot_radius - clearance) : robot_radius;
    const double row[3] = {s.x, s.y, radius};
    const char* names[3] = {"x", "y", "radius"};
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(row[c])) {
        throw std::invalid_argument(std::string("obstacle ") + names[c] + " must be finite, got " +
                                    format_float(row[c]));
      }
    }
    add(s.x, s.y, radius);
  }
}

Vec2 sub_target(const Vec2& start, const Vec2& goal, const std::vector<Sighting>& obstacles, double clearance) {
  Vec2 target = goal;
  for (int detour = 0; detour < kMaxDetours; ++detour) {
    bool blocked = false;
    double best_along = 0.0, bx = 0.0, by = 0.0, bkeep = 0.0;
    for (const Sighting& o : obstacles) {
      const double keep = o.kept ? o.keep : clearance;
      if (std::hypot(o.x - start.x(), o.y - start.y()) < 1e-6) continue;
      const auto [distance, t] = segment_distance(o.x, o.y, start.x(), start.y(), target.x(), target.y());
      if (distance < keep && 0.0 < t && t < 1.0) {
        const double along = t * std::hypot(target.x() - start.x(), target.y() - start.y());
        if (!blocked || along < best_along) {
          blocked = true;
          best_along = along, bx = o.x, by = o.y, bkeep = keep;
        }
      }
    }
    if (!blocked) return target;
    const double dx = target.x() - start.x(), dy = target.y() - start.y();
    const double norm = std::hypot(dx, dy);
    const double nx = -dy / norm, ny = dx / norm;  // left of the path
    const double side = (start.x() - bx) * nx + (start.y() - by) * ny >= 0.0 ? 1.0 : -1.0;
    const double offset = bkeep * 1.2;
    target = {bx + side * nx * offset, by + side * ny * offset};
  }
  return target;
}

Vec2 keep_clear(const Vec2& position, const Vec2& velocity, const std::vector<Vec2>& robots, double min_distance,
                double brake, double latency, double in_the_way) {
  double vx = velocity.x(), vy = velocity.y();
  const double bt = brake * latency;
  for (int round = 0; round < 3; ++round) {  // limiting towards one robot can add speed towards another
    bool changed = false;
    const double speed = std::hypot(vx, vy);
    if (speed < 1e-9) break;
    for (const Vec2& robot : robots) {
      const double dx = robot.x() - position.x(), dy = robot.y() - position.y();
      const double distance = std::hypot(dx, dy);
      if (distance < 1e-6) continue;
      const double towards = (vx * dx + vy * dy) / distance;
      const double wide = std::abs(vx * dy - vy * dx) / speed - min_distance;
      if (towards <= 0.0 || wide >= in_the_way) continue;
      const double room = std::max(distance - min_distance, 0.0);
      double allowed = -bt + std::sqrt(bt * bt + 2.0 * brake * room);
      if (wide > 0.0) allowed += towards > allowed ? (towards - allowed) * wide / in_the_way : 0.0;
      if (towards > allowed + 1e-9) {
        const double cut = towards - allowed;
        vx = vx - cut * dx / distance, vy = vy - cut * dy / distance;
        changed = true;
      }
    }
    if (!changed) break;
  }
  return {vx, vy};
}

Vec2 stay_out(const Vec2& position, const Vec2& velocity, const std::vector<Rect>& rects, double brake,
              double latency) {
  const double x = position.x(), y = position.y();
  double vx = velocity.x(), vy = velocity.y();
  const double bt = brake * latency;
  for (const Rect& r : rects) {
    if (r.x0 < x && x < r.x1 && r.y0 < y && y < r.y1) {  // inside: out by the nearest side
      const std::tuple<double, double, double> exits[4] = {
          {x - r.x0, -1.0, 0.0}, {r.x1 - x, 1.0, 0.0}, {y - r.y0, 0.0, -1.0}, {r.y1 - y, 0.0, 1.0}};
      const auto& [gap, nx, ny] = *std::min_element(std::begin(exits), std::end(exits));
      (void)gap;
      const double outward = vx * nx + vy * ny;
      if (outward < kExitSpeed) vx = vx + (kExitSpeed - outward) * nx, vy = vy + (kExitSpeed - outward) * ny;
      continue;
    }
    const double qx = std::min(std::max(x, r.x0), r.x1), qy = std::min(std::max(y, r.y0), r.y1);
    const double gap = std::hypot(qx - x, qy - y);
    if (gap < 1e-9) continue;
    const double nx = (qx - x) / gap, ny = (qy - y) / gap;
    const double towards = vx * nx + vy * ny;
    const double allowed = -bt + std::sqrt(bt * bt + 2.0 * brake * gap);
    if (towards > allowed) vx = vx - (towards - allowed) * nx, vy = vy - (towards - allowed) * ny;
  }
  return {vx, vy};
}

double dribble_scale(double bx, double by, const MotionParams& p) {
  double scale = 1.0;
  if (bx > p.dribble_speed) {
    scale = p.dribble_speed / bx;
  } else if (bx < -p.dribble_back_speed) {
    scale = p.dribble_back_speed / -bx;
  }
  if (std::abs(by) > p.dribble_side_speed) scale = std::min(scale, p.dribble_side_speed / std::abs(by));
  return scale;
}

MotionCore::MotionCore(const MotionParams& params, const PlannerParams& planner, double robot_radius,
                       const Bounds& bounds, Rows3 goal_table, LaguerreMpc* mpc, double accel_rounding,
                       double intrusion_tolerance)
    : params_(params),
      planner_(planner),
      robot_radius_(robot_radius),
      bounds_(bounds),
      goal_table_(std::move(goal_table)),
      mpc_(mpc),
      accel_rounding_(accel_rounding),
      intrusion_tolerance_(intrusion_tolerance) {}

void MotionCore::reset() {
  velocity_ = Vec2::Zero();
  w_ = 0.0;
  has_plan_ = false;
  has_reference_ = false;
  given_.clear();
  waypoints_.clear();
  plan_goals_.clear();
  plan_limit_ = plan_accel_ = 0.0;
  plan_age_ = 0.0;
  plan_keepable_ = false;
}

Eigen::Vector3d MotionCore::follow(const Pose& me, const std::vector<Vec2>& waypoints, double heading,
                                   const std::vector<Sighting>& obstacles, double dt,
                                   std::optional<double> speed_limit, bool holding, const std::vector<Rect>& no_go,
                                   bool urgent) {
  require_finite(me.x, "pose x");
  require_finite(me.y, "pose y");
  require_finite(me.theta, "pose theta");
  require_finite(heading, "heading");
  require_finite(dt, "dt");
  if (waypoints.empty()) throw std::invalid_argument("waypoints must not be empty: the last one is the goal");
  for (const Vec2& w : waypoints) {
    if (!w.allFinite()) {
      throw std::invalid_argument("waypoints must be finite, got (" + format_float(w.x()) + ", " +
                                  format_float(w.y()) + ")");
    }
  }
  for (const Sighting& o : obstacles) {
    require_finite(o.x, "obstacle x");
    require_finite(o.y, "obstacle y");
    if (o.kept) require_finite(o.keep, "obstacle keep");
  }
  const MotionParams& p = params_;
  // none, or 0, is no limit of its own (as Python's ``speed_limit or max_speed``); a NaN limit is passed over by min
  const double asked = speed_limit.has_value() && *speed_limit != 0.0 ? *speed_limit : p.max_speed;
  if (!(asked > 0.0) && !std::isnan(asked)) {
    throw std::invalid_argument("speed_limit must be positive, got " + format_float(asked));
  }
  const double limit = std::min(std::min(p.max_speed, asked),
                                holding ? p.dribble_speed : std::numeric_limits<double>::infinity());
  const double accel = holding ? p.dribble_accel : p.max_accel;
  // Every check is made before anything changes: a refused cycle leaves the motion layer as it was.
  std::vector<Vec2> goals;
  goals.reserve(waypoints.size());
  for (const Vec2& w : waypoints) goals.push_back(bounds_.clamp(w));
  if (urgent) has_plan_ = false, plan_keepable_ = false;
  Vec2 v;
  if (mpc_ != nullptr && !urgent) {
    v = track(me, goals, obstacles, dt, limit, accel);
  } else {
    if (goals != given_) given_ = goals, waypoints_ = goals;  // a new route; else go on with what remains of it
    while (waypoints_.size() > 1 && std::hypot(waypoints_[0].x() - me.x, waypoints_[0].y() - me.y) < kPassed) {
      waypoints_.erase(waypoints_.begin());
    }
    v = baseline(me, waypoints_[0], obstacles, dt, limit, accel);
  }
  const Vec2 at(me.x, me.y);
  if (!no_go.empty()) v = stay_out(at, v, no_go, p.contact_brake, p.contact_latency);
  if (p.contact_margin > 0.0) {
    std::vector<Vec2> robots;
    for (const Sighting& o : obstacles) {
      if (!o.kept) robots.emplace_back(o.x, o.y);
    }
    // A line that keeps the planner's clearance is left alone: the guard does not bend a plan that avoids the
    // robots, it stops what drives into one.
    v = keep_clear(at, v, robots, 2.0 * robot_radius_ + p.contact_margin, p.contact_brake, p.contact_latency,
                   std::max(p.clearance - p.contact_margin, 0.0));
  }
  Vec2 body = rotate(v.x(), v.y(), -me.theta);
  if (holding) {
    const double scale = dribble_scale(body.x(), body.y(), p);
    body *= scale;
    v *= scale;
  }
  velocity_ = v;
  const double err = wrap_angle(heading - me.theta);
  const double turn = holding ? p.dribble_rot_speed : p.max_rot_speed;
  const double w_want = std::max(-turn, std::min(turn, p.heading_gain * err));
  w_ += std::max(-p.max_rot_accel * dt, std::min(p.max_rot_accel * dt, w_want - w_));
  w_ = std::max(-turn, std::min(turn, w_));
  return {body.x(), body.y(), w_};
}

void MotionCore::state_at(double time, Vec2& position, Vec2& velocity) const {
  Eigen::VectorXd times(1);
  times(0) = time;
  Rows2 xy, v;
  trajectory_states(plan_.t, plan_.xy, plan_.v, times, xy, v);
  position = xy.row(0).transpose();
  velocity = v.row(0).transpose();
}

Vec2 MotionCore::track(const Pose& me, const std::vector<Vec2>& goals, const std::vector<Sighting>& obstacles,
                       double dt, double limit, double accel) {
  plan_age_ += dt;
  std::vector<double> rows;
  rows.reserve(3 * (static_cast<std::size_t>(goal_table_.rows()) + obstacles.size()));
  obstacle_table(me.x, me.y, goal_table_, obstacles, robot_radius_, params_.clearance, params_.planning_range, rows);
  const Rows3 table = Eigen::Map<const Rows3>(rows.data(), static_cast<Eigen::Index>(rows.size() / 3), 3);
  if (plan_holds(me, goals, table, limit, accel)) {
    Vec2 start, start_velocity;
    state_at(plan_age_, start, start_velocity);
    std::vector<Vec2> remaining = ahead(start, start_velocity, waypoints_.begin(),
                                        waypoints_.empty() ? waypoints_.end() : waypoints_.end() - 1);
    remaining.push_back(goals.back());
    given_ = goals;
    waypoints_ = std::move(remaining);
  } else {
    replan(me, goals, table, limit, accel);
  }
  const MpcParams& mp = mpc_->params();
  const int horizon = mp.horizon;
  Eigen::VectorXd times(horizon + 1);
  for (int k = 0; k <= horizon; ++k) times(k) = plan_age_ + static_cast<double>(k) * mp.dt;
  Rows2 ref_positions, ref_velocities;
  trajectory_states(plan_.t, plan_.xy, plan_.v, times, ref_positions, ref_velocities);
  has_reference_ = true;
  reference_position_ = ref_positions.row(0).transpose();
  reference_velocity_ = ref_velocities.row(0).transpose();
  const RowMatrix positions = ref_positions;
  const RowMatrix velocities = ref_velocities.topRows(horizon);
  return mpc_->command(Eigen::Vector2d(me.x, me.y), velocity_, positions, velocities, std::min(limit, mp.max_speed),
                       std::min(accel, mp.max_accel));
}

bool MotionCore::plan_holds(const Pose& me, const std::vector<Vec2>& goals, const Rows3& table, double limit,
                            double accel) const {
  const MotionParams& p = params_;
  if (!has_plan_ || !plan_keepable_ || plan_age_ >= p.keep_plan_time || limit != plan_limit_ || accel != plan_accel_) {
    return false;
  }
  if (goals.size() != plan_goals_.size()) return false;
  for (std::size_t i = 0; i < goals.size(); ++i) {
    const double gx = goals[i].x(), gy = goals[i].y(), hx = plan_goals_[i].x(), hy = plan_goals_[i].y();
    const double shift = p.keep_plan_goal_shift + p.keep_plan_goal_share * std::hypot(gx - me.x, gy - me.y);
    if (std::hypot(gx - hx, gy - hy) > shift) return false;
  }
  Vec2 ref, ref_v;
  state_at(plan_age_, ref, ref_v);
  if (std::hypot(ref.x() - me.x, ref.y() - me.y) > p.keep_plan_deviation) return false;
  if (table.rows() == 0) return true;
  const double* begin = plan_.t.data();
  const Eigen::Index after = std::upper_bound(begin, begin + plan_.t.size(), plan_age_) - begin;
  const Eigen::Index first = std::max<Eigen::Index>(after - 1, 0);
  std::vector<Vec2> ends;
  ends.reserve(goals.size() + 1);
  ends.emplace_back(me.x, me.y);
  ends.insert(ends.end(), goals.begin(), goals.end());
  std::vector<Disc> discs;
  discs.reserve(static_cast<std::size_t>(table.rows()));
  for (Eigen::Index i = 0; i < table.rows(); ++i) discs.push_back({table(i, 0), table(i, 1), table(i, 2)});
  return keeps_clear(plan_.xy.bottomRows(plan_.xy.rows() - first), ends, discs, robot_radius_ + p.clearance,
                     intrusion_tolerance_);
}

void MotionCore::replan(const Pose& me, std::vector<Vec2> goals, const Rows3& table, double limit, double accel) {
  const MotionParams& p = params_;
  const std::vector<Vec2> given = goals;
  Vec2 start(me.x, me.y), start_velocity = velocity_;
  if (has_plan_ && !given_.empty() &&
      std::hypot(given_.back().x() - goals.back().x(), given_.back().y() - goals.back().y()) < p.replan_tolerance) {
    Vec2 ref, ref_v;
    state_at(plan_age_, ref, ref_v);  // where the last plan has the robot now
    if (std::hypot(ref.x() - me.x, ref.y() - me.y) < p.replan_tolerance) start = ref, start_velocity = ref_v;
    if (goals.size() == given_.size()) {  // the same route, on track or not: the waypoints still ahead
      std::vector<Vec2> remaining = ahead(start, start_velocity, waypoints_.begin(),
                                          waypoints_.empty() ? waypoints_.end() : waypoints_.end() - 1);
      remaining.push_back(goals.back());
      goals = std::move(remaining);
    }
  }
  given_ = given;
  waypoints_ = goals;
  PlannerParams planner = planner_;
  planner.robot_radius = robot_radius_;
  planner.safety_margin = p.clearance;
  planner.max_speed = limit * p.plan_share;
  planner.max_accel = accel * p.plan_share;
  planner.max_lateral_accel = p.max_lateral_accel * p.plan_share;
  require_positive(planner.max_speed, "max_speed");
  require_positive(planner.max_accel, "max_accel");
  require_positive(planner.max_lateral_accel, "max_lateral_accel");
  std::vector<Disc> discs;
  discs.reserve(static_cast<std::size_t>(table.rows()));
  for (Eigen::Index i = 0; i < table.rows(); ++i) discs.push_back({table(i, 0), table(i, 1), table(i, 2)});
  plan_ = nubot_control::plan(start, goals, discs, planner, bounds_, start_velocity, 0.0);
  has_plan_ = true;
  ++plan_count_;
  plan_goals_ = given;
  plan_limit_ = limit, plan_accel_ = accel;
  plan_age_ = 0.0;
  plan_keepable_ = within_accel(plan_.t, plan_.v, p.keep_plan_time, accel, accel_rounding_);
}

Vec2 MotionCore::baseline(const Pose& me, const Vec2& goal, const std::vector<Sighting>& obstacles, double dt,
                          double limit, double accel) {
  const MotionParams& p = params_;
  const double clearance = 2.0 * robot_radius_ + p.clearance;
  std::vector<Sighting> near;
  for (const Sighting& o : obstacles) {
    if (std::hypot(o.x - me.x, o.y - me.y) < kNear) near.push_back(o);
  }
  const Vec2 aim = sub_target(Vec2(me.x, me.y), goal, near, clearance);
  const double dx = aim.x() - me.x, dy = aim.y() - me.y;
  const double dist_goal = std::hypot(goal.x() - me.x, goal.y() - me.y);
  const double dist = std::hypot(dx, dy);
  const double speed = std::min(std::min(limit, std::sqrt(2.0 * accel * dist_goal)), p.position_gain * dist_goal);
  double want_x = 0.0, want_y = 0.0;
  if (dist > 1e-3) want_x = dx / dist * speed, want_y = dy / dist * speed;
  for (const Sighting& o : near) {  // push away from anything already too close
    const double keep = o.kept ? o.keep : clearance;
    const double gap = std::hypot(me.x - o.x, me.y - o.y);
    if (1e-6 < gap && gap < keep) {
      const double push = (keep - gap) * kPush;
      want_x = want_x + (me.x - o.x) / gap * push, want_y = want_y + (me.y - o.y) / gap * push;
    }
  }
  double dvx = want_x - velocity_.x(), dvy = want_y - velocity_.y();
  const double dv = std::hypot(dvx, dvy);
  const double step = accel * dt;
  if (dv > step) dvx = dvx / dv * step, dvy = dvy / dv * step;
  double vx = velocity_.x() + dvx, vy = velocity_.y() + dvy;
  const double v = std::hypot(vx, vy);
  if (v > limit) vx = vx / v * limit, vy = vy / v * limit;
  has_reference_ = true;
  reference_position_ = goal;
  reference_velocity_ = Vec2::Zero();
  return {vx, vy};
}

}  // namespace nubot_control

// The motion layer's cycle, compiled (see nubot_control.motion.MotionController, whose docstrings state the rules).
// Units SI: m, s, m/s, m/s^2, rad. Team frame unless said otherwise.
#pragma once

#include <Eigen/Dense>

#include <optional>
#include <vector>

#include "nubot_control/mpc.hpp"
#include "nubot_control/path_planning.hpp"

namespace nubot_control {

// An obstacle as the motion layer sees it this cycle: where it is [m] and, for one that asks for its own clearance
// (``kept``), how far its centre must stay from the robot's (keep [m]); else a robot's footprint.
struct Sighting {
  double x, y, keep;
  bool kept;
};

// An area the robot must stay out of: x0 < x < x1, y0 < y < y1 [m].
struct Rect {
  double x0, x1, y0, y1;
};

// The robot's pose: position [m], heading [rad].
struct Pose {
  double x, y, theta;
};

// nubot_control.params.MotionParams, the numbers the cycle reads (mpc: the tracker is "mpc").
struct MotionParams {
  bool mpc;
  double max_speed, max_accel, max_lateral_accel, max_rot_speed, max_rot_accel;
  double dribble_speed, dribble_back_speed, dribble_side_speed, dribble_rot_speed, dribble_accel;
  double replan_tolerance, keep_plan_deviation, keep_plan_goal_shift, keep_plan_goal_share, keep_plan_time;
  double plan_share, planning_range, position_gain, heading_gain, clearance;
  double contact_margin, contact_brake, contact_latency;
};

// The planner's obstacle table: the goals' rows, then one row per sighting (a robot: the robot's own radius; a kept
// distance: the disc that leaves it, max(0, keep - robot_radius - clearance)), only the rows whose centre lies within
// planning_range of (mx, my). Each row (x, y, radius) [m], appended to ``out`` (k, 3), row-major.
// A sighting that is not finite throws std::invalid_argument naming the field ("obstacle x must be finite, got nan").
void obstacle_table(double mx, double my, const Eigen::Ref<const Rows3>& goals, const std::vector<Sighting>& sightings,
                    double robot_radius, double clearance, double planning_range, std::vector<double>& out);

// The first point to head for from start to goal round the obstacles (a sighting's keep when kept, else clearance).
Vec2 sub_target(const Vec2& start, const Vec2& goal, const std::vector<Sighting>& obstacles, double clearance);

// The velocity without what would bring the robot within min_distance of one of the robots (nubot_control.motion's
// keep_clear states the rule).
Vec2 keep_clear(const Vec2& position, const Vec2& velocity, const std::vector<Vec2>& robots, double min_distance,
                double brake, double latency, double in_the_way);

// The velocity without what would take the robot into one of the rects (nubot_control.areas.stay_out).
Vec2 stay_out(const Vec2& position, const Vec2& velocity, const std::vector<Rect>& rects, double brake,
              double latency);

// The factor (at most 1) that brings the body velocity within what the ball handler keeps.
double dribble_scale(double bx, double by, const MotionParams& p);

// One robot's motion layer: the plan it follows and the commands of its cycles.
class MotionCore {
 public:
  // planner: the planner's fixed parameters (sample_step, max_subtargets, detour_factor); the limits and gaps come
  // from params each plan. mpc: the tracker of the mpc path (not owned; nullptr for the baseline tracker).
  MotionCore(const MotionParams& params, const PlannerParams& planner, double robot_radius, const Bounds& bounds,
             Rows3 goal_table, LaguerreMpc* mpc, double accel_rounding, double intrusion_tolerance);

  // Forget the plan, the route and the last command.
  void reset();

  // One cycle's body-frame command (vx, vy, w) along waypoints (the last the goal), ending facing heading. Throws
  // std::invalid_argument on input that is not finite, no waypoint, or limits the planner refuses.
  Eigen::Vector3d follow(const Pose& me, const std::vector<Vec2>& waypoints, double heading,
                         const std::vector<Sighting>& obstacles, double dt, std::optional<double> speed_limit,
                         bool holding, const std::vector<Rect>& no_go, bool urgent);

  bool has_plan() const { return has_plan_; }
  const PlanResult& plan() const { return plan_; }
  long plan_count() const { return plan_count_; }  // grows with every plan made: which plan is followed
  double plan_age() const { return plan_age_; }
  bool has_reference() const { return has_reference_; }
  const Vec2& reference_position() const { return reference_position_; }
  const Vec2& reference_velocity() const { return reference_velocity_; }
  const std::vector<Vec2>& waypoints() const { return waypoints_; }
  const Vec2& velocity() const { return velocity_; }
  double w() const { return w_; }

 private:
  Vec2 track(const Pose& me, const std::vector<Vec2>& goals, const std::vector<Sighting>& obstacles, double dt,
             double limit, double accel);
  bool plan_holds(const Pose& me, const std::vector<Vec2>& goals, const Rows3& table, double limit,
                  double accel) const;
  void replan(const Pose& me, std::vector<Vec2> goals, const Rows3& table, double limit, double accel);
  Vec2 baseline(const Pose& me, const Vec2& goal, const std::vector<Sighting>& obstacles, double dt, double limit,
                double accel);
  void state_at(double time, Vec2& position, Vec2& velocity) const;

  MotionParams params_;
  PlannerParams planner_;
  double robot_radius_;
  Bounds bounds_;
  Rows3 goal_table_;
  LaguerreMpc* mpc_;
  double accel_rounding_, intrusion_tolerance_;

  Vec2 velocity_ = Vec2::Zero();  // last commanded velocity [m/s]
  double w_ = 0.0;                // last commanded turn rate [rad/s]
  bool has_plan_ = false;
  PlanResult plan_;
  long plan_count_ = 0;
  bool has_reference_ = false;
  Vec2 reference_position_ = Vec2::Zero(), reference_velocity_ = Vec2::Zero();
  std::vector<Vec2> given_;       // the route asked for last cycle
  std::vector<Vec2> waypoints_;   // what remains of it
  std::vector<Vec2> plan_goals_;  // the route asked for when the plan was made
  double plan_limit_ = 0.0, plan_accel_ = 0.0;  // the limits it was made under
  double plan_age_ = 0.0;
  bool plan_keepable_ = false;
};

}  // namespace nubot_control

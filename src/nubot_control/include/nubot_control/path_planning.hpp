// Online path planning for the omnidirectional robot, the compiled core of nubot_control.path_planning (its module
// docstring states the four steps: subtargets, the cubic B-spline, the clearance and bounds corrections, the speed
// profile). Units SI: m, s, m/s, m/s^2.
#pragma once

#include <Eigen/Dense>

#include <vector>

namespace nubot_control {

using Vec2 = Eigen::Vector2d;
using Rows2 = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;  // (n, 2) points or velocities, as numpy
using Rows3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;  // (k, 3) rows: obstacles (x, y, radius)

struct PlannerParams {
  double robot_radius;
  double safety_margin;
  double max_speed;
  double max_accel;
  double max_lateral_accel;
  double sample_step;
  int max_subtargets;
  double detour_factor;
};

struct Bounds {
  double x_min, x_max, y_min, y_max;
  Vec2 clamp(const Vec2& p) const;
  bool contains(const Vec2& p) const;
};

struct Disc {
  double x, y, radius;
};

// Samples of a planned path about sample_step apart in arc length.
struct PlanResult {
  Eigen::VectorXd t;                                   // (n,) time from the plan's start [s]
  Eigen::VectorXd s;                                   // (n,) arc length [m]
  Rows2 xy;                                            // (n, 2) positions [m]
  Rows2 v;                                             // (n, 2) velocities [m/s]
  std::vector<Vec2> via;                               // the route the spline was fitted through
};

// Via-points between start and goal (both excluded) so that each segment keeps every obstacle's clearance.
std::vector<Vec2> subtargets(const Vec2& start, const Vec2& goal, const std::vector<Disc>& obstacles,
                             const PlannerParams& params, const Bounds& bounds);

// The trajectory start -> (subtargets) -> waypoints (the last the goal); the inputs as nubot_control.path_planning.plan
// has checked them (finite; waypoints not empty, inside the bounds; end_speed >= 0).
PlanResult plan(const Vec2& start, const std::vector<Vec2>& waypoints, const std::vector<Disc>& obstacles,
                const PlannerParams& params, const Bounds& bounds, const Vec2& start_velocity, double end_speed);

// Whether every point of path stays margin + radius - tolerance or farther from the centre of each obstacle whose
// margin + radius holds none of ends (as the planner does, an obstacle holding the robot or a waypoint is not
// avoided). Squared distances are compared, as nubot_control.path_planning.keeps_clear's golden trace was made.
bool keeps_clear(const Eigen::Ref<const Rows2>& path, const std::vector<Vec2>& ends,
                 const std::vector<Disc>& obstacles, double margin, double tolerance);

}  // namespace nubot_control

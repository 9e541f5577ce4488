// The motion layer's per-cycle glue, compiled (see nubot_control.motion.MotionController). Units SI.
#pragma once

#include <Eigen/Dense>

#include <vector>

#include "nubot_control/path_planning.hpp"

namespace nubot_control {

// An obstacle as the motion layer sees it this cycle: where it is [m] and, for one that asks for its own clearance
// (``kept``), how far its centre must stay from the robot's (keep [m]); else a robot's footprint.
struct Sighting {
  double x, y, keep;
  bool kept;
};

// The planner's obstacle table: the goals' rows, then one row per sighting (a robot: the robot's own radius; a kept
// distance: the disc that leaves it, max(0, keep - robot_radius - clearance)), only the rows whose centre lies within
// planning_range of (mx, my). Each row (x, y, radius) [m], appended to ``out`` (k, 3), row-major.
// A sighting that is not finite throws std::invalid_argument naming the field ("obstacle x must be finite, got nan").
void obstacle_table(double mx, double my, const Eigen::Ref<const Rows3>& goals, const std::vector<Sighting>& sightings,
                    double robot_radius, double clearance, double planning_range, std::vector<double>& out);

}  // namespace nubot_control

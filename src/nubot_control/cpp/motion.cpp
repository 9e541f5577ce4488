// The motion layer's per-cycle glue (see include/nubot_control/motion.hpp).
#include "nubot_control/motion.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "nubot_control/format.hpp"

namespace nubot_control {

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

}  // namespace nubot_control

// Obstacle merging and labelling: see include/world_model/labels.hpp and world_model/obstacles.py.
#include "world_model/labels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace world_model {

namespace {

// nubot_common.geometry.wrap_angle, the same operations in the same order: into (-pi, pi]
double wrap_angle(double angle) {
  double wrapped = std::fmod(angle + M_PI, 2.0 * M_PI);
  if (wrapped <= 0.0) wrapped += 2.0 * M_PI;
  return wrapped - M_PI;
}

}  // namespace

std::vector<Labelled> label_obstacles(const std::array<double, 3>& me, int agent_id, const std::vector<Point>& own,
                                      std::vector<Seen> reported, std::vector<Seen> mates, double teammate_radius,
                                      double merge_radius) {
  const auto by_id = [](const Seen& a, const Seen& b) { return a.agent_id < b.agent_id; };
  std::stable_sort(reported.begin(), reported.end(), by_id);  // observers in order, each one's obstacles as given
  mates.erase(std::remove_if(mates.begin(), mates.end(), [agent_id](const Seen& m) { return m.agent_id == agent_id; }),
              mates.end());
  std::stable_sort(mates.begin(), mates.end(), by_id);
  std::vector<Labelled> merged;
  merged.reserve(own.size() + reported.size());
  for (const Point& p : own) merged.push_back({p[0], p[1], agent_id, 0, 0.0, 0.0});
  for (const Seen& r : reported) {
    if (std::hypot(r.x - me[0], r.y - me[1]) <= teammate_radius) continue;  // the teammate sees this robot
    const bool known = std::any_of(merged.begin(), merged.end(), [&](const Labelled& q) {
      return std::hypot(r.x - q.x, r.y - q.y) <= merge_radius;
    });
    if (!known) merged.push_back({r.x, r.y, r.agent_id, 0, 0.0, 0.0});
  }
  for (Labelled& o : merged) {
    o.angle = wrap_angle(std::atan2(o.y - me[1], o.x - me[0]) - me[2]);
    o.radius = std::hypot(o.x - me[0], o.y - me[1]);
    double best = std::numeric_limits<double>::infinity();
    for (const Seen& m : mates) {
      const double d = std::hypot(o.x - m.x, o.y - m.y);
      if (d <= teammate_radius && d < best) {
        o.teammate = m.agent_id;
        best = d;
      }
    }
  }
  return merged;
}

}  // namespace world_model

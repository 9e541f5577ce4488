// The obstacle tracker's compiled core: see include/world_model/obstacles.hpp and world_model/obstacles.py.
#include "world_model/obstacles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace world_model {

ObstacleTracker::ObstacleTracker(double gate, double position_gain, double velocity_gain, double coast,
                                 double max_speed)
    : gate_(gate),
      position_gain_(position_gain),
      velocity_gain_(velocity_gain),
      coast_(coast),
      max_speed_(max_speed),
      stamp_(-std::numeric_limits<double>::infinity()) {}

void ObstacleTracker::reset() {
  tracks_.clear();
  stamp_ = -std::numeric_limits<double>::infinity();
}

void ObstacleTracker::update(double stamp, const std::vector<Point>& percepts) {
  if (!(stamp > stamp_)) return;
  stamp_ = stamp;
  std::vector<Track> tracks;
  for (const Track& k : tracks_) {
    if (stamp - k.stamp <= coast_) tracks.push_back(k);
  }
  std::vector<Point> predicted;
  for (const Track& k : tracks) {
    predicted.push_back({k.x + k.vx * (stamp - k.stamp), k.y + k.vy * (stamp - k.stamp)});
  }
  // every track-percept pair within the gate, the closest first
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < predicted.size(); ++i) {
    for (std::size_t j = 0; j < percepts.size(); ++j) {
      const double d = std::hypot(percepts[j][0] - predicted[i][0], percepts[j][1] - predicted[i][1]);
      if (d <= gate_) pairs.emplace_back(d, i, j);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> taken_track(tracks.size(), false), taken(percepts.size(), false);
  for (const auto& [d, i, j] : pairs) {
    if (taken_track[i] || taken[j]) continue;
    taken_track[i] = taken[j] = true;
    Track& k = tracks[i];
    const double px = predicted[i][0], py = predicted[i][1];
    const double dt = stamp - k.stamp;
    k.n += 1;  // a young track weighs its few percepts as a straight-line fit would, then the steady gains
    const double a = std::max(position_gain_, 2.0 * (2 * k.n - 1) / (k.n * (k.n + 1)));
    const double b = std::max(velocity_gain_, 6.0 / (k.n * (k.n + 1)));
    const double rx = percepts[j][0] - px, ry = percepts[j][1] - py;
    double vx = k.vx + b * rx / dt, vy = k.vy + b * ry / dt;
    const double speed = std::hypot(vx, vy);
    if (speed > max_speed_) {
      vx = vx * max_speed_ / speed;
      vy = vy * max_speed_ / speed;
    }
    k = Track{px + a * rx, py + a * ry, vx, vy, stamp, k.n};
  }
  for (std::size_t j = 0; j < percepts.size(); ++j) {
    if (!taken[j]) tracks.push_back(Track{percepts[j][0], percepts[j][1], 0.0, 0.0, stamp, 1});
  }
  tracks_ = std::move(tracks);
}

void ObstacleTracker::estimate(double t, std::vector<Point>& positions, std::vector<Point>& velocities) const {
  positions.clear();
  velocities.clear();
  for (const Track& k : tracks_) {
    if (stamp_ - k.stamp > coast_) continue;
    positions.push_back({k.x + k.vx * (t - k.stamp), k.y + k.vy * (t - k.stamp)});
    velocities.push_back({k.vx, k.vy});
  }
}

}  // namespace world_model

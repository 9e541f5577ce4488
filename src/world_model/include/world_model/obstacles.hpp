// Own obstacle percepts followed from frame to frame: the compiled core of world_model.obstacles.ObstacleTracker
// (its docstring states the association, the alpha-beta filter and the coast).
#pragma once

#include <array>
#include <vector>

namespace world_model {

using Point = std::array<double, 2>;

class ObstacleTracker {
 public:
  ObstacleTracker(double gate, double position_gain, double velocity_gain, double coast, double max_speed);

  void reset();
  // The obstacles of the frame taken at stamp [s]; a frame not newer than the last is ignored.
  void update(double stamp, const std::vector<Point>& percepts);
  // The tracks of the last coast [s] before the latest frame, moved on to t [s]: positions and velocities.
  void estimate(double t, std::vector<Point>& positions, std::vector<Point>& velocities) const;

 private:
  struct Track {
    double x, y, vx, vy, stamp;
    int n;
  };
  double gate_, position_gain_, velocity_gain_, coast_, max_speed_;
  std::vector<Track> tracks_;
  double stamp_;
};

}  // namespace world_model

// The simulator's synthetic omni vision for many robots at once (see sim_visual/sensing.py): what each robot would
// perceive of itself, the ball and the other robots, in its team frame, with Gaussian noise drawn by the caller.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace sim_visual {

using RobotRow = std::array<double, 6>;  // x, y [m], theta [rad], vx, vy [m/s], w [rad/s]; world frame
using BallRow = std::array<double, 4>;   // x, y [m], vx, vy [m/s]; world frame

struct VisionNoise {
  double position_std;       // ball and obstacle positions [m]
  double velocity_std;       // ball and robot velocities [m/s]
  double self_position_std;  // own position [m]
  double heading_std;        // own heading [rad]
  double vision_range;       // objects farther are not seen [m]; 0 unlimited
};

// One robot's frame, team frame: its estimated pose and velocity, the ball if seen, the robots it sees.
struct VisionFrame {
  std::array<double, 5> robot;  // x, y, theta, vx, vy
  bool ball_seen;
  std::array<double, 4> ball;                   // x, y, vx, vy
  std::vector<std::array<double, 2>> obstacles;  // x, y
};

// How many standard normal numbers each observer's frame takes: 6 for itself and 4 per object in range (the ball,
// then every other robot in the order of robots). observers index robots; attacks are +1 or -1, one per observer.
std::vector<std::size_t> vision_draws(const std::vector<RobotRow>& robots, const BallRow& ball,
                                      const std::vector<int>& observers, const std::vector<int>& attacks,
                                      double vision_range);

// The observers' frames from normals (as many as vision_draws gives in all, in its order).
std::vector<VisionFrame> vision_frames(const std::vector<RobotRow>& robots, const BallRow& ball,
                                       const std::vector<int>& observers, const std::vector<int>& attacks,
                                       const VisionNoise& noise, const double* normals, std::size_t count);

}  // namespace sim_visual

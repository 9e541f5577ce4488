// The simulator's synthetic omni vision (sim_visual/include/sim_visual/sensing.hpp). The arithmetic follows
// nubot_common.geometry and TeamFrame operation by operation, so that a frame is the same to the last bit.
#include "sim_visual/sensing.hpp"

#include "sim_visual/geometry.hpp"

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

namespace sim_visual {
namespace {

struct Pose {
  double x, y, theta;
};

// A world point or vector in a team's frame: the field turned half round for a team attacking -x.
std::array<double, 2> to_team(double x, double y, int attack) {
  return attack == 1 ? std::array<double, 2>{x, y} : std::array<double, 2>{-x, -y};
}

Pose truth_of(const RobotRow& me, int attack) {
  const auto [tx, ty] = to_team(me[0], me[1], attack);
  return {tx, ty, attack == 1 ? me[2] : wrap_angle(me[2] + kPi)};
}

// The object at world (wx, wy) relative to the pose, in its body frame.
std::array<double, 2> relative(const Pose& pose, double wx, double wy, int attack) {
  const auto [px, py] = to_team(wx, wy, attack);
  return rotate(px - pose.x, py - pose.y, -pose.theta);
}

bool in_range(const std::array<double, 2>& body, double vision_range) {
  return !(vision_range > 0.0 && std::hypot(body[0], body[1]) > vision_range);
}

void check(const std::vector<RobotRow>& robots, const std::vector<int>& observers, const std::vector<int>& attacks) {
  if (observers.size() != attacks.size()) throw std::invalid_argument("one attack per observer");
  for (std::size_t i = 0; i < observers.size(); ++i) {
    if (observers[i] < 0 || static_cast<std::size_t>(observers[i]) >= robots.size()) {
      throw std::invalid_argument("observer " + std::to_string(observers[i]) + " is not one of the " +
                                  std::to_string(robots.size()) + " robots");
    }
    if (attacks[i] != 1 && attacks[i] != -1) throw std::invalid_argument("attack must be 1 or -1");
  }
}

}  // namespace

std::vector<std::size_t> vision_draws(const std::vector<RobotRow>& robots, const BallRow& ball,
                                      const std::vector<int>& observers, const std::vector<int>& attacks,
                                      double vision_range) {
  check(robots, observers, attacks);
  std::vector<std::size_t> draws;
  draws.reserve(observers.size());
  for (std::size_t i = 0; i < observers.size(); ++i) {
    const auto me = static_cast<std::size_t>(observers[i]);
    const Pose truth = truth_of(robots[me], attacks[i]);
    std::size_t n = 6;
    if (in_range(relative(truth, ball[0], ball[1], attacks[i]), vision_range)) n += 4;
    for (std::size_t j = 0; j < robots.size(); ++j) {
      if (j != me && in_range(relative(truth, robots[j][0], robots[j][1], attacks[i]), vision_range)) n += 4;
    }
    draws.push_back(n);
  }
  return draws;
}

std::vector<VisionFrame> vision_frames(const std::vector<RobotRow>& robots, const BallRow& ball,
                                       const std::vector<int>& observers, const std::vector<int>& attacks,
                                       const VisionNoise& noise, const double* normals, std::size_t count) {
  check(robots, observers, attacks);
  std::vector<VisionFrame> frames;
  frames.reserve(observers.size());
  std::size_t k = 0;
  auto take = [&](std::size_t n) {
    if (k + n > count) throw std::invalid_argument("too few normal numbers for the frames");
    const double* d = normals + k;
    k += n;
    return d;
  };
  for (std::size_t i = 0; i < observers.size(); ++i) {
    const int attack = attacks[i];
    const auto me_index = static_cast<std::size_t>(observers[i]);
    const RobotRow& me = robots[me_index];
    const Pose truth = truth_of(me, attack);
    const auto [tvx, tvy] = to_team(me[3], me[4], attack);
    const double* n = take(6);
    const Pose est{truth.x + noise.self_position_std * n[0], truth.y + noise.self_position_std * n[1],
                   wrap_angle(truth.theta + noise.heading_std * n[2])};
    VisionFrame frame{{est.x, est.y, est.theta, tvx + noise.velocity_std * n[3], tvy + noise.velocity_std * n[4]},
                      false, {0.0, 0.0, 0.0, 0.0}, {}};
    frame.obstacles.reserve(robots.size());
    // An object in range: where the noisy measurement relative to the robot lands with the noisy pose.
    auto seen = [&](double wx, double wy, double wvx, double wvy) -> std::optional<std::array<double, 4>> {
      const auto body = relative(truth, wx, wy, attack);
      if (!in_range(body, noise.vision_range)) return std::nullopt;
      const double* d = take(4);
      const auto w = rotate(body[0] + noise.position_std * d[0], body[1] + noise.position_std * d[1], est.theta);
      const auto [vx, vy] = to_team(wvx, wvy, attack);
      return std::array<double, 4>{est.x + w[0], est.y + w[1], vx + noise.velocity_std * d[2],
                                   vy + noise.velocity_std * d[3]};
    };
    if (const auto b = seen(ball[0], ball[1], ball[2], ball[3])) {
      frame.ball_seen = true;
      frame.ball = *b;
    }
    for (std::size_t j = 0; j < robots.size(); ++j) {
      if (j == me_index) continue;
      if (const auto o = seen(robots[j][0], robots[j][1], robots[j][3], robots[j][4])) {
        frame.obstacles.push_back({(*o)[0], (*o)[1]});
      }
    }
    frames.push_back(std::move(frame));
  }
  if (k != count) throw std::invalid_argument("more normal numbers than the frames take");
  return frames;
}

}  // namespace sim_visual

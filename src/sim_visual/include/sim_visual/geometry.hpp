// Plane geometry as nubot_common.geometry computes it, operation by operation (the compiled pieces answer as the
// Python ones they replaced, to the last bit).
#pragma once

#include <array>
#include <cmath>

namespace sim_visual {

constexpr double kPi = 3.14159265358979323846;

// An angle [rad] into (-pi, pi].
inline double wrap_angle(double angle) {
  double wrapped = std::fmod(angle + kPi, 2.0 * kPi);
  if (wrapped <= 0.0) wrapped += 2.0 * kPi;
  return wrapped - kPi;
}

// The vector (x, y) turned counter-clockwise by angle [rad].
inline std::array<double, 2> rotate(double x, double y, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * x - s * y, s * x + c * y};
}

}  // namespace sim_visual

// A planned trajectory read back (see include/nubot_control/trajectory.hpp).
#include "nubot_control/trajectory.hpp"

#include <algorithm>
#include <cmath>

namespace nubot_control {

void trajectory_states(const Eigen::Ref<const Eigen::VectorXd>& t, const Eigen::Ref<const Rows2>& xy,
                       const Eigen::Ref<const Rows2>& v, const Eigen::Ref<const Eigen::VectorXd>& times, Rows2& out_xy,
                       Rows2& out_v) {
  const Eigen::Index n = t.size(), m = times.size();
  out_xy.resize(m, 2);
  out_v.resize(m, 2);
  if (n == 1) {
    out_xy.rowwise() = xy.row(0);
    out_v.rowwise() = v.row(0);
    return;
  }
  const double* begin = t.data();
  for (Eigen::Index k = 0; k < m; ++k) {
    const double clipped = std::min(std::max(times(k), 0.0), t(n - 1));
    const Eigen::Index after = std::upper_bound(begin, begin + n, clipped) - begin;
    const Eigen::Index i = std::min(std::max(after - 1, Eigen::Index{0}), n - 2);
    const double frac = (clipped - t(i)) / (t(i + 1) - t(i));
    const double v0 = std::hypot(v(i, 0), v(i, 1)), v1 = std::hypot(v(i + 1, 0), v(i + 1, 1));
    const double along = frac * (2.0 * v0 + (v1 - v0) * frac) / std::max(v0 + v1, 1e-12);
    for (int c = 0; c < 2; ++c) {
      out_xy(k, c) = xy(i, c) + along * (xy(i + 1, c) - xy(i, c));
      out_v(k, c) = v(i, c) + frac * (v(i + 1, c) - v(i, c));
    }
  }
}

bool within_accel(const Eigen::Ref<const Eigen::VectorXd>& t, const Eigen::Ref<const Rows2>& v, double until,
                  double accel, double rounding) {
  const double* begin = t.data();
  const Eigen::Index soon = std::min<Eigen::Index>(std::upper_bound(begin, begin + t.size(), until) - begin + 1,
                                                   t.size());
  for (Eigen::Index i = 1; i < soon; ++i) {
    const double dx = v(i, 0) - v(i - 1, 0), dy = v(i, 1) - v(i - 1, 1);
    const double reach = accel * (1.0 + rounding) * (t(i) - t(i - 1));
    if (!(dx * dx + dy * dy <= reach * reach)) return false;
  }
  return true;
}

}  // namespace nubot_control

// The path planner's compiled core: see include/nubot_control/path_planning.hpp and nubot_control/path_planning.py.
#include "nubot_control/path_planning.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace nubot_control {
namespace {

constexpr double kSamePoint = 0.01;       // route points closer than this are one point [m]
constexpr double kDirectionSpeed = 0.1;   // a start velocity faster than this sets the spline's direction [m/s]
constexpr int kMaxRefits = 6;             // spline refits per plan to restore clearances and bounds
constexpr double kTolerance = 0.005;      // clearance violations smaller than this are left alone [m]
constexpr double kBoundsTolerance = 0.05; // bounds violations up to this are only clipped [m]
constexpr double kMinViaGap = 0.1;        // a corrective via-point nearer than this moves the route point [m]
constexpr double kMinTurnSin = 0.05;      // tangents meeting at a sharper angle than this count as parallel
constexpr double kMaxSpan = 1.5;          // longer route segments get points along them [m]
constexpr double kMinSpeed = 1e-3;        // floor of the curvature speed limit [m/s]
constexpr double kMinAlong = 0.2;         // the share of max_accel always left for speeding up and braking
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kDegree = 3;

using Points = Rows2;

double dist(const Vec2& a, const Vec2& b) { return std::hypot(a.x() - b.x(), a.y() - b.y()); }

// The obstacles as arrays: centres, clearances, their squares, detour radii and cluster labels.
struct Scene {
  Points centres;
  Eigen::VectorXd clear, clear2, detour;
  Eigen::VectorXi labels;

  Scene(const std::vector<Disc>& obstacles, const PlannerParams& p) {
    const Eigen::Index k = static_cast<Eigen::Index>(obstacles.size());
    centres.resize(k, 2);
    clear.resize(k);
    for (Eigen::Index j = 0; j < k; ++j) {
      const Disc& d = obstacles[static_cast<std::size_t>(j)];
      centres(j, 0) = d.x;
      centres(j, 1) = d.y;
      clear(j) = p.robot_radius + p.safety_margin + d.radius;
    }
    clear2 = clear.array().square();
    detour = p.detour_factor * clear;
    labels = clusters();
  }

  Eigen::Index size() const { return clear.size(); }

  bool inside(const Vec2& point, Eigen::Index j) const {
    const double rx = point.x() - centres(j, 0), ry = point.y() - centres(j, 1);
    return rx * rx + ry * ry < clear2(j);
  }

  // Each obstacle's cluster, by its lowest member: obstacles closer than the sum of their detour radii are
  // connected, transitively. A search over those connections from each obstacle not yet in a cluster, lowest first:
  // k^2 distance checks (the goals' frames alone are dozens of obstacles).
  Eigen::VectorXi clusters() const {
    const Eigen::Index k = size();
    Eigen::VectorXi labels_ = Eigen::VectorXi::Constant(k, -1);
    std::vector<Eigen::Index> open;
    for (Eigen::Index first = 0; first < k; ++first) {
      if (labels_(first) >= 0) continue;
      labels_(first) = static_cast<int>(first);
      open.assign(1, first);
      while (!open.empty()) {
        const Eigen::Index i = open.back();
        open.pop_back();
        for (Eigen::Index j = first + 1; j < k; ++j) {
          if (labels_(j) >= 0) continue;
          const double dx = centres(i, 0) - centres(j, 0), dy = centres(i, 1) - centres(j, 1);
          const double r = detour(i) + detour(j);
          if (dx * dx + dy * dy < r * r) {
            labels_(j) = static_cast<int>(first);
            open.push_back(j);
          }
        }
      }
    }
    return labels_;
  }
};

// The obstacle whose clearance segment a-b enters first (-1 if none), and which obstacles count for the segment
// (those whose clearance contains neither a nor b).
Eigen::Index first_blocking(const Vec2& a, const Vec2& b, const Scene& scene, std::vector<bool>& active) {
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  const double length2 = dx * dx + dy * dy;
  const Eigen::Index k = scene.size();
  active.assign(static_cast<std::size_t>(k), false);
  std::vector<double> ra2(static_cast<std::size_t>(k)), rd(static_cast<std::size_t>(k));
  for (Eigen::Index j = 0; j < k; ++j) {
    const double rx = scene.centres(j, 0) - a.x(), ry = scene.centres(j, 1) - a.y();
    const std::size_t u = static_cast<std::size_t>(j);
    ra2[u] = rx * rx + ry * ry;
    rd[u] = rx * dx + ry * dy;
    active[u] = ra2[u] >= scene.clear2(j) && ra2[u] - 2.0 * rd[u] + length2 >= scene.clear2(j);
  }
  if (length2 < 1e-12) return -1;
  Eigen::Index best = -1;
  double best_entry = kInf;
  for (Eigen::Index j = 0; j < k; ++j) {
    const std::size_t u = static_cast<std::size_t>(j);
    const double clear2 = scene.clear2(j);
    // with both ends outside, the segment enters a clearance iff its closest point to the centre is inside
    const double perp2 = ra2[u] - rd[u] * rd[u] / length2;
    if (!(active[u] && perp2 < clear2 * (1.0 - 1e-9) && rd[u] > 0.0 && rd[u] < length2)) continue;
    const double entry = rd[u] - std::sqrt(std::max(clear2 - perp2, 0.0) * length2);
    if (entry < best_entry || best < 0) {
      best = j;
      best_entry = entry;
    }
  }
  return best;
}

// Sweep from angle 0 upwards across the overlapping angular intervals [lo, hi] (also taken one turn later); the
// first angle outside them, or >= pi.
double turn(const std::vector<double>& lo, const std::vector<double>& hi) {
  std::vector<double> lo2(lo), hi2(hi);
  for (double x : lo) lo2.push_back(x + 2.0 * M_PI);
  for (double x : hi) hi2.push_back(x + 2.0 * M_PI);
  double theta = 0.0;
  bool moved = true;
  while (moved && theta < M_PI) {
    moved = false;
    for (std::size_t i = 0; i < lo2.size(); ++i) {
      if (lo2[i] <= theta && theta < hi2[i]) {
        theta = hi2[i];
        moved = true;
      }
    }
  }
  return theta;
}

// A subtarget beside obstacle k, and the rest of its cluster, on the better side of the segment a-b.
Vec2 detour_point(const Vec2& a, const Vec2& b, Eigen::Index k, const std::vector<bool>& active, const Scene& scene,
                  const Bounds& bounds) {
  const double ax = a.x(), ay = a.y();
  const double length = std::hypot(b.x() - ax, b.y() - ay);
  const double ux = (b.x() - ax) / length, uy = (b.y() - ay) / length;
  const double nx = -uy, ny = ux;
  std::vector<Eigen::Index> members;
  for (Eigen::Index j = 0; j < scene.size(); ++j) {
    if (active[static_cast<std::size_t>(j)] && scene.labels(j) == scene.labels(k)) members.push_back(j);
  }
  // the cluster's angular shadow seen from a (end 0, looking at b) and from b (end 1, looking at a)
  std::vector<double> lo[2], hi[2];
  double hi_max = -kInf, lo_min = kInf;
  const Vec2 ends[2] = {a, b};
  for (int e = 0; e < 2; ++e) {
    for (Eigen::Index j : members) {
      const double rx = scene.centres(j, 0) - ends[e].x(), ry = scene.centres(j, 1) - ends[e].y();
      double along = rx * ux + ry * uy;
      if (e == 1) along *= -1.0;
      const double side = rx * nx + ry * ny;
      const double d = std::hypot(along, side);
      // an end between clearance and detour radius: the tangent only keeps halfway between them
      const double keep = d > scene.detour(j) ? scene.detour(j) : 0.5 * (scene.clear(j) + d);
      const double half = std::asin(std::min(keep / d, 1.0));
      const double centre = std::atan2(side, along);
      lo[e].push_back(centre - half);
      hi[e].push_back(centre + half);
      hi_max = std::max(hi_max, centre + half);
      lo_min = std::min(lo_min, centre - half);
    }
  }
  double left[2], right[2];
  if (hi_max < M_PI && lo_min > -M_PI) {
    // the shadow is one arc round 0 that stays in front of both ends: its edges are the extremes
    for (int e = 0; e < 2; ++e) {
      left[e] = *std::max_element(hi[e].begin(), hi[e].end());
      right[e] = -*std::min_element(lo[e].begin(), lo[e].end());
    }
  } else {
    for (int e = 0; e < 2; ++e) {
      std::vector<double> neg_hi, neg_lo;
      for (double x : hi[e]) neg_hi.push_back(-x);
      for (double x : lo[e]) neg_lo.push_back(-x);
      left[e] = turn(lo[e], hi[e]);
      right[e] = turn(neg_hi, neg_lo);
    }
  }
  Vec2 points[2];
  const double signs[2] = {1.0, -1.0};
  for (int i = 0; i < 2; ++i) {
    const double sign = signs[i];
    const double turn_a = i == 0 ? left[0] : right[0], turn_b = i == 0 ? left[1] : right[1];
    const double apex = std::sin(turn_a + turn_b);
    if (turn_a + turn_b < M_PI && apex > kMinTurnSin) {
      // where the tangent from a meets the tangent from b: both new segments clear the cluster
      const double reach = length * std::sin(turn_b) / apex;
      const double fwd = reach * std::cos(turn_a), lat = sign * reach * std::sin(turn_a);
      points[i] = Vec2(ax + fwd * ux + lat * nx, ay + fwd * uy + lat * ny);
    } else {
      // the tangents do not meet: perpendicular to the segment, outside the whole cluster on that side
      const double kx = scene.centres(k, 0), ky = scene.centres(k, 1);
      double most = -kInf;
      for (Eigen::Index j : members) {
        const double spread = (scene.centres(j, 0) - kx) * nx + (scene.centres(j, 1) - ky) * ny;
        most = std::max(most, sign * spread + scene.detour(j));
      }
      const double offset = sign * most;
      points[i] = Vec2(kx + offset * nx, ky + offset * ny);
    }
  }
  // the better side: inside the bounds, outside every clearance, the shorter detour; the first on a tie
  std::tuple<bool, bool, double, int> best{true, true, kInf, 2};
  for (int i = 0; i < 2; ++i) {
    bool taken = false;
    for (Eigen::Index j = 0; j < scene.size() && !taken; ++j) taken = scene.inside(points[i], j);
    const std::tuple<bool, bool, double, int> key{!bounds.contains(points[i]), taken,
                                                  dist(a, points[i]) + dist(points[i], b), i};
    if (key < best) best = key;
  }
  return bounds.clamp(points[std::get<3>(best)]);
}

// Subtargets from a to goal (both excluded), at most budget: a stack of pending targets, the segment to the top
// one checked; clear, the robot "moves" there; blocked, a subtarget for the first obstacle on it is pushed.
std::vector<Vec2> leg(Vec2 a, const Vec2& goal, const Scene& scene, const Bounds& bounds, int budget) {
  std::vector<Vec2> route, stack{goal};
  std::vector<bool> active;
  while (!stack.empty() && scene.size() > 0) {
    const Eigen::Index k = first_blocking(a, stack.back(), scene, active);
    if (k < 0) {
      const Vec2 reached = stack.back();
      stack.pop_back();
      if (!stack.empty()) {
        route.push_back(reached);
        a = reached;
      }
      continue;
    }
    if (static_cast<int>(route.size() + stack.size()) - 1 >= budget) break;  // out of subtargets: best effort
    stack.push_back(detour_point(a, stack.back(), k, active, scene, bounds));
  }
  for (std::size_t i = stack.size(); i-- > 1;) route.push_back(stack[i]);
  return route;
}

// Drop points within kSamePoint of the previous one (a waypoint wins over a subtarget), make at least four, and add
// points along segments longer than kMaxSpan.
void prepare_route(std::vector<Vec2>& points, std::vector<bool>& movable) {
  std::vector<Vec2> route{points[0]};
  std::vector<bool> free{movable[0]};
  const std::size_t last = points.size() - 1;
  for (std::size_t i = 1; i <= last; ++i) {
    if (dist(points[i], route.back()) >= kSamePoint) {
      route.push_back(points[i]);
      free.push_back(movable[i]);
    } else if (route.size() > 1 && (free.back() || i == last)) {  // the goal, or a waypoint, wins
      route.back() = points[i];
      free.back() = movable[i];
    }
  }
  if (route.size() == 3) {  // the longer segment gets its midpoint
    const std::size_t i = dist(route[0], route[1]) >= dist(route[1], route[2]) ? 0 : 1;
    route.insert(route.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                 Vec2((route[i].x() + route[i + 1].x()) / 2.0, (route[i].y() + route[i + 1].y()) / 2.0));
    free.insert(free.begin() + static_cast<std::ptrdiff_t>(i) + 1, true);
  }
  std::vector<Vec2> dense{route[0]};
  std::vector<bool> dense_free{free[0]};
  for (std::size_t j = 0; j + 1 < route.size(); ++j) {
    const double ax = route[j].x(), ay = route[j].y(), bx = route[j + 1].x(), by = route[j + 1].y();
    const int pieces = std::max(static_cast<int>(std::ceil(std::hypot(bx - ax, by - ay) / kMaxSpan)),
                                route.size() == 2 ? 3 : 1);
    for (int i = 1; i < pieces; ++i) {
      dense.emplace_back(ax + (bx - ax) * i / pieces, ay + (by - ay) * i / pieces);
      dense_free.push_back(true);
    }
    dense.emplace_back(bx, by);
    dense_free.push_back(free[j + 1]);
  }
  points = std::move(dense);
  movable = std::move(dense_free);
}

// A cubic B-spline with the ends' knots repeated: coefficients (count x 2) and knots.
struct Spline {
  Eigen::VectorXd knots;
  Points coefficients;

  // The interval l with knots[l] <= x < knots[l + 1], the last one for x at the end.
  Eigen::Index interval(double x) const {
    const Eigen::Index n = knots.size() - kDegree - 1;  // the coefficients' count
    return std::upper_bound(knots.data() + kDegree + 1, knots.data() + n, x) - knots.data() - 1;
  }

  // The k + 1 non-zero basis functions' nu-th derivative at x in interval l: de Boor's recursion, its last nu steps
  // differentiating.
  void basis(double x, Eigen::Index l, int nu, double* h) const {
    double hh[kDegree + 1];
    h[0] = 1.0;
    for (int j = 1; j <= kDegree; ++j) {
      const bool derivative = j > kDegree - nu;
      std::copy(h, h + j, hh);
      h[0] = 0.0;
      for (int n = 1; n <= j; ++n) {
        const double xb = knots(l + n), xa = knots(l + n - j);
        if (xb == xa) {
          h[n] = 0.0;
        } else if (derivative) {
          const double w = j * hh[n - 1] / (xb - xa);
          h[n - 1] -= w;
          h[n] = w;
        } else {
          const double w = hh[n - 1] / (xb - xa);
          h[n - 1] += w * (xb - x);
          h[n] = w * (x - xa);
        }
      }
    }
  }

  Vec2 at(double x, int nu) const {
    const Eigen::Index l = interval(x);
    double h[kDegree + 1];
    basis(x, l, nu, h);
    Vec2 sum(0.0, 0.0);
    for (int a = 0; a <= kDegree; ++a) sum += h[a] * coefficients.row(l - kDegree + a).transpose();
    return sum;
  }
};

Eigen::VectorXd chord_params(const Points& route) {
  Eigen::VectorXd u(route.rows());
  u(0) = 0.0;
  for (Eigen::Index i = 1; i < route.rows(); ++i) {
    u(i) = u(i - 1) + std::hypot(route(i, 0) - route(i - 1, 0), route(i, 1) - route(i - 1, 1));
  }
  return u;
}

// The cubic interpolating B-spline through route by chord length: natural at the end, and at the start too unless
// a direction (a unit vector) is given. The conditions' rows: the start's, the points', the end's.
Spline fit(const Points& route, const Eigen::VectorXd& u, const Vec2* direction) {
  const Eigen::Index points = route.rows(), count = points + 2;
  Spline spline;
  spline.knots.resize(points + 6);
  spline.knots.head(3).setConstant(u(0));
  spline.knots.segment(3, points) = u;
  spline.knots.tail(3).setConstant(u(points - 1));
  Eigen::MatrixXd lhs = Eigen::MatrixXd::Zero(count, count);
  Eigen::MatrixXd rhs(count, 2);
  double h[kDegree + 1];
  auto row = [&](Eigen::Index r, double x, int nu) {
    const Eigen::Index l = spline.interval(x);
    spline.basis(x, l, nu, h);
    for (int a = 0; a <= kDegree; ++a) lhs(r, l - kDegree + a) = h[a];
  };
  row(0, u(0), direction ? 1 : 2);
  if (direction) {
    rhs.row(0) = direction->transpose();
  } else {
    rhs.row(0).setZero();
  }
  for (Eigen::Index i = 0; i < points; ++i) {
    row(i + 1, u(i), 0);
    rhs.row(i + 1) = route.row(i);
  }
  row(count - 1, u(points - 1), 2);
  rhs.row(count - 1).setZero();
  spline.coefficients = lhs.partialPivLu().solve(rhs);
  return spline;
}

// Corrective via-points (spline parameter, position) for the deepest violation of each counted obstacle's clearance
// and of the bounds: the sample pushed out to the detour radius, or else the straight route there.
std::vector<std::pair<double, Vec2>> corrections(const Points& samples, const Eigen::VectorXd& at,
                                                 const Points& route, const Eigen::VectorXd& u, const Scene& scene,
                                                 const std::vector<bool>& counted, const Bounds& bounds) {
  const Vec2 lo(bounds.x_min, bounds.y_min), hi(bounds.x_max, bounds.y_max);
  auto on_route = [&](Eigen::Index i) {
    const double x = at(i);
    const Eigen::Index last = u.size() - 2;
    Eigen::Index j = std::upper_bound(u.data(), u.data() + u.size(), x) - u.data() - 1;
    j = std::min(std::max<Eigen::Index>(j, 0), last);
    const double frac = (x - u(j)) / (u(j + 1) - u(j));
    return Vec2(route.row(j).transpose() + frac * (route.row(j + 1) - route.row(j)).transpose());
  };
  struct Candidate {
    Eigen::Index sample;
    Vec2 point;
    Eigen::Index obstacle;
  };
  std::vector<Candidate> candidates;
  const Eigen::Index m = samples.rows();
  for (Eigen::Index j = 0; j < scene.size(); ++j) {
    if (!counted[static_cast<std::size_t>(j)]) continue;
    Eigen::Index deepest = 0;
    double most = -kInf, deepest_dist = 0.0;
    for (Eigen::Index i = 0; i < m; ++i) {
      const double rx = samples(i, 0) - scene.centres(j, 0), ry = samples(i, 1) - scene.centres(j, 1);
      const double d = std::sqrt(rx * rx + ry * ry);
      const double excess = scene.clear(j) - d;
      if (excess > most) {
        most = excess;
        deepest = i;
        deepest_dist = d;
      }
    }
    if (most > kTolerance) {
      const double away = std::max(deepest_dist, 1e-9);
      const Vec2 centre = scene.centres.row(j).transpose();
      const Vec2 rel = samples.row(deepest).transpose() - centre;
      candidates.push_back({deepest, Vec2(centre + rel * (scene.detour(j) / away)), j});
    }
  }
  Eigen::Index worst = 0;
  double outside_most = -kInf;
  for (Eigen::Index i = 0; i < m; ++i) {
    const double ox = std::max(lo.x() - samples(i, 0), 0.0) + std::max(samples(i, 0) - hi.x(), 0.0);
    const double oy = std::max(lo.y() - samples(i, 1), 0.0) + std::max(samples(i, 1) - hi.y(), 0.0);
    const double outside = std::max(ox, oy);
    if (outside > outside_most) {
      outside_most = outside;
      worst = i;
    }
  }
  if (outside_most > kBoundsTolerance) {
    const Vec2 inset = (0.25 * (hi - lo)).cwiseMin(0.1);
    const Vec2 low = lo + inset, high = hi - inset;
    candidates.push_back({worst, Vec2(samples.row(worst).transpose()).cwiseMax(low).cwiseMin(high), -1});
  }
  std::vector<std::pair<double, Vec2>> fixes;
  for (const Candidate& c : candidates) {
    bool blocked = false;
    for (Eigen::Index j = 0; j < scene.size() && !blocked; ++j) {
      blocked = j != c.obstacle && counted[static_cast<std::size_t>(j)] && scene.inside(c.point, j);
    }
    const bool strayed = (c.point.array() < lo.array()).any() || (c.point.array() > hi.array()).any();
    fixes.emplace_back(at(c.sample), blocked || strayed ? on_route(c.sample) : c.point);
  }
  return fixes;
}

// Insert the corrective via-points into their spline segments, or move a movable route point that is too near
// instead; true when the route changed.
bool apply(std::vector<Vec2>& route, std::vector<bool>& movable, const Eigen::VectorXd& u,
           std::vector<std::pair<double, Vec2>> fixes) {
  bool changed = false;
  std::sort(fixes.begin(), fixes.end(), [](const auto& a, const auto& b) {
    return std::make_tuple(a.first, a.second.x(), a.second.y()) > std::make_tuple(b.first, b.second.x(), b.second.y());
  });  // from the end, so that indices stay valid
  for (const auto& [param, p] : fixes) {
    Eigen::Index j = std::upper_bound(u.data(), u.data() + u.size(), param) - u.data() - 1;
    j = std::min(std::max<Eigen::Index>(j, 0), u.size() - 2);
    const std::size_t a = static_cast<std::size_t>(j);
    const std::size_t near = dist(route[a], p) <= dist(route[a + 1], p) ? a : a + 1;
    if (dist(route[near], p) < kMinViaGap) {
      if (movable[near]) {
        route[near] = p;
        changed = true;
      }
      continue;
    }
    route.insert(route.begin() + static_cast<std::ptrdiff_t>(a) + 1, p);
    movable.insert(movable.begin() + static_cast<std::ptrdiff_t>(a) + 1, true);
    changed = true;
  }
  return changed;
}

// Speeds at samples ds apart: from v_start, within limit, speeding up and braking by at most accel (per sample),
// ending at v_end when reachable; a start too fast to brake in time brakes as hard as allowed. On w = v^2.
Eigen::VectorXd speed_profile(const Eigen::VectorXd& limit, double ds, double v_start, double v_end,
                              const Eigen::VectorXd& accel) {
  const Eigen::Index n = limit.size();
  Eigen::VectorXd ramp(n), w(n);
  ramp(0) = 0.0;
  for (Eigen::Index i = 1; i < n; ++i) ramp(i) = ramp(i - 1) + 2.0 * ds * accel(i);
  w = limit.array().square();
  w(0) = v_start * v_start;
  double low = kInf;  // forward: speed up
  for (Eigen::Index i = 0; i < n; ++i) {
    low = std::min(low, w(i) - ramp(i));
    w(i) = ramp(i) + low;
  }
  w(n - 1) = std::min(w(n - 1), v_end * v_end);
  low = kInf;  // backward: brake in time (the start fixed)
  for (Eigen::Index i = n - 1; i >= 1; --i) {
    low = std::min(low, w(i) + ramp(i));
    w(i) = low - ramp(i);
  }
  double high = -kInf;  // no harder braking than allowed after a too fast start
  for (Eigen::Index i = 0; i < n; ++i) {
    high = std::max(high, w(i) + ramp(i));
    w(i) = high - ramp(i);
  }
  return w.cwiseMax(0.0).cwiseSqrt();
}

PlanResult standing(const Vec2& p0) {
  PlanResult result;
  result.t = Eigen::VectorXd::Zero(1);
  result.s = Eigen::VectorXd::Zero(1);
  result.xy.resize(1, 2);
  result.xy.row(0) = p0.transpose();
  result.v = Points::Zero(1, 2);
  result.via = {p0};
  return result;
}

Points to_points(const std::vector<Vec2>& route) {
  Points out(static_cast<Eigen::Index>(route.size()), 2);
  for (std::size_t i = 0; i < route.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = route[i].transpose();
  return out;
}

}  // namespace

Vec2 Bounds::clamp(const Vec2& p) const {
  return Vec2(std::min(std::max(p.x(), x_min), x_max), std::min(std::max(p.y(), y_min), y_max));
}

bool Bounds::contains(const Vec2& p) const {
  return x_min <= p.x() && p.x() <= x_max && y_min <= p.y() && p.y() <= y_max;
}

bool keeps_clear(const Eigen::Ref<const Rows2>& path, const std::vector<Vec2>& ends,
                 const std::vector<Disc>& obstacles, double margin, double tolerance) {
  for (const Disc& d : obstacles) {
    const double clear = margin + d.radius;
    const bool holds = std::any_of(ends.begin(), ends.end(), [&](const Vec2& e) {
      const double rx = e.x() - d.x, ry = e.y() - d.y;
      return rx * rx + ry * ry < clear * clear;
    });
    if (holds) continue;
    const double keep = std::max(clear - tolerance, 0.0);
    for (Eigen::Index i = 0; i < path.rows(); ++i) {
      const double rx = path(i, 0) - d.x, ry = path(i, 1) - d.y;
      if (rx * rx + ry * ry < keep * keep) return false;
    }
  }
  return true;
}

std::vector<Vec2> subtargets(const Vec2& start, const Vec2& goal, const std::vector<Disc>& obstacles,
                             const PlannerParams& params, const Bounds& bounds) {
  return leg(start, goal, Scene(obstacles, params), bounds, params.max_subtargets);
}

PlanResult plan(const Vec2& p0, const std::vector<Vec2>& waypoints, const std::vector<Disc>& obstacles,
                const PlannerParams& params, const Bounds& bounds, const Vec2& v0, double end_speed) {
  std::vector<Vec2> points;
  for (const Vec2& w : waypoints) points.push_back(bounds.clamp(w));
  if (std::all_of(points.begin(), points.end(), [&](const Vec2& p) { return dist(p, p0) <= kSamePoint; })) {
    return standing(p0);
  }
  const Scene scene(obstacles, params);

  // 1. the route; only subtargets and added points may move
  std::vector<Vec2> route{p0};
  std::vector<bool> movable{false};
  int budget = params.max_subtargets;
  for (const Vec2& p : points) {
    const std::vector<Vec2> via = leg(route.back(), p, scene, bounds, budget);
    budget -= static_cast<int>(via.size());
    route.insert(route.end(), via.begin(), via.end());
    movable.insert(movable.end(), via.size(), true);
    route.push_back(p);
    movable.push_back(false);
  }
  std::vector<bool> counted(static_cast<std::size_t>(scene.size()), true);  // obstacles not holding a user point
  for (Eigen::Index j = 0; j < scene.size(); ++j) {
    bool holds = scene.inside(p0, j);
    for (std::size_t i = 0; i < points.size() && !holds; ++i) holds = scene.inside(points[i], j);
    counted[static_cast<std::size_t>(j)] = !holds;
  }
  prepare_route(route, movable);
  if (route.size() < 4) return standing(p0);  // only within a centimetre steps of the start

  // 2-3. fit; correct clearance and bounds violations and refit
  const double speed0 = std::hypot(v0.x(), v0.y());
  const Vec2 unit = speed0 > kDirectionSpeed ? Vec2(v0.x() / speed0, v0.y() / speed0) : Vec2(0.0, 0.0);
  const Vec2* direction = speed0 > kDirectionSpeed ? &unit : nullptr;
  Spline spline;
  Eigen::VectorXd at;
  Points samples;
  for (int attempt = 0; attempt <= kMaxRefits; ++attempt) {
    const Points route_xy = to_points(route);
    const Eigen::VectorXd u = chord_params(route_xy);
    spline = fit(route_xy, u, direction);
    const double end = u(u.size() - 1);
    const Eigen::Index count = std::max(static_cast<Eigen::Index>(std::ceil(end / params.sample_step)),
                                        Eigen::Index{3});
    at.resize(count + 1);
    samples.resize(count + 1, 2);
    for (Eigen::Index i = 0; i <= count; ++i) {
      at(i) = static_cast<double>(i) * (end / static_cast<double>(count));
      samples.row(i) = spline.at(at(i), 0).transpose();
    }
    if (attempt == kMaxRefits) break;
    const auto fixes = corrections(samples, at, route_xy, u, scene, counted, bounds);
    if (fixes.empty() || !apply(route, movable, u, fixes)) break;
  }

  // 4. samples evenly spaced in arc length, and the speed profile
  const Eigen::Index dense = samples.rows();
  Eigen::VectorXd s_dense(dense);
  s_dense(0) = 0.0;
  for (Eigen::Index i = 1; i < dense; ++i) {
    s_dense(i) = s_dense(i - 1) + std::hypot(samples(i, 0) - samples(i - 1, 0), samples(i, 1) - samples(i - 1, 1));
  }
  const double total = s_dense(dense - 1);
  const Eigen::Index count = std::max(static_cast<Eigen::Index>(std::ceil(total / params.sample_step)),
                                      Eigen::Index{1});
  const double ds = total / static_cast<double>(count);
  PlanResult result;
  result.s.resize(count + 1);
  result.xy.resize(count + 1, 2);
  result.v.resize(count + 1, 2);
  Points d1(count + 1, 2);
  Eigen::VectorXd norm(count + 1), curvature(count + 1);
  const Vec2 low(std::min(bounds.x_min, p0.x()), std::min(bounds.y_min, p0.y()));
  const Vec2 high(std::max(bounds.x_max, p0.x()), std::max(bounds.y_max, p0.y()));
  Eigen::Index j = 0;  // s_dense(j) <= s < s_dense(j + 1): np.interp's interval
  for (Eigen::Index i = 0; i <= count; ++i) {
    const double s = static_cast<double>(i) * ds;
    result.s(i) = s;
    double param;
    if (s >= s_dense(dense - 1)) {
      param = at(dense - 1);
    } else if (s <= s_dense(0)) {
      param = at(0);
    } else {
      while (j + 1 < dense && s_dense(j + 1) <= s) ++j;
      const double slope = (at(j + 1) - at(j)) / (s_dense(j + 1) - s_dense(j));
      param = slope * (s - s_dense(j)) + at(j);
    }
    const Vec2 p = spline.at(param, 0), first = spline.at(param, 1), second = spline.at(param, 2);
    result.xy.row(i) = p.cwiseMax(low).cwiseMin(high).transpose();
    d1.row(i) = first.transpose();
    norm(i) = std::max(std::hypot(first.x(), first.y()), 1e-9);
    curvature(i) = std::abs(first.x() * second.y() - first.y() * second.x()) / std::pow(norm(i), 3);
  }
  Eigen::VectorXd limit(count + 1), along(count + 1);
  const double a_max = params.max_accel, a_lat = params.max_lateral_accel;
  for (Eigen::Index i = 0; i <= count; ++i) {
    const double l = std::sqrt(a_lat / std::max(curvature(i), 1e-12));
    limit(i) = std::min(std::max(l, kMinSpeed), params.max_speed);
    // what the curve leaves of max_accel for speeding up and braking (at the speed limit, the most it can take)
    const double lateral = std::min(limit(i) * limit(i) * curvature(i), a_lat);
    along(i) = std::sqrt(std::max(a_max * a_max - lateral * lateral, (kMinAlong * a_max) * (kMinAlong * a_max)));
  }
  const Eigen::VectorXd speed = speed_profile(limit, ds, std::min(speed0, params.max_speed),
                                              std::min(end_speed, params.max_speed), along);
  result.t.resize(count + 1);
  result.t(0) = 0.0;
  for (Eigen::Index i = 1; i <= count; ++i) {
    result.t(i) = result.t(i - 1) + 2.0 * ds / std::max(speed(i - 1) + speed(i), 1e-9);
  }
  for (Eigen::Index i = 0; i <= count; ++i) result.v.row(i) = d1.row(i) * (speed(i) / norm(i));
  result.via = route;
  return result;
}

}  // namespace nubot_control

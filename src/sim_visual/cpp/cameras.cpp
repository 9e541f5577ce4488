// The simulated cameras' ray casting (sim_visual/include/sim_visual/cameras.hpp). Each test is the numpy one it
// replaced, operation by operation and in the same order (numpy's a ** 2 is a * a; 4.0 * a * c is (4.0 * a) * c);
// where the Python went through a matrix product, OpenBLAS summed the products with fused multiply-adds in a fixed
// order, which std::fma repeats. A test is skipped only where its answer is known without it (a ray that cannot meet
// a body: the square root and the division are left out, never changed). The one function that is not numpy's is
// atan2 (RgbdRayCaster::on_line).
#include "sim_visual/cameras.hpp"

#include <cmath>
#include <limits>
#include <utility>

namespace sim_visual {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTwoPi = 2.0 * 3.14159265358979323846;
constexpr double kArcMargin = 1e-6;  // [m] a point this far beyond an arc's band lies outside it whatever the rounding

// numpy's remainder (np.mod) of a float: the sign of the divisor.
double py_mod(double a, double b) {
  double mod = std::fmod(a, b);
  if (mod != 0.0) {
    if ((b < 0.0) != (mod < 0.0)) mod += b;
  } else {
    mod = std::copysign(0.0, b);
  }
  return mod;
}

// The loop's helpers are always inlined: each build of the loop (cast_rays) then has them with its own instructions.

// A row of a matrix times a vector as OpenBLAS's kernels here sum it (numpy's rays @ rotation.T): fused, in order.
[[gnu::always_inline]] inline double blas_dot(double a0, double a1, double a2, double b0, double b1, double b2) {
  return std::fma(a2, b2, std::fma(a1, b1, a0 * b0));
}

// The range along d from o to an upright cylinder on the ground (rgbd_camera._vertical_cylinder), inf if none; ox, oy
// are o relative to its axis, c = ox * ox + oy * oy - r * r.
[[gnu::always_inline]] inline double vertical_cylinder(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double ox,
                                                     double oy, double c, double r, double top) {
  const double a = d[0] * d[0] + d[1] * d[1];
  const double b = 2.0 * (d[0] * ox + d[1] * oy);
  const double disc = b * b - 4.0 * a * c;
  double t = kInf;
  // -b - sqrt(disc) is no positive number where b >= 0, and the root of a negative or NaN disc is NaN: no side hit
  if (disc >= 0.0 && b < 0.0) {
    const double side = (-b - std::sqrt(disc)) / (2.0 * a);
    const double z = o[2] + side * d[2];
    if (side > 0.0 && z >= 0.0 && z <= top) t = side;
  }
  if (o[2] > top) {  // the top disc, seen from above
    const double tt = (top - o[2]) / d[2];
    const double px = ox + tt * d[0], py = oy + tt * d[1];
    const double disc_hit = tt > 0.0 && px * px + py * py <= r * r ? tt : kInf;
    t = disc_hit < t ? disc_hit : t;  // np.minimum; neither is NaN
  }
  return t;
}

// A horizontal bar along y (rgbd_camera._bar): ox, oz are o relative to its centre line, c = ox * ox + oz * oz - r * r.
[[gnu::always_inline]] inline double bar(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double ox, double oz,
                                       double c, double half) {
  const double a = d[0] * d[0] + d[2] * d[2];
  const double b = 2.0 * (d[0] * ox + d[2] * oz);
  const double disc = b * b - 4.0 * a * c;
  if (!(disc >= 0.0 && b < 0.0)) return kInf;
  const double t = (-b - std::sqrt(disc)) / (2.0 * a);
  const double y = o[1] + t * d[1];
  return t > 0.0 && std::abs(y) <= half ? t : kInf;
}

// A sphere (rgbd_camera._sphere): oc is o relative to its centre, c = oc @ oc - r * r.
[[gnu::always_inline]] inline double sphere(const Eigen::Vector3d& d, const Eigen::Vector3d& oc, double c) {
  // d @ oc: numpy's matrix-vector product, which OpenBLAS's kernel here sums fused, the second product first
  const double b = std::fma(d[2], oc[2], std::fma(d[0], oc[0], d[1] * oc[1]));
  const double disc = b * b - c;
  if (!(disc >= 0.0 && b < 0.0)) return kInf;
  const double t = -b - std::sqrt(disc);
  return t > 0.0 ? t : kInf;
}

// A body's constants for one viewpoint, as the Python computes them once a cast.
struct Posed {
  Shape shape;
  std::uint8_t what;
  double u, v, c;  // o relative to the body (cylinder: x, y; bar: x, z), c; a sphere keeps oc in centre
  Eigen::Vector3d centre;
  double size, top;  // cylinder: radius, top; bar: -, half length
};

// The rays' loop of RgbdRayCaster::cast, also built for processors with fused multiply-add instructions (picked when
// the module loads): std::fma is then one instruction instead of a call, with the same, exactly rounded, answers.
[[gnu::target_clones("default", "fma")]] void cast_rays(const std::vector<Eigen::Vector3d>& rays,
                                                        const Eigen::Vector3d& o, const Eigen::Matrix3d& rotation,
                                                        const std::vector<Posed>& posed, double max_range,
                                                        const RgbdRayCaster& lines, double* range, std::uint8_t* kind) {
  const double ground_lift = -o[2];
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Vector3d& ray = rays[i];
    const Eigen::Vector3d d(blas_dot(ray[0], ray[1], ray[2], rotation(0, 0), rotation(0, 1), rotation(0, 2)),
                            blas_dot(ray[0], ray[1], ray[2], rotation(1, 0), rotation(1, 1), rotation(1, 2)),
                            blas_dot(ray[0], ray[1], ray[2], rotation(2, 0), rotation(2, 1), rotation(2, 2)));
    double t = kInf;
    std::uint8_t what = static_cast<std::uint8_t>(RayHit::kNone);
    const auto hit = [&](double t_new, std::uint8_t label) {
      if (t_new < t) {
        t = t_new;
        what = label;
      }
    };
    hit(d[2] < 0.0 ? ground_lift / d[2] : kInf, static_cast<std::uint8_t>(RayHit::kGround));
    for (const auto& q : posed) {
      switch (q.shape) {
        case Shape::kCylinder:
          hit(vertical_cylinder(o, d, q.u, q.v, q.c, q.size, q.top), q.what);
          break;
        case Shape::kBar:
          hit(bar(o, d, q.u, q.v, q.c, q.top), q.what);
          break;
        case Shape::kSphere:
          hit(sphere(d, q.centre, q.c), q.what);
          break;
      }
    }
    if (what == static_cast<std::uint8_t>(RayHit::kGround) && t * ray[0] <= max_range &&
        lines.on_line(o[0] + t * d[0], o[1] + t * d[1])) {
      what = static_cast<std::uint8_t>(RayHit::kLine);
    }
    range[i] = t;
    kind[i] = what;
  }
}

}  // namespace

void paint_cylinder(std::uint8_t* image, const float* rays, int width, const PixelBox& box,
                    const Eigen::Vector3d& origin, const Cylinder& cylinder, const Rgb& side_rgb, const Rgb& top_rgb) {
  const double ox = origin[0] - cylinder.x, oy = origin[1] - cylinder.y;
  const double radius = cylinder.radius, height = cylinder.height;
  const double c = ox * ox + oy * oy - radius * radius;
  const double rise = height - origin[2];
  for (int v = box.v0; v < box.v1; ++v) {
    for (int u = box.u0; u < box.u1; ++u) {
      const std::size_t at = (static_cast<std::size_t>(v) * static_cast<std::size_t>(width) +
                              static_cast<std::size_t>(u)) * 3;
      const double dx = rays[at], dy = rays[at + 1], dz = rays[at + 2];
      const double a = dx * dx + dy * dy;
      const double b = 2.0 * (ox * dx + oy * dy);
      const double disc = b * b - 4.0 * a * c;
      bool side = false;
      double t_side = 0.0;
      // -b - sqrt(max(disc, 0)) is no positive number where b >= 0: no side hit, whatever the root
      if (disc >= 0.0 && b < 0.0) {
        t_side = (-b - std::sqrt(disc)) / (2.0 * a);
        const double z_side = origin[2] + t_side * dz;
        side = t_side > 0.0 && z_side >= 0.0 && z_side <= height;
      }
      const double t_top = rise / dz;
      const double px = ox + t_top * dx, py = oy + t_top * dy;
      const bool top = t_top > 0.0 && px * px + py * py <= radius * radius && (!side || t_top < t_side);
      if (side || top) {
        const Rgb& rgb = top ? top_rgb : side_rgb;
        image[at] = rgb[0];
        image[at + 1] = rgb[1];
        image[at + 2] = rgb[2];
      }
    }
  }
}

RgbdRayCaster::RgbdRayCaster(std::vector<Eigen::Vector3d> rays, const std::vector<LineSegment>& segments,
                             std::vector<LineArc> arcs, double line_half_width, double max_range)
    : rays_(std::move(rays)), arcs_(std::move(arcs)), half_width_(line_half_width), max_range_(max_range) {
  segments_.reserve(segments.size());
  for (const auto& s : segments) {
    const double abx = s.bx - s.ax, aby = s.by - s.ay;
    const double length2 = abx * abx + aby * aby;
    segments_.push_back({s.ax, s.ay, abx, aby, length2 > 1e-12 ? length2 : 1e-12});
  }
}

bool RgbdRayCaster::on_line(double gx, double gy) const {
  const double half = half_width_;
  for (const auto& s : segments_) {
    double u = ((gx - s.ax) * s.abx + (gy - s.ay) * s.aby) / s.length2;
    u = u < 0.0 ? 0.0 : (u > 1.0 ? 1.0 : u);  // np.clip; u is no NaN
    const double ex = gx - s.ax - u * s.abx, ey = gy - s.ay - u * s.aby;
    // hypot is at least either side's size
    if (std::abs(ex) <= half && std::abs(ey) <= half && std::hypot(ex, ey) <= half) return true;
  }
  for (const auto& arc : arcs_) {
    const double rx = gx - arc.x, ry = gy - arc.y;
    // hypot lies between the larger side and the sum of both: points far off the band are known to be off it
    const double ax = std::abs(rx), ay = std::abs(ry);
    if ((ax > ay ? ax : ay) > arc.radius + half + kArcMargin || ax + ay < arc.radius - half - kArcMargin) continue;
    if (!(std::abs(std::hypot(rx, ry) - arc.radius) <= half)) continue;
    // libm's atan2; numpy had its own (vectorised), which differs in the last bit for some angles: an answer could
    // differ only for a point within that bit of an arc's end
    if (py_mod(std::atan2(ry, rx) - arc.start, kTwoPi) <= arc.end - arc.start + 1e-9) return true;
  }
  return false;
}

void RgbdRayCaster::cast(const Eigen::Vector3d& origin, const Eigen::Matrix3d& rotation,
                         const std::vector<Body>& bodies, double* range, std::uint8_t* kind) const {
  const Eigen::Vector3d& o = origin;
  std::vector<Posed> posed;
  posed.reserve(bodies.size());
  for (const auto& body : bodies) {
    const auto& p = body.p;
    Posed q{body.shape, body.what, 0.0, 0.0, 0.0, Eigen::Vector3d::Zero(), 0.0, 0.0};
    switch (body.shape) {
      case Shape::kCylinder:  // x, y, radius, top
        q.u = o[0] - p[0];
        q.v = o[1] - p[1];
        q.c = q.u * q.u + q.v * q.v - p[2] * p[2];
        q.size = p[2];
        q.top = p[3];
        break;
      case Shape::kBar:  // x, z, radius, half length
        q.u = o[0] - p[0];
        q.v = o[2] - p[1];
        q.c = q.u * q.u + q.v * q.v - p[2] * p[2];
        q.top = p[3];
        break;
      case Shape::kSphere:  // x, y, z, radius; oc @ oc is numpy's dot product, which OpenBLAS sums fused
        q.centre = o - Eigen::Vector3d(p[0], p[1], p[2]);
        q.c = blas_dot(q.centre[0], q.centre[1], q.centre[2], q.centre[0], q.centre[1], q.centre[2]) - p[3] * p[3];
        break;
    }
    posed.push_back(q);
  }
  cast_rays(rays_, o, rotation, posed, max_range_, *this, range, kind);
}

}  // namespace sim_visual

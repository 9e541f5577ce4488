// The ray casting of the simulated cameras (see sim_visual/front_camera.py and sim_visual/rgbd_camera.py): the front
// camera's upright cylinders painted pixel by pixel, and the goalie's RGB-D cameras' rays cast against the ground, its
// lines, the robots, the goals and the ball. The arithmetic is the Python's, operation by operation, so that a frame
// is the same to the last bit. Units SI: m; rays are unit vectors.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sim_visual {

using Rgb = std::array<std::uint8_t, 3>;

// An upright cylinder standing on the ground at (x, y) of the front camera's body frame.
struct Cylinder {
  double x, y, height, radius;
};

// The pixels (u0 <= u < u1, v0 <= v < v1) of a box of the image.
struct PixelBox {
  int u0, v0, u1, v1;
};

// Paints the pixels of box whose rays from origin (body frame) meet the cylinder's side in side_rgb or, nearer, its
// top in top_rgb. image: height x width x 3 bytes, row by row; rays: the camera's body-frame rays, height x width x 3
// single-precision numbers, row by row; the box lies within both.
void paint_cylinder(std::uint8_t* image, const float* rays, int width, const PixelBox& box,
                    const Eigen::Vector3d& origin, const Cylinder& cylinder, const Rgb& side_rgb, const Rgb& top_rgb);

// What an RGB-D ray met first, where the bodies do not say (rgbd_camera.py's NONE, GROUND, LINE).
enum class RayHit : std::uint8_t { kNone = 0, kGround = 1, kLine = 2 };
// The bodies' shapes (rgbd_camera.py's CYLINDER, BAR, SPHERE).
enum class Shape : int { kCylinder = 0, kBar = 1, kSphere = 2 };

// A body the RGB-D rays can meet: its shape, what a ray meeting it shows (its label) and four numbers: an upright
// cylinder on the ground x, y, radius, top; a bar along y x, z, radius, half length; a sphere x, y, z, radius.
struct Body {
  Shape shape;
  std::uint8_t what;
  std::array<double, 4> p;
};

// A white line segment of the field, from (ax, ay) to (bx, by).
struct LineSegment {
  double ax, ay, bx, by;
};

// A white arc: centre (x, y), radius, from start to end counter-clockwise [rad].
struct LineArc {
  double x, y, radius, start, end;
};

// An RGB-D camera's rays (its frame: x along the optical axis) and the field's lines: built once, cast every frame.
class RgbdRayCaster {
 public:
  // line_half_width: half a line's width; max_range: the farthest depth (along the optical axis) a return has.
  RgbdRayCaster(std::vector<Eigen::Vector3d> rays, const std::vector<LineSegment>& segments,
                std::vector<LineArc> arcs, double line_half_width, double max_range);

  std::size_t size() const { return rays_.size(); }

  // Every ray turned into the world by rotation (world <- camera) from origin: the range to what it meets first in
  // range (inf: nothing) and what that is in kind (RayHit, a body's label); both as many as the rays. The ground
  // first, then the bodies in their order (a tie goes to the first), then the lines on the ground in range.
  void cast(const Eigen::Vector3d& origin, const Eigen::Matrix3d& rotation, const std::vector<Body>& bodies,
            double* range, std::uint8_t* kind) const;

  // Whether the ground point (gx, gy) lies on a white line.
  bool on_line(double gx, double gy) const;

 private:
  struct Segment {  // as the Python holds it: a start, its way to the end and that way's squared length
    double ax, ay, abx, aby, length2;
  };

  std::vector<Eigen::Vector3d> rays_;
  std::vector<Segment> segments_;
  std::vector<LineArc> arcs_;
  double half_width_, max_range_;
};

}  // namespace sim_visual

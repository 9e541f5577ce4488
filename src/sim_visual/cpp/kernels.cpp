// sim_visual._kernels: the compiled cores under sim_visual's Python API (see sim_visual/world.py).
#include <pybind11/pybind11.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "sim_visual/cameras.hpp"
#include "sim_visual/physics.hpp"
#include "sim_visual/sensing.hpp"

namespace py = pybind11;
using sim_visual::Physics;

namespace {

template <std::size_t N>
std::array<double, N> finite(const std::array<double, N>& values, const char* what) {
  for (double v : values) {
    if (!std::isfinite(v)) throw std::invalid_argument(std::string(what) + " must be finite numbers");
  }
  return values;
}

std::vector<sim_visual::RobotRow> finite_rows(const std::vector<sim_visual::RobotRow>& rows) {
  for (const auto& row : rows) finite(row, "robot states");
  return rows;
}

double finite(double value, const char* what) {
  if (!std::isfinite(value)) throw std::invalid_argument(std::string(what) + " must be a finite number");
  return value;
}

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::string shape_text(const std::vector<py::ssize_t>& shape) {
  std::string text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    text += (i ? ", " : "") + (shape[i] < 0 ? std::string("n") : std::to_string(shape[i]));
  }
  return text + (shape.size() == 1 ? ",)" : ")");
}

std::vector<py::ssize_t> shape_of(const py::array& array) { return {array.shape(), array.shape() + array.ndim()}; }

bool fits(const std::vector<py::ssize_t>& shape, const std::vector<py::ssize_t>& wanted) {
  if (shape.size() != wanted.size()) return false;
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (wanted[i] >= 0 && shape[i] != wanted[i]) return false;
  }
  return true;
}

// value as finite floats of shape wanted (-1: any length), else std::invalid_argument naming it.
Array finite_array(const py::object& value, const char* name, const std::vector<py::ssize_t>& wanted) {
  Array array = Array::ensure(value);
  if (!array) {
    PyErr_Clear();
    throw std::invalid_argument(std::string(name) + " must be numbers of shape " + shape_text(wanted) + ", got " +
                                std::string(py::repr(value)));
  }
  if (!fits(shape_of(array), wanted)) {
    throw std::invalid_argument(std::string(name) + " must have shape " + shape_text(wanted) + ", got " +
                                shape_text(shape_of(array)));
  }
  const double* data = array.data();
  for (py::ssize_t i = 0; i < array.size(); ++i) {
    if (!std::isfinite(data[i])) throw std::invalid_argument(std::string(name) + " must be finite numbers");
  }
  return array;
}

// An image-sized array as it is, read in place: of dtype T, C-contiguous, of shape wanted; else std::invalid_argument.
template <typename T>
py::array in_place(const py::object& value, const char* name, const char* dtype, const std::vector<py::ssize_t>& wanted,
                   bool writeable) {
  if (!py::isinstance<py::array>(value)) {
    throw std::invalid_argument(std::string(name) + " must be a numpy array of " + dtype);
  }
  auto array = py::reinterpret_borrow<py::array>(value);
  if (!array.dtype().is(py::dtype::of<T>())) {
    throw std::invalid_argument(std::string(name) + " must be of dtype " + dtype + ", got " +
                                std::string(py::str(array.dtype())));
  }
  if (!fits(shape_of(array), wanted)) {
    throw std::invalid_argument(std::string(name) + " must have shape " + shape_text(wanted) + ", got " +
                                shape_text(shape_of(array)));
  }
  if (!(array.flags() & py::array::c_style)) throw std::invalid_argument(std::string(name) + " must be C-contiguous");
  if (writeable && !array.writeable()) throw std::invalid_argument(std::string(name) + " must be writeable");
  return array;
}

sim_visual::Rgb colour(const std::array<int, 3>& rgb, const char* name) {
  for (int c : rgb) {
    if (c < 0 || c > 255) throw std::invalid_argument(std::string(name) + " must be three integers in [0, 255]");
  }
  return {static_cast<std::uint8_t>(rgb[0]), static_cast<std::uint8_t>(rgb[1]), static_cast<std::uint8_t>(rgb[2])};
}

// The bodies of a cast: rows (shape, label, four numbers).
std::vector<sim_visual::Body> bodies_of(const py::object& value) {
  const Array rows = finite_array(value, "shapes", {-1, 6});
  std::vector<sim_visual::Body> bodies;
  bodies.reserve(static_cast<std::size_t>(rows.shape(0)));
  for (py::ssize_t i = 0; i < rows.shape(0); ++i) {
    const double* r = rows.data(i, 0);
    if (!(r[0] == 0.0 || r[0] == 1.0 || r[0] == 2.0)) {
      throw std::invalid_argument("a shape must be CYLINDER, BAR or SPHERE (0, 1, 2), got " + std::to_string(r[0]));
    }
    if (!(r[1] >= 0.0 && r[1] <= 255.0 && r[1] == std::floor(r[1]))) {
      throw std::invalid_argument("a shape's label must be an integer in [0, 255], got " + std::to_string(r[1]));
    }
    bodies.push_back({static_cast<sim_visual::Shape>(static_cast<int>(r[0])), static_cast<std::uint8_t>(r[1]),
                      {r[2], r[3], r[4], r[5]}});
  }
  return bodies;
}

}  // namespace

PYBIND11_MODULE(_kernels, m) {
  m.doc() = "sim_visual's compiled kernels: the physics world's per-step work (see sim_visual.world), the "
            "robots' synthetic omni vision (see sim_visual.sensing) and the cameras' ray casting (see "
            "sim_visual.front_camera and sim_visual.rgbd_camera).";

  m.def(
      "paint_cylinder",
      [](const py::object& image, const py::object& rays, const std::array<int, 4>& box, const py::object& origin,
         const py::object& geometry, const std::array<int, 3>& side_rgb, const std::array<int, 3>& top_rgb) {
        py::array picture = in_place<std::uint8_t>(image, "image", "uint8", {-1, -1, 3}, true);
        const py::ssize_t height = picture.shape(0), width = picture.shape(1);
        const py::array grid = in_place<float>(rays, "rays", "float32", {height, width, 3}, false);
        const auto [u0, v0, u1, v1] = box;
        if (!(0 <= u0 && u0 <= u1 && u1 <= width && 0 <= v0 && v0 <= v1 && v1 <= height)) {
          throw std::invalid_argument("box (u0, v0, u1, v1) must lie within the " + std::to_string(width) + " x " +
                                      std::to_string(height) + " image, got (" + std::to_string(u0) + ", " +
                                      std::to_string(v0) + ", " + std::to_string(u1) + ", " + std::to_string(v1) +
                                      ")");
        }
        const Array o = finite_array(origin, "origin", {3});
        const Array g = finite_array(geometry, "geometry", {4});
        sim_visual::paint_cylinder(static_cast<std::uint8_t*>(picture.mutable_data()),
                                   static_cast<const float*>(grid.data()), static_cast<int>(width),
                                   {u0, v0, u1, v1}, Eigen::Vector3d(o.at(0), o.at(1), o.at(2)),
                                   {g.at(0), g.at(1), g.at(2), g.at(3)}, colour(side_rgb, "side_rgb"),
                                   colour(top_rgb, "top_rgb"));
      },
      py::arg("image"), py::arg("rays"), py::arg("box"), py::arg("origin"), py::arg("geometry"), py::arg("side_rgb"),
      py::arg("top_rgb"),
      "Paints, in place, the pixels of box (u0, v0, u1, v1; ends exclusive) of image (height x width x 3 uint8) "
      "whose rays (the camera's body-frame rays, height x width x 3 float32) from origin meet the upright cylinder "
      "geometry (x, y, height, radius [m], body frame): its side in side_rgb or, nearer, its top in top_rgb.");

  py::class_<sim_visual::RgbdRayCaster>(m, "RgbdRayCaster",
                                         "An RGB-D camera's rays and the field's lines, cast every frame.")
      .def(py::init([](const py::object& rays, const py::object& segments, const py::object& arcs,
                       double line_half_width, double max_range) {
             const Array r = finite_array(rays, "rays", {-1, 3});
             const Array s = finite_array(segments, "segments", {-1, 2, 2});
             const Array a = finite_array(arcs, "arcs", {-1, 5});
             if (!(std::isfinite(line_half_width) && line_half_width >= 0.0)) {
               throw std::invalid_argument("line_half_width must be a finite number, not negative");
             }
             if (!(std::isfinite(max_range) && max_range > 0.0)) {
               throw std::invalid_argument("max_range must be a finite number above 0");
             }
             std::vector<Eigen::Vector3d> ray_list;
             ray_list.reserve(static_cast<std::size_t>(r.shape(0)));
             for (py::ssize_t i = 0; i < r.shape(0); ++i) ray_list.emplace_back(r.at(i, 0), r.at(i, 1), r.at(i, 2));
             std::vector<sim_visual::LineSegment> segment_list;
             for (py::ssize_t i = 0; i < s.shape(0); ++i) {
               segment_list.push_back({s.at(i, 0, 0), s.at(i, 0, 1), s.at(i, 1, 0), s.at(i, 1, 1)});
             }
             std::vector<sim_visual::LineArc> arc_list;
             for (py::ssize_t i = 0; i < a.shape(0); ++i) {
               arc_list.push_back({a.at(i, 0), a.at(i, 1), a.at(i, 2), a.at(i, 3), a.at(i, 4)});
             }
             return sim_visual::RgbdRayCaster(std::move(ray_list), segment_list, std::move(arc_list), line_half_width,
                                              max_range);
           }),
           py::arg("rays"), py::arg("segments"), py::arg("arcs"), py::arg("line_half_width"), py::arg("max_range"),
           "rays: the camera-frame unit rays (n x 3); segments: the field's straight lines ((x0, y0), (x1, y1)); "
           "arcs: its arcs (x, y, radius, start, end); half a line's width and the farthest depth of a return [m].")
      .def("__len__", &sim_visual::RgbdRayCaster::size)
      .def(
          "cast",
          [](const sim_visual::RgbdRayCaster& caster, const py::object& origin, const py::object& rotation,
             const py::object& shapes) {
            const Array o = finite_array(origin, "origin", {3});
            const Array r = finite_array(rotation, "rotation", {3, 3});
            const auto bodies = bodies_of(shapes);
            Eigen::Matrix3d turn;
            for (int j = 0; j < 3; ++j) {
              for (int k = 0; k < 3; ++k) turn(j, k) = r.at(j, k);
            }
            const auto n = static_cast<py::ssize_t>(caster.size());
            py::array_t<double> range(n);
            py::array_t<std::uint8_t> kind(n);
            caster.cast(Eigen::Vector3d(o.at(0), o.at(1), o.at(2)), turn, bodies, range.mutable_data(),
                        kind.mutable_data());
            return py::make_tuple(range, kind);
          },
          py::arg("origin"), py::arg("rotation"), py::arg("shapes"),
          "The range [m] along each ray turned by rotation (world <- camera) from origin (world) to what it meets "
          "first (inf: nothing) and what that is (GROUND, LINE, a shape's label; NONE): the ground, then shapes "
          "(rows: CYLINDER, BAR or SPHERE, its label, four numbers) in order, then the lines.");

  m.def(
      "limit_drive",
      [](const std::array<double, 3>& current, const std::array<double, 3>& wanted, double dt, double linear_accel,
         double linear_brake, double angular_accel) {
        return sim_visual::limit_drive(finite(current, "current"), finite(wanted, "wanted"), dt,
                                       {linear_accel, linear_brake, angular_accel});
      },
      py::arg("current"), py::arg("wanted"), py::arg("dt"), py::arg("linear_accel"), py::arg("linear_brake"),
      py::arg("angular_accel"), "The base's velocity one step of dt after current on its way to wanted.");

  m.def(
      "vision_draws",
      [](const std::vector<sim_visual::RobotRow>& robots, const sim_visual::BallRow& ball,
         const std::vector<int>& observers, const std::vector<int>& attacks, double vision_range) {
        return sim_visual::vision_draws(finite_rows(robots), finite(ball, "the ball's state"), observers, attacks,
                                        vision_range);
      },
      py::arg("robots"), py::arg("ball"), py::arg("observers"), py::arg("attacks"), py::arg("vision_range"),
      "How many standard normal numbers each observer's vision frame takes (6, and 4 per object in range).");

  m.def(
      "vision_frames",
      [](const std::vector<sim_visual::RobotRow>& robots, const sim_visual::BallRow& ball,
         const std::vector<int>& observers, const std::vector<int>& attacks, const std::array<double, 5>& noise,
         const py::array_t<double, py::array::c_style | py::array::forcecast>& normals) {
        if (normals.ndim() != 1) throw std::invalid_argument("normals must be a flat array");
        const auto frames = sim_visual::vision_frames(
            finite_rows(robots), finite(ball, "the ball's state"), observers, attacks,
            {noise[0], noise[1], noise[2], noise[3], noise[4]}, normals.data(), static_cast<std::size_t>(normals.size()));
        // As the records want them: (x, y, theta, vx, vy), the ball (x, y, vx, vy) or None, obstacles ((x, y), ...).
        py::list out;
        for (const auto& f : frames) {
          py::tuple obstacles(f.obstacles.size());
          for (std::size_t j = 0; j < f.obstacles.size(); ++j) {
            obstacles[j] = py::make_tuple(f.obstacles[j][0], f.obstacles[j][1]);
          }
          const auto& r = f.robot;
          py::object ball_out = f.ball_seen ? py::object(py::make_tuple(f.ball[0], f.ball[1], f.ball[2], f.ball[3]))
                                            : py::object(py::none());
          out.append(py::make_tuple(py::make_tuple(r[0], r[1], r[2], r[3], r[4]), ball_out, obstacles));
        }
        return out;
      },
      py::arg("robots"), py::arg("ball"), py::arg("observers"), py::arg("attacks"), py::arg("noise"),
      py::arg("normals"),
      "The observers' vision frames in their team frames; noise: position, velocity, self-position and heading "
      "standard deviations and the vision range; normals: the standard normal numbers vision_draws asked for.");

  m.def(
      "update_stuck",
      [](const std::tuple<bool, double, double, double, double, double, bool>& before, double command_vx,
         double command_vy, double x, double y, double dt, double time, double min_command, double filter_time,
         double stuck_time) {
        const auto& [has_last, last_x, last_y, ground_vx, ground_vy, slow_since, stuck] = before;
        sim_visual::StuckState state{has_last, last_x, last_y, ground_vx, ground_vy, !std::isnan(slow_since),
                                     std::isnan(slow_since) ? 0.0 : slow_since, stuck};
        sim_visual::update_stuck(state, command_vx, command_vy, x, y, dt, time, {min_command, filter_time, stuck_time});
        return std::make_tuple(state.has_last, state.last_x, state.last_y, state.ground_vx, state.ground_vy,
                               state.slow ? state.slow_since : std::nan(""), state.stuck);
      },
      py::arg("state"), py::arg("command_vx"), py::arg("command_vy"), py::arg("x"), py::arg("y"), py::arg("dt"),
      py::arg("time"), py::arg("min_command"), py::arg("filter_time"), py::arg("stuck_time"),
      "A robot's stuck detection one update on; state: has a last position, its x, y, the ground velocity's vx, "
      "vy, slow since (NaN: not slow), stuck.");

  m.def(
      "grip_holds",
      [](double vx, double vy, double w, double forward, double backward, double sideways, double turn) {
        sim_visual::HandlerParams p{};
        p.hold_forward_speed = forward;
        p.hold_backward_speed = backward;
        p.hold_sideways_speed = sideways;
        p.hold_turn_rate = turn;
        finite(std::array<double, 3>{vx, vy, w}, "a body velocity");
        return sim_visual::grip_holds(vx, vy, w, p);
      },
      py::arg("vx"), py::arg("vy"), py::arg("w"), py::arg("forward"), py::arg("backward"), py::arg("sideways"),
      py::arg("turn"), "Whether the ball handler keeps the ball at the body velocity (vx ahead, vy left, w).");
  m.def(
      "dribble_condition",
      [](double x, double y, double theta, double bx, double by, double bz, double ball_radius, double distance,
         double half_angle) {
        sim_visual::HandlerParams p{};
        p.ball_radius = ball_radius;
        p.dribble_distance = distance;
        p.dribble_half_angle = half_angle;
        finite(std::array<double, 3>{x, y, theta}, "a robot's pose");
        finite(std::array<double, 3>{bx, by, bz}, "the ball's position");
        return sim_visual::dribble_condition(x, y, theta, bx, by, bz, p);
      },
      py::arg("x"), py::arg("y"), py::arg("theta"), py::arg("bx"), py::arg("by"), py::arg("bz"), py::arg("ball_radius"),
      py::arg("distance"), py::arg("half_angle"), "Whether a robot at (x, y, theta) can take the ball at (bx, by, bz).");
  m.def(
      "held_ball",
      [](double x, double y, double theta, double vx, double vy, double w, double hold_distance) {
        finite(std::array<double, 6>{x, y, theta, vx, vy, w}, "a robot's state");
        return sim_visual::held_ball(x, y, theta, vx, vy, w, hold_distance);
      },
      py::arg("x"), py::arg("y"), py::arg("theta"), py::arg("vx"), py::arg("vy"), py::arg("w"),
      py::arg("hold_distance"),
        "Where the ball a robot at (x, y, theta) moving at (vx, vy, w) holds sits and how it moves: x, y, vx, vy.");

  py::class_<sim_visual::Surface>(m, "Surface", "Contact properties of a pair of kinds of geometry.")
      .def(py::init([](double mu, double bounce, int pair) { return sim_visual::Surface{true, mu, bounce, pair}; }),
           py::arg("mu"), py::arg("bounce"), py::arg("pair"));

  py::class_<Physics>(m, "Physics", "An ODE world of one field: static geometry, the ball and robot cylinders.")
      .def(py::init([](double gravity, double erp, double cfm, double ball_mass, double ball_radius,
                       double rolling_decel, double net_keep, double bounce_min_speed, double on_ground_tolerance) {
             return new Physics(gravity, erp, cfm,
                                {ball_mass, ball_radius, rolling_decel, net_keep, bounce_min_speed,
                                 on_ground_tolerance});
           }),
           py::arg("gravity"), py::arg("erp"), py::arg("cfm"), py::arg("ball_mass"), py::arg("ball_radius"),
           py::arg("rolling_decel"), py::arg("net_keep"), py::arg("bounce_min_speed"),
           py::arg("on_ground_tolerance"))
      .def("add_plane", &Physics::add_plane, py::arg("kind"), py::arg("category"), py::arg("collide"))
      .def("add_box", &Physics::add_box, py::arg("kind"), py::arg("category"), py::arg("collide"), py::arg("size"),
           py::arg("centre"))
      .def("add_cylinder", &Physics::add_cylinder, py::arg("kind"), py::arg("category"), py::arg("collide"),
           py::arg("radius"), py::arg("length"), py::arg("centre"))
      .def("set_surface", &Physics::set_surface, py::arg("kind_a"), py::arg("kind_b"), py::arg("surface"))
      .def("add_ball", &Physics::add_ball, py::arg("category"), py::arg("collide"))
      .def("add_robot", &Physics::add_robot, py::arg("mass"), py::arg("inertia_zz"), py::arg("radius"),
           py::arg("height"), py::arg("category"), py::arg("collide"))
      .def("remove_robot", &Physics::remove_robot, py::arg("robot"))
      .def(
          "robot_state", [](const Physics& p, int robot) { return p.robot_state(robot); }, py::arg("robot"))
      .def("robot_states", &Physics::robot_states)
      .def(
          "set_robot_state",
          [](Physics& p, int robot, const std::array<double, 6>& s) { p.set_robot_state(robot, finite(s, "a state")); },
          py::arg("robot"), py::arg("state"))
      .def("heading", &Physics::heading, py::arg("robot"))
      .def(
          "drive_robots",
          [](Physics& p, double dt, double time, long steps, double timeout, int stuck_every, double min_command,
             double filter_time, double stuck_time, double linear_accel, double linear_brake, double angular_accel) {
            p.drive_robots(finite(dt, "dt"), finite(time, "time"), steps,
                           {timeout, stuck_every, {min_command, filter_time, stuck_time},
                            {linear_accel, linear_brake, angular_accel}});
          },
          py::arg("dt"), py::arg("time"), py::arg("steps"), py::arg("timeout"), py::arg("stuck_every"),
          py::arg("min_command"), py::arg("filter_time"), py::arg("stuck_time"), py::arg("linear_accel"),
          py::arg("linear_brake"), py::arg("angular_accel"))
      .def(
          "set_command",
          [](Physics& p, int robot, double vx, double vy, double w, double time) {
            sim_visual::Base& b = p.base(robot);
            b.command = finite(std::array<double, 3>{vx, vy, w}, "a command");
            b.command_time = time;
          },
          py::arg("robot"), py::arg("vx"), py::arg("vy"), py::arg("w"), py::arg("time"))
      .def(
          "command", [](const Physics& p, int robot) { return p.base(robot).command; }, py::arg("robot"))
      .def(
          "set_by_wheels", [](Physics& p, int robot, bool on) { p.base(robot).by_wheels = on; }, py::arg("robot"),
          py::arg("by_wheels"))
      .def(
          "set_drive",
          [](Physics& p, int robot, const std::array<double, 3>& drive) {
            p.base(robot).drive = finite(drive, "a drive");
          },
          py::arg("robot"), py::arg("drive"))
      .def(
          "drive_of", [](const Physics& p, int robot) { return p.base(robot).drive; }, py::arg("robot"))
      .def(
          "stuck", [](const Physics& p, int robot) { return p.base(robot).stuck.stuck; }, py::arg("robot"))
      .def(
          "reset_base", [](Physics& p, int robot) { p.base(robot) = sim_visual::Base{}; }, py::arg("robot"))
      .def(
          "drive",
          [](Physics& p, int robot, double vx, double vy, double w, bool world_frame) {
            p.drive(robot, finite(vx, "vx"), finite(vy, "vy"), finite(w, "w"), world_frame);
          },
          py::arg("robot"), py::arg("vx"), py::arg("vy"), py::arg("w"), py::arg("world_frame"))
      .def(
          "set_handler",
          [](Physics& p, double dribble_distance, double dribble_half_angle, double hold_distance, double forward,
             double backward, double sideways, double turn, double slip_time, double recapture_delay,
             double ball_radius) {
            p.set_handler({dribble_distance, dribble_half_angle, hold_distance, forward, backward, sideways, turn,
                           slip_time, recapture_delay, ball_radius});
          },
          py::arg("dribble_distance"), py::arg("dribble_half_angle"), py::arg("hold_distance"), py::arg("forward"),
          py::arg("backward"), py::arg("sideways"), py::arg("turn"), py::arg("slip_time"),
          py::arg("recapture_delay"), py::arg("ball_radius"))
      .def("grip_slips", &Physics::grip_slips, py::arg("holder"), py::arg("dt"), py::arg("time"))
      .def("can_capture", &Physics::can_capture, py::arg("robot"), py::arg("time"))
      .def("first_capture", &Physics::first_capture, py::arg("time"))
      .def("carry_ball", &Physics::carry_ball, py::arg("holder"))
      .def(
          "set_dribbling", [](Physics& p, int robot, bool on) { p.base(robot).dribbling = on; }, py::arg("robot"),
          py::arg("on"))
      .def(
          "dribbling", [](const Physics& p, int robot) { return p.base(robot).dribbling; }, py::arg("robot"))
      .def(
          "set_no_capture_until",
          [](Physics& p, int robot, double time) { p.base(robot).no_capture_until = time; }, py::arg("robot"),
          py::arg("time"))
      .def("ball_state", &Physics::ball_state)
      .def("ball_x", [](const Physics& p) { return p.ball_state()[0]; })
      .def(
          "set_ball_state",
          [](Physics& p, const std::array<double, 9>& s) { p.set_ball_state(finite(s, "a ball state")); },
          py::arg("state"))
      .def("ball_on_ground", &Physics::ball_on_ground)
      .def("set_ball_holder", &Physics::set_ball_holder, py::arg("robot"))
      .def("step", &Physics::step, py::arg("dt"))
      .def("step_seconds", &Physics::step_seconds)
      .def("solver_errors", &Physics::solver_errors)
      .def(
          "set_base_params",
          [](Physics& p, double timeout, int stuck_every, double min_command, double filter_time, double stuck_time,
             double linear_accel, double linear_brake, double angular_accel) {
            const auto stuck = finite(std::array<double, 3>{min_command, filter_time, stuck_time}, "stuck detection");
            const auto limits = finite(std::array<double, 3>{linear_accel, linear_brake, angular_accel}, "drive limits");
            p.set_base_params({finite(timeout, "timeout"), stuck_every, {stuck[0], stuck[1], stuck[2]},
                               {limits[0], limits[1], limits[2]}});
          },
          py::arg("timeout"), py::arg("stuck_every"), py::arg("min_command"), py::arg("filter_time"),
          py::arg("stuck_time"), py::arg("linear_accel"), py::arg("linear_brake"), py::arg("angular_accel"))
      .def("set_goal_line", &Physics::set_goal_line, py::arg("x"))
      .def(
          "advance",
          [](Physics& p, double dt, double time, long steps, int holder) -> py::object {
            const auto out = p.advance(finite(dt, "dt"), finite(time, "time"), steps, holder);
            // The usual step: nothing happened to the ball and no goal is possible; one object, no tuple to build.
            if (out.touched.empty() && !out.slipped && out.captured < 0 && p.ball_short_of_goal_lines()) {
              return py::none();
            }
            return py::make_tuple(out.touched, out.slipped, out.captured);
          },
          py::arg("dt"), py::arg("time"), py::arg("steps"), py::arg("holder"))
      .def("body", &Physics::body, py::arg("robot"))
      .def(
          "set_body", [](Physics& p, int robot, const sim_visual::BodyRow& r) { p.set_body(robot, finite(r, "a body")); },
          py::arg("robot"), py::arg("row"))
      .def("pairs_offered", &Physics::pairs_offered);
}

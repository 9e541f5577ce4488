// nubot_control._kernels: the compiled cores under nubot_control's Python API (see nubot_control/mpc.py).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "nubot_control/format.hpp"
#include "nubot_control/motion.hpp"
#include "nubot_control/mpc.hpp"
#include "nubot_control/path_planning.hpp"
#include "nubot_control/trajectory.hpp"

namespace py = pybind11;
using nubot_control::LaguerreMpc;
using nubot_control::MpcParams;
using nubot_control::RowMatrix;

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::string shape_text(const std::vector<py::ssize_t>& shape) {
  std::string text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
  return text + (shape.size() == 1 ? ",)" : ")");
}

// ``value`` as a float array of ``shape`` (rows x cols; cols 0: a vector), else std::invalid_argument naming it.
Array as_array(const py::object& value, const char* name, py::ssize_t rows, py::ssize_t cols) {
  const std::vector<py::ssize_t> wanted = cols ? std::vector<py::ssize_t>{rows, cols} : std::vector<py::ssize_t>{rows};
  Array array = Array::ensure(value);
  if (!array) {
    PyErr_Clear();
    throw std::invalid_argument(std::string(name) + " must be numbers of shape " + shape_text(wanted) + ", got " +
                                std::string(py::repr(value)));
  }
  const std::vector<py::ssize_t> shape(array.shape(), array.shape() + array.ndim());
  if (shape != wanted) {
    throw std::invalid_argument(std::string(name) + " must have shape " + shape_text(wanted) + ", got " +
                                shape_text(shape));
  }
  return array;
}

Eigen::Map<const RowMatrix> as_matrix(const Array& array) {
  return {array.data(), array.shape(0), array.ndim() == 2 ? array.shape(1) : 1};
}

// std::invalid_argument from the core, with the offending value as Python prints it when it is not finite.
void require_finite(const Array& array, const char* name) {
  if (!as_matrix(array).allFinite()) {
    throw std::invalid_argument(std::string(name) + " must be finite, got " + std::string(py::str(array.attr("tolist")())));
  }
}

// ``value`` as a point (x, y) of finite floats, else std::invalid_argument naming it as the planner always has.
nubot_control::Vec2 finite_point(const py::handle& value, const std::string& name) {
  double xy[2];
  try {
    const py::list items(py::reinterpret_borrow<py::object>(value));
    if (items.size() != 2) throw py::value_error("not two numbers");
    for (std::size_t i = 0; i < 2; ++i) xy[i] = py::float_(items[i]).cast<double>();
  } catch (const py::error_already_set&) {
    throw std::invalid_argument(name + " must be a point (x, y), got " + std::string(py::repr(value)));
  } catch (const py::value_error&) {
    throw std::invalid_argument(name + " must be a point (x, y), got " + std::string(py::repr(value)));
  }
  if (!(std::isfinite(xy[0]) && std::isfinite(xy[1]))) {
    throw std::invalid_argument(name + " must be finite, got " + std::string(py::repr(value)));
  }
  return {xy[0], xy[1]};
}

std::vector<nubot_control::Disc> discs(const Array& table) {
  if (table.ndim() != 2 || (table.shape(0) > 0 && table.shape(1) != 3)) {
    throw std::invalid_argument("obstacles must be a table of (x, y, radius) rows");
  }
  std::vector<nubot_control::Disc> out;
  for (py::ssize_t i = 0; i < table.shape(0); ++i) {
    const nubot_control::Disc d{table.at(i, 0), table.at(i, 1), table.at(i, 2)};
    if (!(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.radius) && d.radius >= 0.0)) {
      throw std::invalid_argument("obstacle " + std::to_string(i) + " must be finite with a radius not negative, got (" +
                                  nubot_control::format_float(d.x) + ", " + nubot_control::format_float(d.y) + ", " +
                                  nubot_control::format_float(d.radius) + ")");
    }
    out.push_back(d);
  }
  return out;
}

nubot_control::PlannerParams planner_params(const py::handle& p) {
  return {p.attr("robot_radius").cast<double>(),      p.attr("safety_margin").cast<double>(),
          p.attr("max_speed").cast<double>(),         p.attr("max_accel").cast<double>(),
          p.attr("max_lateral_accel").cast<double>(), p.attr("sample_step").cast<double>(),
          p.attr("max_subtargets").cast<int>(),       p.attr("detour_factor").cast<double>()};
}

nubot_control::Bounds bounds_of(const py::handle& b) {
  return {b.attr("x_min").cast<double>(), b.attr("x_max").cast<double>(), b.attr("y_min").cast<double>(),
          b.attr("y_max").cast<double>()};
}

// A trajectory's sample times (n,) and (n, 2) rows of the same n, else std::invalid_argument.
void require_samples(const Array& t, const Array& rows, const char* name) {
  if (t.ndim() != 1 || t.shape(0) < 1) throw std::invalid_argument("t must be a vector of at least one sample time");
  if (rows.ndim() != 2 || rows.shape(0) != t.shape(0) || rows.shape(1) != 2) {
    throw std::invalid_argument(std::string(name) + " must be (n, 2) rows for the n = " + std::to_string(t.shape(0)) +
                                " sample times");
  }
}

Eigen::Map<const Eigen::VectorXd> as_vector(const Array& array) { return {array.data(), array.shape(0)}; }

Eigen::Map<const nubot_control::Rows2> as_rows(const Array& array) { return {array.data(), array.shape(0), 2}; }

py::list point_list(const std::vector<nubot_control::Vec2>& points) {
  py::list out;
  for (const auto& p : points) out.append(py::make_tuple(p.x(), p.y()));
  return out;
}

// The motion layer's obstacles: each (x, y) (a robot) or (x, y, keep) (a centre kept that far), numbers.
std::vector<nubot_control::Sighting> sightings(const py::iterable& obstacles) {
  std::vector<nubot_control::Sighting> out;
  for (const py::handle o : obstacles) {
    const auto refuse = [&o]() {
      return std::invalid_argument("an obstacle is (x, y) or (x, y, keep) in numbers, got " + std::string(py::repr(o)));
    };
    if (!py::isinstance<py::sequence>(o)) throw refuse();
    const auto row = py::reinterpret_borrow<py::sequence>(o);
    const auto size = py::len(row);
    if (size < 2) throw refuse();
    try {
      out.push_back({py::float_(row[0]).cast<double>(), py::float_(row[1]).cast<double>(),
                     size > 2 ? py::float_(row[2]).cast<double>() : 0.0, size > 2});
    } catch (const py::error_already_set&) {
      throw refuse();
    }
  }
  return out;
}

// The areas to keep out of: each (x0, x1, y0, y1) [m].
std::vector<nubot_control::Rect> rects(const py::iterable& areas) {
  std::vector<nubot_control::Rect> out;
  for (const py::handle a : areas) {
    try {
      const py::sequence row = py::reinterpret_borrow<py::sequence>(a);
      if (!py::isinstance<py::sequence>(a) || py::len(row) != 4) throw py::value_error("not four numbers");
      out.push_back({py::float_(row[0]).cast<double>(), py::float_(row[1]).cast<double>(),
                     py::float_(row[2]).cast<double>(), py::float_(row[3]).cast<double>()});
    } catch (const py::error_already_set&) {
      throw std::invalid_argument("an area is (x0, x1, y0, y1) in numbers, got " + std::string(py::repr(a)));
    } catch (const py::value_error&) {
      throw std::invalid_argument("an area is (x0, x1, y0, y1) in numbers, got " + std::string(py::repr(a)));
    }
  }
  return out;
}

// A point (x, y) of numbers (finite or not: the caller's rules decide), else std::invalid_argument naming it.
nubot_control::Vec2 point(const py::handle& value, const std::string& name) {
  try {
    const py::sequence items = py::reinterpret_borrow<py::sequence>(value);
    if (!py::isinstance<py::sequence>(value) || py::len(items) != 2) throw py::value_error("not two numbers");
    return {py::float_(items[0]).cast<double>(), py::float_(items[1]).cast<double>()};
  } catch (const py::error_already_set&) {
    throw std::invalid_argument(name + " must be a point (x, y), got " + std::string(py::repr(value)));
  } catch (const py::value_error&) {
    throw std::invalid_argument(name + " must be a point (x, y), got " + std::string(py::repr(value)));
  }
}

std::vector<nubot_control::Vec2> points(const py::iterable& values, const std::string& name) {
  std::vector<nubot_control::Vec2> out;
  std::size_t i = 0;
  for (const py::handle v : values) out.push_back(point(v, name + "[" + std::to_string(i++) + "]"));
  return out;
}

nubot_control::MotionParams motion_params(const py::handle& p) {
  const auto f = [&p](const char* name) { return p.attr(name).cast<double>(); };
  return {p.attr("tracker").cast<std::string>() == "mpc", f("max_speed"), f("max_accel"), f("max_lateral_accel"),
          f("max_rot_speed"), f("max_rot_accel"), f("dribble_speed"), f("dribble_back_speed"),
          f("dribble_side_speed"), f("dribble_rot_speed"), f("dribble_accel"), f("replan_tolerance"),
          f("keep_plan_deviation"), f("keep_plan_goal_shift"), f("keep_plan_goal_share"), f("keep_plan_time"),
          f("plan_share"), f("planning_range"), f("position_gain"), f("heading_gain"), f("clearance"),
          f("contact_margin"), f("contact_brake"), f("contact_latency")};
}

py::tuple pair(const nubot_control::Vec2& v) { return py::make_tuple(v.x(), v.y()); }

}  // namespace

PYBIND11_MODULE(_kernels, m) {
  m.doc() = "nubot_control's compiled kernels: the Laguerre MPC tracker (nubot_control.mpc) and the path planner "
            "(nubot_control.path_planning).";

  m.def(
      "subtargets",
      [](const py::object& start, const py::object& goal, const Array& obstacles, const py::object& params,
         const py::object& bounds) {
        const auto a = finite_point(start, "start"), b = finite_point(goal, "goal");
        return point_list(nubot_control::subtargets(a, b, discs(obstacles), planner_params(params), bounds_of(bounds)));
      },
      py::arg("start"), py::arg("goal"), py::arg("obstacles"), py::arg("params"), py::arg("bounds"),
      "Via-points between start and goal (see nubot_control.path_planning.subtargets); obstacles: (k, 3) rows.");

  m.def(
      "plan",
      [](const py::object& start, const py::object& waypoints, const Array& obstacles, const py::object& params,
         const py::object& bounds, const py::object& start_velocity, double end_speed) {
        const auto p0 = finite_point(start, "start");
        std::vector<nubot_control::Vec2> points;
        std::size_t i = 0;
        for (const py::handle w : waypoints) points.push_back(finite_point(w, "waypoints[" + std::to_string(i++) + "]"));
        if (points.empty()) throw std::invalid_argument("waypoints must not be empty: the last one is the goal");
        const auto v0 = finite_point(start_velocity, "start_velocity");
        if (!(std::isfinite(end_speed) && end_speed >= 0.0)) {
          throw std::invalid_argument("end_speed must be finite and not negative, got " +
                                      nubot_control::format_float(end_speed));
        }
        const auto result = nubot_control::plan(p0, points, discs(obstacles), planner_params(params),
                                                bounds_of(bounds), v0, end_speed);
        return py::make_tuple(result.t, result.s, result.xy, result.v, point_list(result.via));
      },
      py::arg("start"), py::arg("waypoints"), py::arg("obstacles"), py::arg("params"), py::arg("bounds"),
      py::arg("start_velocity"), py::arg("end_speed"),
      "The trajectory's (t, s, xy, v, via) (see nubot_control.path_planning.plan); obstacles: (k, 3) rows.");

  m.def(
      "keeps_clear",
      [](const py::object& path, const py::object& ends, const Array& obstacles, double margin, double tolerance) {
        const Array xy = Array::ensure(path);
        if (!xy || xy.ndim() != 2 || xy.shape(1) != 2) {
          PyErr_Clear();
          throw std::invalid_argument("path must be an (n, 2) array of points");
        }
        std::vector<nubot_control::Vec2> points;
        std::size_t i = 0;
        for (const py::handle e : ends) points.push_back(finite_point(e, "ends[" + std::to_string(i++) + "]"));
        return nubot_control::keeps_clear(as_rows(xy), points, discs(obstacles), margin, tolerance);
      },
      py::arg("path"), py::arg("ends"), py::arg("obstacles"), py::arg("margin"), py::arg("tolerance"),
      "Whether the path keeps the obstacles' clearances (see nubot_control.path_planning.keeps_clear).");

  m.def(
      "trajectory_states",
      [](const Array& t, const Array& xy, const Array& v, const Array& times) {
        require_samples(t, xy, "xy");
        require_samples(t, v, "v");
        if (times.ndim() != 1) throw std::invalid_argument("times must be a vector");
        nubot_control::Rows2 out_xy, out_v;
        nubot_control::trajectory_states(as_vector(t), as_rows(xy), as_rows(v), as_vector(times), out_xy, out_v);
        return py::make_tuple(out_xy, out_v);
      },
      py::arg("t"), py::arg("xy"), py::arg("v"), py::arg("times"),
      "Positions and velocities (m, 2) at the m times (see nubot_control.path_planning.Trajectory.states_at).");

  m.def(
      "within_accel",
      [](const Array& t, const Array& v, double until, double accel, double rounding) {
        require_samples(t, v, "v");
        return nubot_control::within_accel(as_vector(t), as_rows(v), until, accel, rounding);
      },
      py::arg("t"), py::arg("v"), py::arg("until"), py::arg("accel"), py::arg("rounding"),
      "Whether the velocity changes no faster than accel * (1 + rounding) up to the first sample after until.");

  m.def(
      "obstacle_table",
      [](double mx, double my, const Array& goals, const py::iterable& obstacles, double robot_radius,
         double clearance, double planning_range) {
        if (goals.ndim() != 2 || goals.shape(1) != 3) throw std::invalid_argument("goals must be (k, 3) rows");
        const std::vector<nubot_control::Sighting> found = sightings(obstacles);
        std::vector<double> table;
        table.reserve(3 * (goals.shape(0) + found.size()));
        nubot_control::obstacle_table(mx, my, Eigen::Map<const nubot_control::Rows3>(goals.data(), goals.shape(0), 3),
                                      found, robot_radius, clearance, planning_range, table);
        Array out({static_cast<py::ssize_t>(table.size() / 3), py::ssize_t{3}});
        std::copy(table.begin(), table.end(), out.mutable_data());
        return out;
      },
      py::arg("mx"), py::arg("my"), py::arg("goals"), py::arg("obstacles"), py::arg("robot_radius"),
      py::arg("clearance"), py::arg("planning_range"),
      "The planner's obstacle table (k, 3) (see nubot_control.motion.MotionController).");

  m.def(
      "sub_target",
      [](const py::object& start, const py::object& goal, const py::iterable& obstacles, double clearance) {
        return pair(nubot_control::sub_target(point(start, "start"), point(goal, "goal"), sightings(obstacles),
                                              clearance));
      },
      py::arg("start"), py::arg("goal"), py::arg("obstacles"), py::arg("clearance"),
      "The first point to head for round the obstacles (see nubot_control.motion.sub_target).");

  m.def(
      "keep_clear",
      [](const py::object& position, const py::object& velocity, const py::iterable& robots, double min_distance,
         double brake, double latency, double in_the_way) {
        return pair(nubot_control::keep_clear(point(position, "position"), point(velocity, "velocity"),
                                              points(robots, "robots"), min_distance, brake, latency, in_the_way));
      },
      py::arg("position"), py::arg("velocity"), py::arg("robots"), py::arg("min_distance"), py::arg("brake"),
      py::arg("latency"), py::arg("in_the_way"),
      "The velocity without what would drive into a robot (see nubot_control.motion.keep_clear).");

  m.def(
      "stay_out",
      [](const py::object& position, const py::object& velocity, const py::iterable& areas, double brake,
         double latency) {
        return pair(nubot_control::stay_out(point(position, "position"), point(velocity, "velocity"), rects(areas),
                                            brake, latency));
      },
      py::arg("position"), py::arg("velocity"), py::arg("rects"), py::arg("brake"), py::arg("latency"),
      "The velocity without what would take the robot into an area (see nubot_control.areas.stay_out).");

  m.def(
      "dribble_scale",
      [](double bx, double by, const py::object& params) {
        return nubot_control::dribble_scale(bx, by, motion_params(params));
      },
      py::arg("bx"), py::arg("by"), py::arg("params"),
      "The factor that brings the body velocity within what the ball handler keeps.");

  py::class_<nubot_control::MotionCore>(m, "MotionCore", "One robot's motion layer (see nubot_control.motion).")
      .def(py::init([](const py::object& params, const py::object& planner, double robot_radius,
                       const py::object& bounds, const Array& goal_table, const py::object& mpc,
                       double accel_rounding, double intrusion_tolerance) {
             if (goal_table.ndim() != 2 || goal_table.shape(1) != 3) {
               throw std::invalid_argument("goal_table must be (k, 3) rows");
             }
             LaguerreMpc* tracker = mpc.is_none() ? nullptr : mpc.cast<LaguerreMpc*>();
             return nubot_control::MotionCore(
                 motion_params(params), planner_params(planner), robot_radius, bounds_of(bounds),
                 Eigen::Map<const nubot_control::Rows3>(goal_table.data(), goal_table.shape(0), 3), tracker,
                 accel_rounding, intrusion_tolerance);
           }),
           py::arg("params"), py::arg("planner"), py::arg("robot_radius"), py::arg("bounds"), py::arg("goal_table"),
           py::arg("mpc"), py::arg("accel_rounding"), py::arg("intrusion_tolerance"),
           py::keep_alive<1, 7>())  // the tracker lives as long as the motion layer
      .def("reset", &nubot_control::MotionCore::reset)
      .def(
          "follow",
          [](nubot_control::MotionCore& self, double x, double y, double theta, const py::iterable& waypoints,
             double heading, const py::iterable& obstacles, double dt, std::optional<double> speed_limit, bool holding,
             const py::iterable& no_go, bool urgent) {
            const Eigen::Vector3d c = self.follow({x, y, theta}, points(waypoints, "waypoints"), heading,
                                                  sightings(obstacles), dt, speed_limit, holding, rects(no_go), urgent);
            return py::make_tuple(c.x(), c.y(), c.z());
          },
          py::arg("x"), py::arg("y"), py::arg("theta"), py::arg("waypoints"), py::arg("heading"), py::arg("obstacles"),
          py::arg("dt"), py::arg("speed_limit"), py::arg("holding"), py::arg("no_go"), py::arg("urgent"),
          "One cycle's body-frame command (vx, vy, w) (see nubot_control.motion.MotionController.follow).")
      .def_property_readonly("plan_count", &nubot_control::MotionCore::plan_count,
                             "How many plans were made: which plan is followed.")
      .def_property_readonly("has_plan", &nubot_control::MotionCore::has_plan)
      .def(
          "plan",
          [](const nubot_control::MotionCore& self) {
            const auto& r = self.plan();
            return py::make_tuple(r.t, r.s, r.xy, r.v, point_list(r.via));
          },
          "The plan followed: (t, s, xy, v, via) copies.")
      .def_property_readonly("plan_age", &nubot_control::MotionCore::plan_age)
      .def_property_readonly(
          "reference",
          [](const nubot_control::MotionCore& self) -> py::object {
            if (!self.has_reference()) return py::none();
            return py::make_tuple(pair(self.reference_position()), pair(self.reference_velocity()));
          },
          "((x, y), (vx, vy)): where the robot should be now and how fast; None before a cycle.")
      .def_property_readonly(
          "waypoints", [](const nubot_control::MotionCore& self) { return py::tuple(point_list(self.waypoints())); },
          "What remains of the route, the goal last.")
      .def_property_readonly("velocity", [](const nubot_control::MotionCore& self) { return pair(self.velocity()); },
                             "The last commanded velocity, team frame [m/s].")
      .def_property_readonly("w", &nubot_control::MotionCore::w, "The last commanded turn rate [rad/s].");

  m.def("laguerre_basis", &nubot_control::laguerre_basis, py::arg("pole"), py::arg("terms"), py::arg("steps"),
        "Discrete Laguerre functions: row i is L(i)^T, shape (steps, terms).");

  py::class_<LaguerreMpc>(m, "LaguerreMpc", "Laguerre-parameterised MPC for a planar integrator.")
      .def(py::init([](double dt, int horizon, int laguerre_terms, double laguerre_pole, double position_weight,
                       double effort_weight, double max_speed, double max_accel, int polygon_sides,
                       int constrained_steps, int solver_iterations) {
             return LaguerreMpc(MpcParams{dt, horizon, laguerre_terms, laguerre_pole, position_weight, effort_weight,
                                          max_speed, max_accel, polygon_sides, constrained_steps, solver_iterations});
           }),
           py::kw_only(), py::arg("dt"), py::arg("horizon"), py::arg("laguerre_terms"), py::arg("laguerre_pole"),
           py::arg("position_weight"), py::arg("effort_weight"), py::arg("max_speed"), py::arg("max_accel"),
           py::arg("polygon_sides"), py::arg("constrained_steps"), py::arg("solver_iterations"))
      .def(
          "command",
          [](LaguerreMpc& self, const py::object& position, const py::object& previous,
             const py::object& ref_positions, const py::object& ref_velocities, std::optional<double> max_speed,
             std::optional<double> max_accel) {
            const int h = self.params().horizon;
            const Array p = as_array(position, "position", 2, 0), u = as_array(previous, "previous", 2, 0);
            const Array r = as_array(ref_positions, "ref_positions", h + 1, 2);
            const Array v = as_array(ref_velocities, "ref_velocities", h, 2);
            require_finite(p, "position");
            require_finite(u, "previous");
            require_finite(r, "ref_positions");
            require_finite(v, "ref_velocities");
            return self.command(Eigen::Vector2d(p.at(0), p.at(1)), Eigen::Vector2d(u.at(0), u.at(1)), as_matrix(r),
                                as_matrix(v), max_speed, max_accel);
          },
          py::arg("position"), py::arg("previous"), py::arg("ref_positions"), py::arg("ref_velocities"),
          py::arg("max_speed") = py::none(), py::arg("max_accel") = py::none(),
          "World-frame velocity (2,) for this cycle (see nubot_control.mpc.LaguerreMpc.command).")
      .def_property_readonly("fallbacks", &LaguerreMpc::fallbacks,
                             "How many calls used the fallback rule instead of the QP's answer.")
      .def_property_readonly("last_status", &LaguerreMpc::last_status,
                             "How the last command was found: 'unconstrained', 'solved' (by the QP solver), or "
                             "'fallback: <reason>'.")
      .def(
          "last_qp",
          [](const LaguerreMpc& self) {
            return py::make_tuple(self.qp_hessian(), self.qp_gradient(), self.qp_rows(), self.qp_lower(),
                                  self.qp_upper());
          },
          "The QP of the last call: (hessian, gradient, rows, lower, upper), minimise 0.5 x'Hx + q'x with "
          "lower <= rows x <= upper (copies).");
}

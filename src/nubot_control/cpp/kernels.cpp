// nubot_control._kernels: the compiled cores under nubot_control's Python API (see nubot_control/mpc.py).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>

#include "nubot_control/mpc.hpp"

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

}  // namespace

PYBIND11_MODULE(_kernels, m) {
  m.doc() = "nubot_control's compiled kernels: the Laguerre MPC tracker (see nubot_control.mpc).";

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

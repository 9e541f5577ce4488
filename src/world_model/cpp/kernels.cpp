// world_model._kernels: the compiled cores under world_model's Python API (see world_model/obstacles.py).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "world_model/obstacles.hpp"

namespace py = pybind11;
using world_model::ObstacleTracker;
using world_model::Point;

PYBIND11_MODULE(_kernels, m) {
  m.doc() = "world_model's compiled kernels: the obstacle tracker (see world_model.obstacles).";

  py::class_<ObstacleTracker>(m, "ObstacleTracker", "Own obstacle percepts of successive frames, followed as tracks.")
      .def(py::init<double, double, double, double, double>(), py::arg("gate"), py::arg("position_gain"),
           py::arg("velocity_gain"), py::arg("coast"), py::arg("max_speed"))
      .def("reset", &ObstacleTracker::reset)
      .def("update", &ObstacleTracker::update, py::arg("stamp"), py::arg("percepts"),
           "The obstacles of the frame taken at ``stamp`` [s]; a frame not newer than the last is ignored.")
      .def(
          "estimate",
          [](const ObstacleTracker& self, double t) {
            std::vector<Point> positions, velocities;
            self.estimate(t, positions, velocities);
            py::tuple p(positions.size()), v(velocities.size());
            for (std::size_t i = 0; i < positions.size(); ++i) {
              p[i] = py::make_tuple(positions[i][0], positions[i][1]);
              v[i] = py::make_tuple(velocities[i][0], velocities[i][1]);
            }
            return py::make_tuple(p, v);
          },
          py::arg("t"),
          "The tracks of the last ``coast`` [s] before the latest frame, moved on to ``t`` [s]: (positions [m], "
          "velocities [m/s]), in the same order.");
}

// world_model._kernels: the compiled cores under world_model's Python API (see world_model/obstacles.py).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tuple>
#include <vector>

#include "world_model/labels.hpp"
#include "world_model/obstacles.hpp"

namespace py = pybind11;
using world_model::Labelled;
using world_model::ObstacleTracker;
using world_model::Point;
using world_model::Seen;

PYBIND11_MODULE(_kernels, m) {
  m.doc() = "world_model's compiled kernels: the obstacle tracker and labelling (see world_model.obstacles).";

  m.def(
      "label_obstacles",
      [](double mx, double my, double mtheta, int agent_id, const std::vector<Point>& own,
         const std::vector<std::tuple<int, double, double>>& reported,
         const std::vector<std::tuple<int, double, double>>& mates, double teammate_radius, double merge_radius) {
        const auto seen = [](const std::vector<std::tuple<int, double, double>>& rows) {
          std::vector<Seen> out;
          out.reserve(rows.size());
          for (const auto& [id, x, y] : rows) out.push_back({id, x, y});
          return out;
        };
        const std::vector<Labelled> labelled = world_model::label_obstacles(
            {mx, my, mtheta}, agent_id, own, seen(reported), seen(mates), teammate_radius, merge_radius);
        py::list out(labelled.size());
        for (std::size_t i = 0; i < labelled.size(); ++i) {
          const Labelled& o = labelled[i];
          out[i] = py::make_tuple(o.x, o.y, o.observer, o.teammate, o.angle, o.radius);
        }
        return out;
      },
      py::arg("mx"), py::arg("my"), py::arg("mtheta"), py::arg("agent_id"), py::arg("own"), py::arg("reported"),
      py::arg("mates"), py::arg("teammate_radius"), py::arg("merge_radius"),
      "Own obstacles, then the teammates' (observer, x, y) not already listed nor this robot, each labelled with the "
      "teammate (AgentID, x, y) it is: a list of (x, y, observer, teammate (0: an opponent), bearing [rad], "
      "distance [m]) from this robot at (mx, my, mtheta).");

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

// world_model._kernels: the compiled cores under world_model's Python API (see world_model/obstacles.py).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <tuple>
#include <vector>

#include "world_model/fusion.hpp"
#include "world_model/labels.hpp"
#include "world_model/obstacles.hpp"

namespace py = pybind11;
using world_model::Fusion;
using world_model::Labelled;
using world_model::ObstacleTracker;
using world_model::Point;
using world_model::Seen;


namespace {

// A ball given as None or (stamp, x, y, vx, vy, velocity_known).
std::optional<world_model::Ball> ball_of(const py::object& value) {
  if (value.is_none()) return std::nullopt;
  const auto [stamp, x, y, vx, vy, known] = value.cast<std::tuple<double, double, double, double, double, bool>>();
  return world_model::Ball{stamp, x, y, vx, vy, known};
}

py::object ball_tuple(const world_model::OwnBall& own) {
  if (!own.known) return py::none();
  const world_model::Ball& b = own.ball;
  return py::make_tuple(b.stamp, b.x, b.y, b.vx, b.vy, b.velocity_known);
}

py::tuple points_tuple(const std::vector<Point>& points) {
  py::tuple out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) out[i] = py::make_tuple(points[i][0], points[i][1]);
  return out;
}

}  // namespace

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

  py::class_<Fusion>(m, "Fusion", "One robot's world model, the numbers of it (see world_model.world_model).")
      .def(py::init([](const py::object& params, int agent_id, double half_length, double half_width, double border,
                       double ball_radius) {
             const auto f = [&params](const char* name) { return params.attr(name).cast<double>(); };
             return Fusion(world_model::FusionParams{
                 params.attr("team_size").cast<int>(), agent_id, f("teammate_timeout"), f("strategy_timeout"),
                 f("ball_timeout"), f("velocity_window"), params.attr("min_fit_samples").cast<int>(),
                 f("teammate_radius"), f("obstacle_merge_radius"), f("ball_agreement_radius"),
                 f("sighting_confidence"), f("sensor_timeout"), f("air_margin"), f("obstacle_gate"),
                 f("obstacle_position_gain"), f("obstacle_velocity_gain"), f("obstacle_coast"),
                 f("obstacle_max_speed"), half_length, half_width, border, ball_radius});
           }),
           py::arg("params"), py::arg("agent_id"), py::arg("half_length"), py::arg("half_width"), py::arg("border"),
           py::arg("ball_radius"))
      .def("note_time", &Fusion::note_time, py::arg("t"),
           "The clock: True when t went back by more than a second and everything was forgotten.")
      .def(
          "on_vision",
          [](Fusion& self, double stamp, double x, double y, double theta, bool valid, const py::object& ball,
             const std::vector<Point>& obstacles) {
            return self.on_vision(stamp, {x, y, theta}, valid, ball_of(ball), obstacles);
          },
          py::arg("stamp"), py::arg("x"), py::arg("y"), py::arg("theta"), py::arg("valid"), py::arg("ball"),
          py::arg("obstacles"), "Own percepts; whether the ball (stamp, x, y, vx, vy, known) or None was kept.")
      .def("on_front_ball", &Fusion::on_front_ball, py::arg("stamp"), py::arg("rx"), py::arg("ry"))
      .def(
          "on_ball3d",
          [](Fusion& self, double stamp, double x, double y, double z, double vx, double vy, double vz, bool known) {
            return self.on_ball3d({stamp, x, y, z, vx, vy, vz, known});
          },
          py::arg("stamp"), py::arg("x"), py::arg("y"), py::arg("z"), py::arg("vx"), py::arg("vy"), py::arg("vz"),
          py::arg("velocity_known"), "The 3-D ball; whether it was taken.")
      .def(
          "on_teammate",
          [](Fusion& self, double t, int agent_id, double stamp, double x, double y, double theta, bool valid,
             const py::object& ball, const std::vector<Point>& obstacles) -> py::object {
            if (!self.on_teammate(t, agent_id, stamp, {x, y, theta}, valid, ball_of(ball), obstacles)) {
              return py::none();
            }
            return py::make_tuple(self.mate_stamp(agent_id), self.mate_ball_kept(agent_id));
          },
          py::arg("t"), py::arg("agent_id"), py::arg("stamp"), py::arg("x"), py::arg("y"), py::arg("theta"),
          py::arg("valid"), py::arg("ball"), py::arg("obstacles"),
          "A teammate's packet: None when it was not taken, else (its stamp as taken, whether its ball was kept).")
      .def("on_teammate_strategy", &Fusion::on_teammate_strategy, py::arg("agent_id"), py::arg("stamp"))
      .def(
          "snapshot",
          [](Fusion& self, double t, const py::object& teammate, const py::object& opponent) {
            const world_model::Snapshot s = self.snapshot(t);
            py::tuple robots(s.robots.size()), mate_ball(s.mate_ball.size());
            for (std::size_t i = 0; i < s.robots.size(); ++i) {
              robots[i] = py::make_tuple(s.robots[i].valid, s.robots[i].age);
              mate_ball[i] = py::bool_(s.mate_ball[i]);
            }
            const world_model::FusedBall& b = s.ball;
            py::tuple seen_by(b.seen_by.size());
            for (std::size_t i = 0; i < b.seen_by.size(); ++i) seen_by[i] = b.seen_by[i];
            const py::tuple ball = py::make_tuple(
                b.x, b.y, b.vx, b.vy, b.known, b.velocity_known, b.confidence, seen_by, static_cast<int>(b.source),
                b.source_id, b.stamp, b.angle, b.radius, static_cast<int>(b.sensor));
            py::list obstacles(s.obstacles.size());
            for (std::size_t i = 0; i < s.obstacles.size(); ++i) {
              const Labelled& o = s.obstacles[i];
              const Point v = i < s.velocities.size() ? s.velocities[i] : Point{0.0, 0.0};
              obstacles[i] = py::make_tuple(o.x, o.y, o.teammate ? teammate : opponent, o.teammate, o.observer, o.angle,
                                            o.radius, v[0], v[1]);
            }
            return py::make_tuple(robots, ball_tuple(s.own), mate_ball, ball, obstacles);
          },
          py::arg("t"), py::arg("teammate"), py::arg("opponent"),
          "The fused world at t: (robots ((valid, age [s]) by AgentID), this robot's own ball (stamp, x, y, vx, vy, "
          "known) or None, whether each teammate's own ball counts, the fused ball (FusedBall's fields, source and "
          "sensor as numbers), the obstacles (x, y, label (teammate or opponent, the objects given), teammate "
          "(0: an opponent), observer, bearing, distance, vx, vy): LabelledObstacle's fields).")
      .def(
          "own_view",
          [](const Fusion& self, double t) -> py::object {
            const world_model::OwnView v = self.own_view(t);
            if (!v.known) return py::none();
            return py::make_tuple(v.valid, ball_tuple(v.ball), v.fresh ? points_tuple(v.obstacles) : py::tuple());
          },
          py::arg("t"),
          "What this robot shares at t: (its validity, its own ball or None, its obstacles); None before a vision "
          "frame.");

  m.def("fit_velocity", &world_model::fit_velocity, py::arg("samples"), py::arg("min_samples"),
        "The slope (vx, vy) [m/s] of the least-squares lines x(t), y(t) through (t, x, y) samples; None if "
        "underdetermined.");
  m.def("ball_confidence", &world_model::ball_confidence, py::arg("age"), py::arg("sightings"), py::arg("ball_timeout"),
        py::arg("sighting_confidence"), "Confidence in [0, 1] of a ball this old seen by this many robots.");
  m.def(
      "choose_ball",
      [](const std::vector<std::tuple<int, double, double, double, double, double, double>>& team) {
        std::vector<world_model::Candidate> candidates;
        for (const auto& [agent_id, bx, by, ox, oy, otheta, age] : team) {
          candidates.push_back({agent_id, world_model::Source::Teammate, {0.0, bx, by, 0.0, 0.0, false},
                                {ox, oy, otheta}, age});
        }
        return world_model::choose_ball(candidates);
      },
      py::arg("team"),
      "Which teammate's ball to believe, of (AgentID, ball x, ball y, observer x, y, theta, age) rows: the nearest "
      "to its ball, then the freshest, then the lower AgentID; -1 when none.");
  py::class_<world_model::BallTrack>(m, "BallTrack", "The recent ball observations of one source.")
      .def(py::init<double>(), py::arg("keep"))
      .def(
          "add",
          [](world_model::BallTrack& self, double stamp, double x, double y, double vx, double vy, bool known) {
            self.add({stamp, x, y, vx, vy, known});
          },
          py::arg("stamp"), py::arg("x"), py::arg("y"), py::arg("vx"), py::arg("vy"), py::arg("velocity_known"))
      .def("clear", &world_model::BallTrack::clear)
      .def("__len__", &world_model::BallTrack::size)
      .def_property_readonly(
          "latest",
          [](const world_model::BallTrack& self) -> py::object {
            const world_model::Ball* b = self.latest();
            if (b == nullptr) return py::none();
            return py::make_tuple(b->stamp, b->x, b->y, b->vx, b->vy, b->velocity_known);
          },
          "The newest observation (stamp, x, y, vx, vy, velocity_known), or None.")
      .def("velocity", &world_model::BallTrack::velocity, py::arg("window"), py::arg("min_samples"));
}

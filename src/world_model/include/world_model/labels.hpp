// Obstacles merged from this robot's and its teammates' percepts and labelled teammate or opponent: the compiled
// core of world_model.obstacles.label_obstacles (its docstring states the rules).
#pragma once

#include <array>
#include <vector>

#include "world_model/obstacles.hpp"

namespace world_model {

struct Seen {  // an obstacle a teammate reports, or a teammate's own position
  int agent_id;  // the observer, or the teammate
  double x, y;
};

struct Labelled {
  double x, y;
  int observer;  // AgentID of the robot that saw it
  int teammate;  // the teammate it is, 0 for an opponent
  double angle;   // bearing from this robot's front, in (-pi, pi] [rad] (nubot_common.geometry.Pose2D.bearing_to)
  double radius;  // distance from this robot's centre [m]
};

// Own obstacles first, then the reported ones (by observer, each observer's in order) that are no obstacle already
// listed (farther than merge_radius) and not this robot (farther than teammate_radius from me); each one within
// teammate_radius of a teammate's position is the nearest such teammate (the lower AgentID on a tie). me: (x, y,
// theta) [m, rad].
std::vector<Labelled> label_obstacles(const std::array<double, 3>& me, int agent_id, const std::vector<Point>& own,
                                      std::vector<Seen> reported, std::vector<Seen> mates, double teammate_radius,
                                      double merge_radius);

}  // namespace world_model

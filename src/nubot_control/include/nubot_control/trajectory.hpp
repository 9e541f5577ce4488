// A planned trajectory read back: the state at any time, and whether a robot can follow its first part (the compiled
// core of nubot_control.path_planning.Trajectory.states_at and MotionController's acceleration check). Units SI.
#pragma once

#include <Eigen/Dense>

#include "nubot_control/path_planning.hpp"

namespace nubot_control {

// Positions and velocities at ``times`` on the trajectory sampled at t (increasing, t[0] == 0) with positions xy and
// velocities v; before 0 the first sample's state, after the end the last one's. Between two samples the velocity is
// linear in time and the position moves along the step by the distance covered at that constant acceleration.
void trajectory_states(const Eigen::Ref<const Eigen::VectorXd>& t, const Eigen::Ref<const Rows2>& xy,
                       const Eigen::Ref<const Rows2>& v, const Eigen::Ref<const Eigen::VectorXd>& times, Rows2& out_xy,
                       Rows2& out_v);

// Whether the velocity changes between consecutive samples no faster than accel * (1 + rounding), over the samples up
// to the first one after ``until`` [s] (the part of a plan that may be kept).
bool within_accel(const Eigen::Ref<const Eigen::VectorXd>& t, const Eigen::Ref<const Rows2>& v, double until,
                  double accel, double rounding);

}  // namespace nubot_control

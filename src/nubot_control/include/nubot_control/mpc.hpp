// Trajectory tracking by model predictive control with Laguerre-parameterised control increments: the compiled
// core of nubot_control.mpc (its module docstring states the model, the QP and the safety rules).
#pragma once

#include <Eigen/Dense>

#include <memory>
#include <optional>
#include <string>

namespace nubot_control {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The parameters as nubot_control.mpc.MpcParams checks them (SI units).
struct MpcParams {
  double dt;
  int horizon;
  int laguerre_terms;
  double laguerre_pole;
  double position_weight;
  double effort_weight;
  double max_speed;
  double max_accel;
  int polygon_sides;
  int constrained_steps;
  int solver_iterations;  // DAQP's iteration limit
};

// Discrete Laguerre functions: row i is L(i)^T, shape (steps, terms) (Wang 2009, ch. 3).
RowMatrix laguerre_basis(double pole, int terms, int steps);

// One QP with 2N variables per control cycle; the Hessian and constraint rows are built once, and so is the solver's
// workspace (on the first constrained QP). Movable, not copyable: the workspace is the tracker's own.
class LaguerreMpc {
 public:
  explicit LaguerreMpc(const MpcParams& params);
  ~LaguerreMpc();
  LaguerreMpc(LaguerreMpc&&) noexcept;
  LaguerreMpc& operator=(LaguerreMpc&&) noexcept;
  LaguerreMpc(const LaguerreMpc&) = delete;
  LaguerreMpc& operator=(const LaguerreMpc&) = delete;

  // The world-frame velocity for this cycle. ref_positions: (horizon + 1) x 2 at k .. k+horizon; ref_velocities:
  // horizon x 2 (checked, not needed by the prediction); the limits default to the parameters' and may only lower
  // them. Throws std::invalid_argument on non-finite input or limits out of range.
  Eigen::Vector2d command(const Eigen::Vector2d& position, const Eigen::Vector2d& previous,
                          const Eigen::Ref<const RowMatrix>& ref_positions,
                          const Eigen::Ref<const RowMatrix>& ref_velocities, std::optional<double> max_speed,
                          std::optional<double> max_accel);

  const MpcParams& params() const { return params_; }
  int fallbacks() const { return fallbacks_; }
  const std::string& last_status() const { return last_status_; }

  // The QP of the last call (its gradient and bounds; the Hessian and rows are constant).
  const RowMatrix& qp_hessian() const { return qp_hessian_; }
  const RowMatrix& qp_rows() const { return qp_rows_; }
  const Eigen::VectorXd& qp_gradient() const { return q_; }
  const Eigen::VectorXd& qp_lower() const { return lower_; }
  const Eigen::VectorXd& qp_upper() const { return upper_; }

 private:
  class QpSolver;  // DAQP's workspace for this tracker's QP (mpc.cpp)

  Eigen::Vector2d move(const Eigen::Vector2d& previous, const Eigen::VectorXd& eta) const;

  MpcParams params_;
  Eigen::RowVectorXd first_;    // L(0)^T
  Eigen::VectorXd carry_;       // dt * (1 .. H): how far u_{k-1} held carries the robot by step i
  RowMatrix gradient_t_;        // position_weight * phi, H x N
  RowMatrix hessian_inv_t_;     // (H^-1)^T, N x N
  RowMatrix normals_;           // the polygon's side normals (one per pair of opposite sides when M is even)
  double apothem_;
  bool two_sided_;
  Eigen::VectorXi per_step_;    // row r's side
  Eigen::VectorXd accel_upper_, accel_lower_;
  RowMatrix qp_hessian_, qp_rows_;
  Eigen::VectorXi qp_sense_;
  Eigen::VectorXd upper_, lower_, q_;
  std::unique_ptr<QpSolver> solver_;  // set up on the first constrained QP
  int fallbacks_ = 0;
  std::string last_status_ = "not run";
};

}  // namespace nubot_control

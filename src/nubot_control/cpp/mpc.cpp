// The Laguerre MPC's compiled core: see include/nubot_control/mpc.hpp and nubot_control/mpc.py.
#include "nubot_control/mpc.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include "nubot_control/format.hpp"

extern "C" {
#include <api.h>  // DAQP
#include <utils.h>
}

namespace nubot_control {
namespace {

constexpr double kUnbounded = 1e30;  // DAQP's infinity: a bound beyond it is no bound

std::string daqp_status(int flag) {
  switch (flag) {
    case 1:
    case 2:
      return "solved";  // optimal; optimal with soft constraints violated (none here)
    case -1:
      return "infeasible";
    case -2:
      return "cycling";
    case -3:
      return "unbounded";
    case -4:
      return "iteration limit";
    case -5:
      return "not convex";
    case -6:
      return "initial working set overdetermined";
    default:
      return "exit flag " + std::to_string(flag);
  }
}

// v shortened to length radius if it is longer.
Eigen::Vector2d clip_norm(const Eigen::Vector2d& v, double radius) {
  const double norm = std::hypot(v.x(), v.y());
  return norm <= radius ? v : Eigen::Vector2d(v * (radius / norm));
}

// The point nearest x in {|v| <= speed} and {|v - centre| <= step}; none if the discs do not meet.
std::optional<Eigen::Vector2d> project_two_discs(const Eigen::Vector2d& x, double speed, const Eigen::Vector2d& centre,
                                                 double step) {
  Eigen::Vector2d p = clip_norm(x, speed);
  if (std::hypot(p.x() - centre.x(), p.y() - centre.y()) <= step) return p;
  p = centre + clip_norm(x - centre, step);
  if (std::hypot(p.x(), p.y()) <= speed) return p;
  // Neither single projection lies in both discs: the answer is a point where the two circles cross.
  const double d = std::hypot(centre.x(), centre.y());
  if (d == 0.0 || d > speed + step || d < std::abs(speed - step)) return std::nullopt;
  const double along = (speed * speed - step * step + d * d) / (2.0 * d);
  const double across = std::sqrt(std::max(speed * speed - along * along, 0.0));
  const Eigen::Vector2d unit = centre / d;
  const Eigen::Vector2d normal(-unit.y(), unit.x());
  const Eigen::Vector2d a = along * unit + across * normal, b = along * unit - across * normal;
  return std::hypot(b.x() - x.x(), b.y() - x.y()) < std::hypot(a.x() - x.x(), a.y() - x.y()) ? b : a;
}

void require_finite(const Eigen::Ref<const RowMatrix>& value, const char* name) {
  if (!value.allFinite()) throw std::invalid_argument(std::string(name) + " must be finite");
}

double limit(std::optional<double> value, double most, const char* name) {
  const double chosen = value.value_or(most);
  if (!(std::isfinite(chosen) && 0.0 < chosen && chosen <= most)) {
    throw std::invalid_argument(std::string(name) + " must lie in (0, " + format_float(most) + "], got " +
                                (value ? format_float(*value) : "None"));
  }
  return chosen;
}

}  // namespace

// DAQP's workspace for the QPs of one tracker, whose Hessian H and rows A never change: H's Cholesky factor R, R^-1
// and the normalised M = A R^-1 are formed once, and each QP brings only its gradient f and bounds. Every answer is
// daqp_quadprog's to the last bit. That one-shot solve tests the unconstrained optimum with R itself, by triangular
// solves (it inverts R only when a constrained solve needs R^-1), and keeps that test's v = R^-T f and d = b - A x
// for the solve; DAQP's update of a workspace holding R^-1 would form them by products with R^-1, which round
// differently. So the workspace keeps R too and runs DAQP's own test on it; then it solves from an empty working
// set, as the one-shot solve does. A QP whose setup takes another way (R inverted at once or regularised, a zero
// row, bounds that meet or cross) is left to daqp_quadprog.
class LaguerreMpc::QpSolver {
 public:
  QpSolver(const DAQPProblem& qp, int iterations);
  ~QpSolver() { release(); }
  QpSolver(const QpSolver&) = delete;
  QpSolver& operator=(const QpSolver&) = delete;

  // DAQP's exit flag for qp (H and A those of the setup); x and the multipliers as daqp_quadprog gives them.
  int solve(const DAQPProblem& qp, double* x, double* lam);

 private:
  int solve_once(const DAQPProblem& qp, double* x, double* lam);
  void release();

  DAQPSettings settings_{};
  DAQPWorkspace work_{};
  DAQPProblem qp_{};            // the QP being solved (the workspace points to it)
  std::vector<c_float> factor_;  // R, packed by rows with the reciprocal diagonal (DAQP's layout)
  bool allocated_ = false;
  bool kept_ = false;            // the workspace holds the LDP of H and A; else daqp_quadprog solves each QP
};

LaguerreMpc::QpSolver::QpSolver(const DAQPProblem& qp, int iterations)
    : factor_(static_cast<std::size_t>(qp.n) * (qp.n + 1) / 2) {
  daqp_default_settings(&settings_);
  settings_.iter_limit = iterations;
  // First a QP whose unconstrained optimum (x = 0) is feasible: DAQP factors H and leaves R uninverted, as the
  // one-shot solve does up to its test; R is kept. Then the LDP: R^-1, M and its normalisation.
  std::vector<c_float> zeros(qp.n, 0.0), upper(qp.m, DAQP_INF), lower(qp.m, -DAQP_INF);
  DAQPProblem open = qp;
  open.f = zeros.data();
  open.bupper = upper.data();
  open.blower = lower.data();
  work_.settings = &settings_;
  if (setup_daqp_main(&open, &work_, nullptr, DAQP_UPDATE_unconstrained) < 0) {
    work_ = DAQPWorkspace{};  // DAQP freed what it had allocated
    return;
  }
  allocated_ = true;
  const bool deferred = (work_.state & DAQP_STATE_CHOLESKY_PENDING) && (work_.state & DAQP_STATE_UNCONSTRAINED) &&
                        work_.Rinv != nullptr;
  if (deferred) {
    std::copy(work_.Rinv, work_.Rinv + factor_.size(), factor_.begin());
    const int flag = daqp_update_ldp(DAQP_UPDATE_v | DAQP_UPDATE_d | DAQP_UPDATE_sense, &work_, &open);
    kept_ = flag >= 0 && !(work_.state & (DAQP_STATE_PENDING | DAQP_STATE_CHOLESKY_PENDING)) &&
            work_.Rinv != nullptr && work_.n_prox == 0 && work_.bnb == nullptr && work_.avi == nullptr &&
            work_.eq == nullptr && work_.hierarchy == nullptr && std::equal(work_.sense, work_.sense + qp.m, qp.sense);
  }
  work_.qp = nullptr;  // open goes now
  if (!kept_) release();
}

void LaguerreMpc::QpSolver::release() {
  if (!allocated_) return;
  work_.settings = nullptr;  // settings_ is not DAQP's to free
  free_daqp_workspace(&work_);
  free_daqp_ldp(&work_);
  work_ = DAQPWorkspace{};
  allocated_ = kept_ = false;
}

int LaguerreMpc::QpSolver::solve_once(const DAQPProblem& qp, double* x, double* lam) {
  DAQPProblem problem = qp;
  DAQPResult result{x, lam, 0.0, 0.0, 0, 0, 0, 0.0, 0.0};
  daqp_quadprog(&result, &problem, &settings_);
  return result.exitflag;
}

int LaguerreMpc::QpSolver::solve(const DAQPProblem& qp, double* x, double* lam) {
  if (!kept_) return solve_once(qp, x, lam);
  // The constraints' states as the one-shot solve starts them: none active; its bound check marks nothing here.
  qp_ = qp;
  work_.qp = &qp_;
  std::copy(qp.sense, qp.sense + qp.m, work_.sense);
  if (daqp_check_bounds(&work_, qp.bupper, qp.blower) != 0) return solve_once(qp, x, lam);
  reset_daqp_workspace(&work_);
  work_.state &= DAQP_STATE_RINV_NORMALIZED | DAQP_STATE_ILL_CONDITIONED;  // what an update of the LDP keeps
  // DAQP's test of the unconstrained optimum, on R: it forms v and d = b - A x (unscaled) and reports whether x is
  // feasible.
  c_float* const inverse = work_.Rinv;
  work_.Rinv = factor_.data();
  work_.state |= DAQP_STATE_CHOLESKY_PENDING;
  const int tested = daqp_check_unconstrained(&work_, DAQP_UPDATE_unconstrained | DAQP_UPDATE_v | DAQP_UPDATE_d);
  work_.Rinv = inverse;
  work_.state &= ~DAQP_STATE_CHOLESKY_PENDING;
  if (tested == 1) {  // infeasible: d scaled as M's rows, and the working set formed from the states (empty)
    for (int i = 0; i < work_.m; ++i) {
      work_.dupper[i] *= work_.scaling[i];
      work_.dlower[i] *= work_.scaling[i];
    }
    work_.reuse_ind = 0;
    const int flag = daqp_reactivate_constraints(&work_);
    if (flag < 0) return flag;
  } else if (tested != DAQP_UNCONSTRAINED_OPTIMAL) {
    return solve_once(qp, x, lam);  // not tested (not reached with the states above)
  }
  DAQPResult result{x, lam, 0.0, 0.0, 0, 0, 0, 0.0, 0.0};
  daqp_solve(&result, &work_);
  return result.exitflag;
}

RowMatrix laguerre_basis(double pole, int terms, int steps) {
  if (!(0.0 <= pole && pole < 1.0)) throw std::invalid_argument("pole must lie in [0, 1), got " + format_float(pole));
  if (terms < 1 || steps < 1) {
    throw std::invalid_argument("terms and steps must be >= 1, got " + std::to_string(terms) + " and " +
                                std::to_string(steps));
  }
  const double beta = 1.0 - pole * pole;
  RowMatrix a_l = RowMatrix::Zero(terms, terms);
  for (int r = 0; r < terms; ++r) {
    a_l(r, r) = pole;
    for (int c = 0; c < r; ++c) a_l(r, c) = beta * std::pow(-pole, r - c - 1);
  }
  RowMatrix basis(steps, terms);
  for (int c = 0; c < terms; ++c) basis(0, c) = std::sqrt(beta) * std::pow(-pole, c);
  for (int i = 1; i < steps; ++i) basis.row(i) = (a_l * basis.row(i - 1).transpose()).transpose();
  return basis;
}

LaguerreMpc::LaguerreMpc(const MpcParams& params) : params_(params) {
  const MpcParams& p = params_;
  if (!(p.dt > 0.0 && std::isfinite(p.dt))) throw std::invalid_argument("dt must be positive");
  if (p.laguerre_terms < 1 || p.laguerre_terms > p.horizon) {
    throw std::invalid_argument("laguerre_terms must lie in 1..horizon, got " + std::to_string(p.laguerre_terms));
  }
  if (p.polygon_sides < 3) throw std::invalid_argument("polygon_sides must be >= 3");
  if (p.constrained_steps < 1 || p.constrained_steps > p.horizon) {
    throw std::invalid_argument("constrained_steps must lie in 1..horizon");
  }
  if (p.solver_iterations < 1) throw std::invalid_argument("solver_iterations must be >= 1");
  const int h = p.horizon, n = p.laguerre_terms, nc = p.constrained_steps, m = p.polygon_sides;
  const RowMatrix basis = laguerre_basis(p.laguerre_pole, n, h);  // du_{k+i} = basis[i] @ eta_axis
  first_ = basis.row(0);
  RowMatrix cumulative(h, n);  // u_{k+i} - u_{k-1} = cumulative[i] @ eta_axis
  cumulative.row(0) = basis.row(0);
  for (int i = 1; i < h; ++i) cumulative.row(i) = cumulative.row(i - 1) + basis.row(i);
  // Per axis, e_{k+1..k+H} = free response + phi @ eta_axis with phi[i-1] = dt * sum_{j<i} cumulative[j].
  RowMatrix phi(h, n);
  phi.row(0) = cumulative.row(0);
  for (int i = 1; i < h; ++i) phi.row(i) = phi.row(i - 1) + cumulative.row(i);
  phi *= p.dt;
  carry_.resize(h);
  for (int i = 0; i < h; ++i) carry_(i) = p.dt * (i + 1);
  const RowMatrix hessian = p.position_weight * phi.transpose() * phi +
                            p.effort_weight * RowMatrix::Identity(n, n);  // the same for both axes
  gradient_t_ = p.position_weight * phi;
  hessian_inv_t_ = hessian.inverse().transpose();

  // The inscribed polygon, a vertex at angle 0; with M even opposite sides share a normal and make one two-sided row.
  two_sided_ = m % 2 == 0;
  const int count = two_sided_ ? m / 2 : m;
  normals_.resize(count, 2);
  for (int j = 0; j < count; ++j) {
    const double angle = (j + 0.5) * (2.0 * M_PI / m);
    normals_(j, 0) = std::cos(angle);
    normals_(j, 1) = std::sin(angle);
  }
  apothem_ = std::cos(M_PI / m);
  // Row (i, j): n_j . (vectors[i] @ eta_x, vectors[i] @ eta_y), for the constrained steps i; the speed sides first
  // (they move with u_{k-1}), then the acceleration sides.
  const int per_kind = nc * count;
  qp_rows_.resize(2 * per_kind, 2 * n);
  per_step_.resize(per_kind);
  for (int i = 0; i < nc; ++i) {
    for (int j = 0; j < count; ++j) {
      const int r = i * count + j;
      per_step_(r) = j;
      qp_rows_.block(r, 0, 1, n) = normals_(j, 0) * cumulative.row(i);
      qp_rows_.block(r, n, 1, n) = normals_(j, 1) * cumulative.row(i);
      qp_rows_.block(per_kind + r, 0, 1, n) = normals_(j, 0) * basis.row(i);
      qp_rows_.block(per_kind + r, n, 1, n) = normals_(j, 1) * basis.row(i);
    }
  }
  const double accel = p.max_accel * p.dt * apothem_;
  accel_upper_ = Eigen::VectorXd::Constant(per_kind, accel);
  accel_lower_ = two_sided_ ? Eigen::VectorXd(-accel_upper_) : Eigen::VectorXd::Constant(per_kind, -kUnbounded);
  qp_hessian_ = RowMatrix::Zero(2 * n, 2 * n);
  qp_hessian_.topLeftCorner(n, n) = hessian;
  qp_hessian_.bottomRightCorner(n, n) = hessian;
  qp_sense_ = Eigen::VectorXi::Zero(2 * per_kind);  // every row an inequality
  upper_ = Eigen::VectorXd::Constant(2 * per_kind, kUnbounded);
  lower_ = Eigen::VectorXd::Constant(2 * per_kind, -kUnbounded);
  q_ = Eigen::VectorXd::Zero(2 * n);
}

LaguerreMpc::~LaguerreMpc() = default;
LaguerreMpc::LaguerreMpc(LaguerreMpc&&) noexcept = default;
LaguerreMpc& LaguerreMpc::operator=(LaguerreMpc&&) noexcept = default;

Eigen::Vector2d LaguerreMpc::move(const Eigen::Vector2d& previous, const Eigen::VectorXd& eta) const {
  const int n = params_.laguerre_terms;
  return previous + Eigen::Vector2d(first_.dot(eta.head(n)), first_.dot(eta.tail(n)));
}

Eigen::Vector2d LaguerreMpc::command(const Eigen::Vector2d& position, const Eigen::Vector2d& previous,
                                     const Eigen::Ref<const RowMatrix>& ref_positions,
                                     const Eigen::Ref<const RowMatrix>& ref_velocities,
                                     std::optional<double> max_speed, std::optional<double> max_accel) {
  const MpcParams& p = params_;
  const int h = p.horizon, n = p.laguerre_terms;
  if (ref_positions.rows() != h + 1 || ref_positions.cols() != 2) {
    throw std::invalid_argument("ref_positions must have shape (" + std::to_string(h + 1) + ", 2)");
  }
  if (ref_velocities.rows() != h || ref_velocities.cols() != 2) {
    throw std::invalid_argument("ref_velocities must have shape (" + std::to_string(h) + ", 2)");
  }
  require_finite(position.transpose(), "position");
  require_finite(previous.transpose(), "previous");
  require_finite(ref_positions, "ref_positions");
  require_finite(ref_velocities, "ref_velocities");
  const double speed = limit(max_speed, p.max_speed, "max_speed");
  const double accel = limit(max_accel, p.max_accel, "max_accel");
  const double step = accel * p.dt;

  // Predicted errors e_{k+1..k+H} if u stayed u_{k-1} (eta = 0), H x 2; per axis (rows x, y) the QP gradient and
  // the unconstrained optimum.
  RowMatrix free = ref_positions.bottomRows(h);
  for (int i = 0; i < h; ++i) {
    free(i, 0) = position.x() + carry_(i) * previous.x() - free(i, 0);
    free(i, 1) = position.y() + carry_(i) * previous.y() - free(i, 1);
  }
  const RowMatrix gradient = free.transpose() * gradient_t_;  // 2 x N
  const RowMatrix optimum = gradient * hessian_inv_t_;        // -eta per axis
  q_ << gradient.row(0).transpose(), gradient.row(1).transpose();
  Eigen::VectorXd eta(2 * n);
  eta << -optimum.row(0).transpose(), -optimum.row(1).transpose();
  const Eigen::Vector2d unconstrained = previous - optimum * first_.transpose();

  // Speed: n_j . (u_{k-1} + du_k + ... + du_{k+i}) within the polygon of ``speed``; acceleration: n_j . du.
  const Eigen::VectorXd side_offset = normals_ * previous;
  const int per_kind = static_cast<int>(per_step_.size());
  for (int r = 0; r < per_kind; ++r) {
    const double offset = side_offset(per_step_(r));
    upper_(r) = speed * apothem_ - offset;
    if (two_sided_) lower_(r) = -speed * apothem_ - offset;
  }
  const double scale = accel / p.max_accel;
  upper_.tail(per_kind) = accel_upper_ * scale;
  lower_.tail(per_kind) = accel_lower_ * scale;
  const Eigen::VectorXd rows = qp_rows_ * eta;
  std::string status;
  std::optional<Eigen::Vector2d> chosen;
  if ((rows.array() <= upper_.array()).all() && (rows.array() >= lower_.array()).all()) {
    status = "unconstrained";
    chosen = project_two_discs(unconstrained, speed, previous, step);  // inside already, bar rounding
  } else {
    const int m = static_cast<int>(qp_rows_.rows());
    Eigen::VectorXd x(2 * n), lam(m);
    const DAQPProblem problem{2 * n, m, 0, qp_hessian_.data(), q_.data(), qp_rows_.data(), upper_.data(),
                              lower_.data(), qp_sense_.data(), nullptr, 0, 0};
    if (!solver_) solver_ = std::make_unique<QpSolver>(problem, p.solver_iterations);
    status = daqp_status(solver_->solve(problem, x.data(), lam.data()));
    if (status == "solved" && x.allFinite()) {
      chosen = project_two_discs(move(previous, x), speed, previous, step);
      if (!chosen) status = "limits unreachable in one step";
    }
  }
  if (chosen) {
    last_status_ = status;
    return *chosen;
  }
  // Fallback: head for the velocity within the limit nearest the unconstrained choice, by at most one step (keeping
  // within the limit too when one step can reach it).
  ++fallbacks_;
  last_status_ = "fallback: " + status;
  const Eigen::Vector2d target = clip_norm(unconstrained, speed);
  const std::optional<Eigen::Vector2d> within = project_two_discs(target, speed, previous, step);
  return within ? *within : Eigen::Vector2d(previous + clip_norm(target - previous, step));
}

}  // namespace nubot_control

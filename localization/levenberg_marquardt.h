#pragma once
// The one Levenberg–Marquardt loop of the localizers (Marquardt's diagonal scaling, Nielsen's damping update:
// H. B. Nielsen, "Damping parameter in Marquardt's method", IMM-REP-1999-05). The range cost (range_cost.h)
// and the joint wrapped-phase model (joint_model.h) differ only in their residuals and stopping tolerances.
// Header-only; no state; thread-safe.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace rfidray::loc {

// Stopping rules. Gradient: ‖Jᵀr‖∞ < gradient_abs + gradient_rel·f. After an accepted step: ‖step‖ <
// step_abs + step_rel·‖u‖, or a decrease ≤ gain_rel·f + 1e-30. After a rejected step: ‖step‖ < reject_abs +
// reject_rel·‖u‖. f = Σr².
struct LmTolerances {
  double gradient_abs = 1e-15, gradient_rel = 0.0;
  double step_abs = 1e-9, step_rel = 1e-9;
  double gain_rel = 1e-14;
  double reject_abs = 1e-12, reject_rel = 1e-12;
};

struct LmSolution {
  Eigen::VectorXd unknowns;
  double cost = 0.0;  // Σr² at `unknowns`
  int iterations = 0;
  bool converged = false;
};

// `evaluate(u, r, J)` fills the residuals r (and, when J is non-null, the Jacobian) at unknowns u.
template <typename Evaluate>
LmSolution levenberg_marquardt_core(Eigen::VectorXd u, Evaluate&& evaluate, int max_iterations,
                                    const LmTolerances& tol) {
  LmSolution out;
  Eigen::VectorXd r, r_new;
  Eigen::MatrixXd J, J_new;
  evaluate(u, r, &J);
  double f = r.squaredNorm();
  double mu = -1.0, nu = 2.0;
  for (int it = 0; it < max_iterations; ++it) {
    out.iterations = it + 1;
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    // Marquardt's scaling damps by μ·diag(A): μ is relative (dimensionless), so it starts at τ = 1e-3
    // (Nielsen's τ) — not τ·max diag(A), which belongs to the unscaled μ·I form and would start the
    // scaled form with steps 1e-3/max diag(A) too short.
    if (mu < 0.0) mu = 1e-3;
    if (g.lpNorm<Eigen::Infinity>() < tol.gradient_abs + tol.gradient_rel * f) {
      out.converged = true;
      break;
    }
    Eigen::MatrixXd Ad = A;
    Ad.diagonal() += mu * A.diagonal().cwiseMax(1e-12);
    const Eigen::VectorXd step = Ad.ldlt().solve(-g);
    if (!step.allFinite()) break;
    const Eigen::VectorXd u_new = u + step;
    // The trial point is evaluated with its Jacobian: most steps are accepted, and re-evaluating the accepted
    // point for J would compute every residual twice (the residuals are the cost: one sincos per read).
    evaluate(u_new, r_new, &J_new);
    const double f_new = r_new.squaredNorm();
    // Gain ratio of actual to predicted decrease (Nielsen 1999).
    const double predicted = step.dot(mu * A.diagonal().cwiseMax(1e-12).cwiseProduct(step) - g);
    const double rho = predicted > 0.0 ? (f - f_new) / predicted : -1.0;
    if (rho > 0.0) {
      u = u_new;
      const bool small = step.norm() < tol.step_abs + tol.step_rel * u.norm() ||
                         (f - f_new) <= tol.gain_rel * f + 1e-30;
      f = f_new;
      r.swap(r_new);
      J.swap(J_new);
      mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
      nu = 2.0;
      if (small) {
        out.converged = true;
        break;
      }
    } else {
      if (step.norm() < tol.reject_abs + tol.reject_rel * u.norm()) {
        out.converged = true;
        break;
      }
      mu *= nu;
      nu *= 2.0;
    }
  }
  out.unknowns = u;
  out.cost = f;
  return out;
}

}  // namespace rfidray::loc

// The correction of one pass of the reference integrator, solved in double (docs/design.md
// section 3.2): delta = r + hl S [f(X + delta) - f(X)], by Picard sweeps on the small correction,
// with the increment of f from euler_field.hpp (exact for a torque that does not depend on the
// state).
#pragma once

#include <eulervop/core/outcome.hpp>
#include <eulervop/reference/detail/picard_matrices.hpp>
#include <eulervop/reference/detail/picard_workspace.hpp>
#include <eulervop/reference/settings.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>

namespace eulervop::detail {

// The Jacobian at the nodes, where the sweeps linearize it: the torque's (a torque of the
// state), or the whole problem's (the coupled problem).
template <class P>
void linearize_torque(picard_workspace<P>& w) {
  constexpr std::size_t D = P::dimension;
  if constexpr (is_coupled_problem_v<P>) {
    std::array<double, D> x;
    for (std::size_t k = 0; k < w.n1; ++k) {
      for (std::size_t i = 0; i < D; ++i) x[i] = w.Xd[i][k];
      w.field.jacobian_double(w.time_d_of(k), x, w.torque_J[k]);
    }
  } else if constexpr (picard_workspace<P>::traits::depends_on_state) {
    for (std::size_t k = 0; k < w.n1; ++k)
      w.field.torque_jacobian(w.time_d_of(k), {w.Xd[0][k], w.Xd[1][k], w.Xd[2][k]}, w.torque_J[k]);
  }
}

// g = f(X + delta) - f(X) at the nodes: the exact quadratic increment of Euler's equations
// (plus the torque's linear part when it reads the state), or J(X) delta for the coupled problem.
template <class P>
void increments(picard_workspace<P>& w) {
  constexpr std::size_t D = P::dimension;
  if constexpr (is_coupled_problem_v<P>) {
    for (std::size_t k = 0; k < w.n1; ++k) {
      const auto& J = w.torque_J[k];
      for (std::size_t i = 0; i < D; ++i) {
        double sum = 0;
        for (std::size_t m = 0; m < D; ++m) sum += J[i][m] * w.delta[m][k];
        w.g[i][k] = sum;
      }
    }
  } else {
    for (std::size_t k = 0; k < w.n1; ++k) {
      const double d1 = w.delta[0][k], d2 = w.delta[1][k], d3 = w.delta[2][k];
      w.field.increment(w.Xd[0][k], w.Xd[1][k], w.Xd[2][k], d1, d2, d3, w.g[0][k], w.g[1][k], w.g[2][k]);
      if constexpr (picard_workspace<P>::traits::depends_on_state)
        for (int i = 0; i < 3; ++i)
          w.g[i][k] += w.torque_J[k][i][0] * d1 + w.torque_J[k][i][1] * d2 + w.torque_J[k][i][2] * d3;
    }
  }
}

// One sweep delta <- r + hl S g(delta), g = f(X + delta) - f(X). Returns the largest change;
// dmax is the largest entry of the new delta.
template <class P, class T = typename P::value_type>
double correction_sweep(const picard_matrices<T>& m, picard_workspace<P>& w, double hl_d, double& dmax) {
  increments(w);
  // The maxima in locals: through the reference, each would make a store and its reload on
  // the loop's critical path.
  double diff = 0, big = dmax;
  m.double_integral(w.g, w.delta_new);
  for (std::size_t i = 0; i < P::dimension; ++i) {
    w.delta_new[i][0] = 0;
    for (std::size_t j = 1; j < w.n1; ++j) {
      const double v = w.r[i][j] + hl_d * w.delta_new[i][j];
      diff = std::max(diff, std::abs(v - w.delta[i][j]));
      big = std::max(big, std::abs(v));
      w.delta_new[i][j] = v;
    }
  }
  dmax = big;
  std::swap(w.delta, w.delta_new);
  return diff;
}

// Sweeps from delta = r until the change is at double rounding, or stagnant near it; a growing
// change means the segment is too long.
template <class P, class T = typename P::value_type>
outcome solve_correction(const picard_matrices<T>& m, picard_workspace<P>& w, double hl_d, picard_stats& st) {
  constexpr std::size_t max_sweeps = 200;
  for (std::size_t i = 0; i < P::dimension; ++i) w.delta[i] = w.r[i];
  linearize_torque(w);
  double prev_diff = std::numeric_limits<double>::infinity();
  double first_diff = -1;
  for (std::size_t sweep = 0; sweep < max_sweeps; ++sweep) {
    ++st.double_sweeps;
    double dmax = 0;
    const double diff = correction_sweep(m, w, hl_d, dmax);
    if (!std::isfinite(diff)) return {outcome_kind::correction_diverged};
    if (first_diff < 0) first_diff = diff;
    if (diff <= 4e-16 * dmax) return {};
    if (sweep > 4 && diff >= 0.7 * prev_diff) {
      if (diff <= 1e-12 * dmax) return {};
      if (diff > first_diff) return {outcome_kind::correction_diverged};
    }
    prev_diff = diff;
  }
  return {.kind = outcome_kind::correction_stalled, .count = max_sweeps};
}

// Solves for the correction of the residual in r (largest entry r_max) and adds it to Yc.
template <class P, class T = typename P::value_type>
outcome correct(const picard_matrices<T>& m, picard_workspace<P>& w, double r_max, double hl_d, picard_stats& st) {
  if (!std::isfinite(r_max)) return {outcome_kind::residual_non_finite};
  if (const outcome o = solve_correction(m, w, hl_d, st); !o.ok()) return o;
  for (std::size_t i = 0; i < P::dimension; ++i)
    for (std::size_t j = 1; j < w.n1; ++j) w.add_double(w.Yc[i][j], w.delta[i][j]);
  return {};
}

}  // namespace eulervop::detail

// The correction of one pass of the reference integrator, solved in double (docs/design.md
// section 3.2): delta = r + hl S [f(X + delta) - f(X)], by Gauss-Seidel sweeps on the small
// correction, with the increment of f from euler_field.hpp (exact for a torque that does not
// depend on the state).
#pragma once

#include <eulervop/core/error_free.hpp>
#include <eulervop/core/outcome.hpp>
#include <eulervop/reference/detail/double4.hpp>
#include <eulervop/reference/detail/picard_matrices.hpp>
#include <eulervop/reference/detail/picard_workspace.hpp>
#include <eulervop/reference/settings.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <utility>

// x86-64 with GCC or Clang: the sweeps also compiled for AVX, chosen at run time.
#if defined(__x86_64__) && defined(__GNUC__)
#define EULERVOP_SWEEP_AVX 1
#else
#define EULERVOP_SWEEP_AVX 0
#endif

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

// g = f(X + delta) - f(X) at node k: the exact quadratic increment of Euler's equations (plus
// the torque's linear part when it reads the state), or J(X) delta for the coupled problem.
template <class P>
[[gnu::always_inline]] inline void increment_at(picard_workspace<P>& w, std::size_t k) {
  constexpr std::size_t D = P::dimension;
  if constexpr (is_coupled_problem_v<P>) {
    const auto& J = w.torque_J[k];
    for (std::size_t i = 0; i < D; ++i) {
      double sum = 0;
      for (std::size_t m = 0; m < D; ++m) sum += J[i][m] * w.delta[m][k];
      w.g[i][k] = sum;
    }
  } else {
    const double d1 = w.delta[0][k], d2 = w.delta[1][k], d3 = w.delta[2][k];
    w.field.increment(w.Xd[0][k], w.Xd[1][k], w.Xd[2][k], d1, d2, d3, w.g[0][k], w.g[1][k], w.g[2][k]);
    if constexpr (picard_workspace<P>::traits::depends_on_state)
      for (int i = 0; i < 3; ++i)
        w.g[i][k] += w.torque_J[k][i][0] * d1 + w.torque_J[k][i][1] * d2 + w.torque_J[k][i][2] * d3;
  }
}

// The same at every node.
template <class P>
void increments(picard_workspace<P>& w) {
  for (std::size_t k = 0; k < w.n1; ++k) increment_at(w, k);
}

// For Euler's equations (3 states): the step b at node k made implicit in the node's own term,
// s = (I - c J)^-1 b with c = hl S_kk and J the Jacobian of the quadratic part at X + delta
// there, taken as b + c J b + (c J)^2 b: c |J| is about |J| hl / N, so the series errs by
// (c |J|)^3 of b, and its terms, a_i (x_k b_j + x_j b_k), are the same operations whatever the
// labels of the axes (a relabelled body gives the same bits). A Newton step on that node's
// equation alone: it takes the sweeps from 24 to 17 per segment on the paper scene.
template <class P>
[[gnu::always_inline]] inline void implicit_node_step(const picard_workspace<P>& w, std::size_t k, double c,
                                                      std::array<double, 3>& b) {
  const std::array<double, 3> x = {w.Xd[0][k] + w.delta[0][k], w.Xd[1][k] + w.delta[1][k],
                                   w.Xd[2][k] + w.delta[2][k]};
  const std::array<double, 3> Jb = w.field.quadratic_jacobian_times(x, b);
  const std::array<double, 3> cJb = {c * Jb[0], c * Jb[1], c * Jb[2]};
  const std::array<double, 3> JJb = w.field.quadratic_jacobian_times(x, cJb);
  for (int i = 0; i < 3; ++i) b[i] += cJb[i] + c * JJb[i];
}

// sums[i] = sum_k row[k] g[i][k], i < D, for all components in one pass over the row (it is
// loaded once, not D times). Each sum in four partial sums, k = 0, 1, 2, 3 mod 4 (the lanes of
// one double4), added as (s0 + s1) + (s2 + s3): one running sum would bind the loop to the
// latency of its additions. Compiled for AVX (correction_sweep_avx), a double4 is one register
// and one operation; otherwise two SSE pairs, with the same roundings.
template <std::size_t D>
[[gnu::always_inline]] inline void row_times_increments(const double* row, const std::array<const double*, D>& g,
                                                        std::size_t n1, std::array<double, D>& sums) {
  std::array<double4, D> acc{};
  std::size_t k = 0;
  for (; k + 4 <= n1; k += 4) {
    double4 r, gk;
    std::memcpy(&r, row + k, sizeof r);
    for (std::size_t i = 0; i < D; ++i) {
      std::memcpy(&gk, g[i] + k, sizeof gk);
      acc[i] += r * gk;
    }
  }
  for (std::size_t i = 0; i < D; ++i) {
    double s0 = acc[i][0];
    for (std::size_t m = k; m < n1; ++m) s0 += row[m] * g[i][m];
    sums[i] = (s0 + acc[i][1]) + (acc[i][2] + acc[i][3]);
  }
}

// One Gauss-Seidel sweep of delta = r + hl S g(delta), g = f(X + delta) - f(X): node by node in
// time, each node's row of S applied to the newest g of every node (those before it already
// swept), its own term made implicit (implicit_node_step), then its g updated. The integral is
// mostly over the nodes before: this halves the sweeps of the plain Picard sweep (all nodes from
// the previous sweep). Returns the largest change; dmax is the largest entry of the new delta.
// g holds g(delta) on entry and on return.
template <class P, class T = typename P::value_type>
[[gnu::always_inline]] inline double correction_sweep_body(const picard_matrices<T>& m, picard_workspace<P>& w,
                                                           double hl_d, double& dmax) {
  constexpr std::size_t D = P::dimension;
  const std::size_t n1 = w.n1;
  double diff = 0, big = dmax;
  std::array<const double*, D> g;
  for (std::size_t i = 0; i < D; ++i) g[i] = w.g[i].data();
  for (std::size_t j = 1; j < n1; ++j) {
    const double* row = &m.S_d[j * n1];
    std::array<double, D> step;
    row_times_increments(row, g, n1, step);
    for (std::size_t i = 0; i < D; ++i) step[i] = w.r[i][j] + hl_d * step[i] - w.delta[i][j];
    if constexpr (!is_coupled_problem_v<P>) implicit_node_step(w, j, hl_d * row[j], step);
    for (std::size_t i = 0; i < D; ++i) {
      const double v = w.delta[i][j] + step[i];
      diff = std::max(diff, std::abs(step[i]));
      big = std::max(big, std::abs(v));
      w.delta[i][j] = v;
    }
    increment_at(w, j);
  }
  dmax = big;
  return diff;
}

// The sweep as compiled for the baseline x86-64 (SSE2), and for AVX where the processor has it
// (chosen at run time: sweeps_use_avx). The source and its operations are the same, and AVX
// enables no fused multiply-add, so both round alike: the same bits. With AVX the row products,
// the bulk of a sweep, take half the vector operations (the sweeps were 29% of a quad run on the
// paper scene).
template <class P, class T = typename P::value_type>
double correction_sweep(const picard_matrices<T>& m, picard_workspace<P>& w, double hl_d, double& dmax) {
  return correction_sweep_body(m, w, hl_d, dmax);
}
#if EULERVOP_SWEEP_AVX
template <class P, class T = typename P::value_type>
[[gnu::target("avx")]] double correction_sweep_avx(const picard_matrices<T>& m, picard_workspace<P>& w, double hl_d,
                                                   double& dmax) {
  return correction_sweep_body(m, w, hl_d, dmax);
}
inline bool sweeps_use_avx() {
  static const bool avx = __builtin_cpu_supports("avx");
  return avx;
}
#endif

// What may end the sweeps besides a change at the target: `measured`, nothing (the segment's last
// correction: its error stays in the values and adds up over the segments, and the floor of
// chebyshev_picard::wide_floor assumes what a measured stop leaves, about q times the target);
// `predicted`, also a change that the rate of the last two sweeps predicts to be within the
// target (a correction that a later residual measures and corrects).
enum class correction_stop { measured, predicted };

// Sweeps from delta = r until the change is at double rounding, or below `floor` (or, with
// correction_stop::predicted, the next one would be), or stagnant near either; a growing change
// means the segment is too long. `floor` is the absolute accuracy the pass needs: a correction is
// only as good as the residual it corrects (rounded in double after the first pass) and the run's
// tolerance, so sweeping a 1e-32 correction to 16 digits of its own buys nothing.
template <class P, class T = typename P::value_type>
outcome solve_correction(const picard_matrices<T>& m, picard_workspace<P>& w, double hl_d, double floor,
                         correction_stop stop, picard_stats& st) {
  constexpr std::size_t max_sweeps = 200;
  for (std::size_t i = 0; i < P::dimension; ++i) w.delta[i] = w.r[i];
  linearize_torque(w);
  increments(w);
  double prev_diff = std::numeric_limits<double>::infinity();
  double first_diff = -1;
  for (std::size_t sweep = 0; sweep < max_sweeps; ++sweep) {
    ++st.double_sweeps;
    double dmax = 0;
#if EULERVOP_SWEEP_AVX
    const double diff = sweeps_use_avx() ? correction_sweep_avx(m, w, hl_d, dmax) : correction_sweep(m, w, hl_d, dmax);
#else
    const double diff = correction_sweep(m, w, hl_d, dmax);
#endif
    if (!std::isfinite(diff)) return {outcome_kind::correction_diverged};
    if (first_diff < 0) first_diff = diff;
    const double target = std::max(4e-16 * dmax, floor);
    if (diff <= target) return {};
    // Contracting by q = diff / prev_diff per sweep, the next sweeps would change delta by about
    // q diff / (1 - q) in all, under 2 q diff for q < 1/2: when that is within the target, the
    // sweep that would only confirm it is skipped (one of the 7 to 10 a correction takes).
    if (stop == correction_stop::predicted && sweep > 0 && diff < 0.25 * prev_diff &&
        2 * diff * (diff / prev_diff) <= target)
      return {};
    if (sweep > 4 && diff >= 0.7 * prev_diff) {
      if (diff <= std::max(1e-12 * dmax, floor)) return {};
      if (diff > first_diff) return {outcome_kind::correction_diverged};
    }
    prev_diff = diff;
  }
  return {.kind = outcome_kind::correction_stalled, .count = max_sweeps};
}

// Yc += delta, rows 1..N.
template <class P>
void add_correction(picard_workspace<P>& w) {
  for (std::size_t i = 0; i < P::dimension; ++i)
    for (std::size_t j = 1; j < w.n1; ++j) w.add_double(w.Yc[i][j], w.delta[i][j]);
}

// Ydd += delta, the iterate in double-double (picard_workspace.hpp), rows 1..N.
template <class P>
void add_correction_double_double(picard_workspace<P>& w) {
  for (std::size_t i = 0; i < P::dimension; ++i)
    for (std::size_t j = 1; j < w.n1; ++j) {
      const double_double s = two_sum(w.Ydd_hi[i][j], w.delta[i][j]);
      const double_double y = quick_two_sum(s.hi, s.lo + w.Ydd_lo[i][j]);
      w.Ydd_hi[i][j] = y.hi;
      w.Ydd_lo[i][j] = y.lo;
    }
}

// Solves for the correction of the residual in r (largest entry r_max) to the absolute accuracy
// `floor` (or double's) and adds it to Yc.
template <class P, class T = typename P::value_type>
outcome correct(const picard_matrices<T>& m, picard_workspace<P>& w, double r_max, double hl_d, double floor,
                correction_stop stop, picard_stats& st) {
  if (!std::isfinite(r_max)) return {outcome_kind::residual_non_finite};
  if (const outcome o = solve_correction(m, w, hl_d, floor, stop, st); !o.ok()) return o;
  add_correction(w);
  return {};
}

}  // namespace eulervop::detail

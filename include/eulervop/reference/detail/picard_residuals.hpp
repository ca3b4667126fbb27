// The residuals of the Picard map on one segment, r = hl S f(X) - Yc at the nodes, in the
// precisions the reference integrator climbs through (docs/design.md section 3.2): double from
// the warm start, then double-double, then T, which decides convergence; for MPFR also the
// residual updated after a correction in double-double, without a new residual in T.
// Each returns max |r| and leaves r in the workspace.
#pragma once

#include <eulervop/core/error_free.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/detail/picard_matrices.hpp>
#include <eulervop/reference/detail/picard_workspace.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <type_traits>

namespace eulervop::detail {

// X = x0 + (c0 + Yc) at node j, in node_x and in double in Xd.
template <class P, class T = typename P::value_type>
void node_state(picard_workspace<P>& w, const std::array<T, P::dimension>& x0, const std::array<T, P::dimension>& c0,
                std::size_t j) {
  for (std::size_t i = 0; i < P::dimension; ++i) {
    w.node_x[i] = x0[i] + (c0[i] + w.Yc[i][j]);
    w.Xd[i][j] = static_cast<double>(w.node_x[i]);
  }
}

// X and F = f(t, X) at the nodes, X also in double (Xd) and, for MPFR, its remainder (Xl).
// Returns the state scale max |X|.
template <class P, class T = typename P::value_type>
double evaluate_nodes(picard_workspace<P>& w, const std::array<T, P::dimension>& x0,
                      const std::array<T, P::dimension>& c0) {
  double scale = 0;
  for (std::size_t j = 0; j < w.n1; ++j) {
    node_state(w, x0, c0, j);
    for (std::size_t i = 0; i < P::dimension; ++i) {
      scale = std::max(scale, std::abs(w.Xd[i][j]));
      if constexpr (std::is_same_v<T, mpfr_real>) {  // only MPFR's residual updates read it
        w.acc = w.node_x[i];
        w.acc -= w.Xd[i][j];
        w.Xl[i][j] = static_cast<double>(w.acc);
      }
    }
    w.field.rhs_at_node(j, w.time_of(j), w.node_x, w.node_f);
    for (std::size_t i = 0; i < P::dimension; ++i) w.F[i][j] = w.node_f[i];
  }
  return scale;
}

// The Picard map Yn = hl S F in T, and r = Yn - Yc. For wide T the product S F is exact integer
// arithmetic rounded once (fixed_point_matrix), several times faster than the same sums in T and
// no less accurate. `first`: with S_fx_first where there is one (MPFR), accurate to about 2^-180
// of the state instead of the run's bits, for a residual that only starts a correction.
template <class P, class T = typename P::value_type>
double wide_residual(picard_matrices<T>& m, picard_workspace<P>& w, const T& hl, bool first = false) {
  double r_max = 0;
  for (std::size_t i = 0; i < P::dimension; ++i) {
    w.Yn[i][0] = 0;
    if constexpr (!std::is_same_v<T, double>) {
      (first && m.has_first_residual_matrix() ? m.S_fx_first : m.S_fx).multiply(w.F[i].data(), w.Yn[i].data(), 1);
      for (std::size_t j = 1; j < w.n1; ++j) w.Yn[i][j] *= hl;
    } else {
      for (std::size_t j = 1; j < w.n1; ++j) {
        const T* row = &m.basis.integral[j * w.n1];
        w.acc = 0;
        for (std::size_t k = 0; k < w.n1; ++k) w.acc += row[k] * w.F[i][k];
        w.acc *= hl;
        w.Yn[i][j] = w.acc;
      }
    }
    for (std::size_t j = 1; j < w.n1; ++j) {
      w.r[i][j] = difference_to_double(w.Yn[i][j], w.Yc[i][j], w.acc);
      r_max = std::max(r_max, std::abs(w.r[i][j]));
    }
    w.r[i][0] = 0;
  }
  return r_max;
}

// The residual from the warm start, all in double: it is far above double rounding, so
// computing it in T would buy nothing (for T = double the first wide residual is this pass).
template <class P, class T = typename P::value_type>
double double_residual(const picard_matrices<T>& m, picard_workspace<P>& w, const std::array<T, P::dimension>& x0,
                       const std::array<T, P::dimension>& c0, double hl_d) {
  constexpr std::size_t D = P::dimension;
  std::array<double, D> x0d, dx;
  for (std::size_t i = 0; i < D; ++i) x0d[i] = static_cast<double>(x0[i]) + static_cast<double>(c0[i]);
  for (std::size_t j = 0; j < w.n1; ++j) {
    std::array<double, D> x;
    for (std::size_t i = 0; i < D; ++i) x[i] = w.Xd[i][j] = x0d[i] + w.warm[i][j];
    w.field.rhs_double(w.time_d_of(j), x, dx);
    for (std::size_t i = 0; i < D; ++i) w.g[i][j] = dx[i];
  }
  double r_max = 0;
  m.double_integral(w.g, w.r);
  for (std::size_t i = 0; i < D; ++i) {
    w.r[i][0] = 0;
    for (std::size_t j = 1; j < w.n1; ++j) {
      w.r[i][j] = hl_d * w.r[i][j] - w.warm[i][j];
      r_max = std::max(r_max, std::abs(w.r[i][j]));
    }
  }
  return r_max;
}

// r = Y_hi + Y_lo - Yc in T (after S was applied to one component in double-double), for rows
// 1..N of component i.
template <class P>
double difference_to_iterate(picard_workspace<P>& w, std::size_t i) {
  using T = typename P::value_type;
  double r_max = 0;
  w.r[i][0] = 0;
  for (std::size_t j = 1; j < w.n1; ++j) {
    w.acc = T(w.Y_hi[j]);
    w.acc -= w.Yc[i][j];
    w.acc += T(w.Y_lo[j]);
    w.r[i][j] = static_cast<double>(w.acc);
    r_max = std::max(r_max, std::abs(w.r[i][j]));
  }
  return r_max;
}

// The second residual, for wide T: in double-double (~1e-32 relative), enough to drive the
// correction that follows to that level, at a fraction of a residual in T. The next residual, in
// T, decides convergence.
template <class P, class T = typename P::value_type>
double double_double_residual(picard_matrices<T>& m, picard_workspace<P>& w, const std::array<T, P::dimension>& x0,
                              const std::array<T, P::dimension>& c0, const T& hl) {
  for (std::size_t j = 0; j < w.n1; ++j) {
    node_state(w, x0, c0, j);
    w.field.rhs_at_node(j, w.time_of(j), w.node_x, w.node_f);
    for (std::size_t i = 0; i < P::dimension; ++i) w.F[i][j] = w.node_f[i] * hl;  // scaled by hl here, once
  }
  double r_max = 0;
  for (std::size_t i = 0; i < P::dimension; ++i) {
    for (std::size_t j = 0; j < w.n1; ++j) {
      w.F_hi[j] = static_cast<double>(w.F[i][j]);
      w.F_lo[j] = static_cast<double>(T(w.F[i][j] - T(w.F_hi[j])));
    }
    m.S_dd.multiply(w.F_hi.data(), w.F_lo.data(), w.Y_hi.data(), w.Y_lo.data(), 1);
    r_max = std::max(r_max, difference_to_iterate(w, i));
  }
  return r_max;
}

// The second residual where the field has a double-double right-hand side (a torque that does
// not read the state): the same, from the iterate in double-double (Ydd) and x0 + c0 split once
// as x0dd, with no operation in T. Leaves X in double in Xd, where the correction linearizes f.
template <class P, class T = typename P::value_type>
double double_double_residual(picard_matrices<T>& m, picard_workspace<P>& w,
                              const std::array<double_double, P::dimension>& x0dd, const double_double& hl) {
  constexpr std::size_t D = P::dimension;
  std::array<double_double, D> x, f;
  for (std::size_t j = 0; j < w.n1; ++j) {
    for (std::size_t i = 0; i < D; ++i) {
      x[i] = add(x0dd[i], double_double{w.Ydd_hi[i][j], w.Ydd_lo[i][j]});
      w.Xd[i][j] = x[i].hi;
    }
    w.field.scaled_rhs(j, x, hl, f);
    for (std::size_t i = 0; i < D; ++i) {
      w.Fdd_hi[i][j] = f[i].hi;
      w.Fdd_lo[i][j] = f[i].lo;
    }
  }
  double r_max = 0;
  for (std::size_t i = 0; i < D; ++i) {
    m.S_dd.multiply(w.Fdd_hi[i].data(), w.Fdd_lo[i].data(), w.Y_hi.data(), w.Y_lo.data(), 1);
    w.r[i][0] = 0;
    for (std::size_t j = 1; j < w.n1; ++j) {
      const double_double d =
          add(double_double{w.Y_hi[j], w.Y_lo[j]}, double_double{-w.Ydd_hi[i][j], -w.Ydd_lo[i][j]});
      w.r[i][j] = d.hi + d.lo;
      r_max = std::max(r_max, std::abs(w.r[i][j]));
    }
  }
  return r_max;
}

// Yn += Y_hi + Y_lo and r = Yn - Yc, rows 1..N of component i.
template <class P>
double updated_difference(picard_workspace<P>& w, int i) {
  double r_max = 0;
  w.r[i][0] = 0;
  for (std::size_t j = 1; j < w.n1; ++j) {
    w.add_double(w.Yn[i][j], w.Y_hi[j]);
    w.add_double(w.Yn[i][j], w.Y_lo[j]);
    w.r[i][j] = difference_to_double(w.Yn[i][j], w.Yc[i][j], w.acc);
    r_max = std::max(r_max, std::abs(w.r[i][j]));
  }
  return r_max;
}

// For MPFR, the residual after the correction delta (already added to Yc) without a new residual
// in T. With X the nodes' state before the correction, f(t, X + delta) - f(t, X) = g is the exact
// quadratic increment (euler_field.hpp), and the Picard map moves by hl S g: Yn += hl S g,
// F += g, r = Yn - Yc. g and hl S g are formed in double-double from X in double-double (Xd + Xl,
// moved by delta here), so the update errs by about 2^-100 |delta|: a residual at the level of
// the last full one times 2^-100 is resolved, at a fraction of the cost of a full residual.
template <class P, class T = typename P::value_type>
double update_residual(picard_matrices<T>& m, picard_workspace<P>& w, const T& hl) {
  static_assert(!picard_workspace<P>::traits::depends_on_state,
                "the increment of a torque of the state is not exact: no residual updates");
  const double hl_hi = static_cast<double>(hl);
  w.acc = hl;
  w.acc -= hl_hi;
  const double_double hl_dd{hl_hi, static_cast<double>(w.acc)};
  for (std::size_t j = 0; j < w.n1; ++j) {
    const std::array<double_double, 3> x = {double_double{w.Xd[0][j], w.Xl[0][j]},
                                            double_double{w.Xd[1][j], w.Xl[1][j]},
                                            double_double{w.Xd[2][j], w.Xl[2][j]}};
    const std::array<double_double, 3> g = w.field.increment(x, w.delta[0][j], w.delta[1][j], w.delta[2][j]);
    for (int i = 0; i < 3; ++i) {
      w.df_hi[i][j] = g[i].hi;
      w.df_lo[i][j] = g[i].lo;
      const double_double moved = add(x[i], double_double{w.delta[i][j], 0});
      w.Xd[i][j] = moved.hi;
      w.Xl[i][j] = moved.lo;
    }
  }
  double r_max = 0;
  for (int i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < w.n1; ++j) {
      const double_double hg = mul(double_double{w.df_hi[i][j], w.df_lo[i][j]}, hl_dd);
      w.F_hi[j] = hg.hi;
      w.F_lo[j] = hg.lo;
      w.add_double(w.F[i][j], w.df_hi[i][j]);
      w.add_double(w.F[i][j], w.df_lo[i][j]);
    }
    m.S_dd.multiply(w.F_hi.data(), w.F_lo.data(), w.Y_hi.data(), w.Y_lo.data(), 1);
    r_max = std::max(r_max, updated_difference(w, i));
  }
  return r_max;
}

}  // namespace eulervop::detail

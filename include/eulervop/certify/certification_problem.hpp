// A problem as the general path of --certify sees it (docs/certified.md, "The general path"):
// every number exact (a ball that holds it), and the field
//   y_i' = a_i y_j y_k + g_i(t, y[, q]),   (i, j, k) cyclic        (Eq. 5, or Eq. 1: euler_problem.hpp)
//   q'   = 1/2 q (x) (0, W(y))                                       (dimension 7: coupled_problem.hpp)
// written once over an algebra (detail/field_algebra.hpp), so that the same statement gives the
// field along a segment's polynomial with its Jacobian, and the field over a box with its Hessian.
// The torque g is the scene's formulas (model/torque_law.hpp) in the scene's variables, mapped to
// the integrator's as expression_torque.hpp maps them, with the map's numbers exact.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/field_algebra.hpp>
#include <eulervop/model/principal_axes.hpp>
#include <eulervop/model/torque_law.hpp>

#include <arb.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace eulervop {

// The scene's variables from the integrator's (expression_torque.hpp, torque_variables), exact:
// time = t / rate, state = P^T (state_scale y), g = (P torque) / divisor.
struct exact_variables {
  bool identity = true;
  axis_permutation axes;
  std::array<ball, 3> state_scale{ball(1), ball(1), ball(1)};
  std::array<ball, 3> divisor_inverse{ball(1), ball(1), ball(1)};
  ball rate_inverse{1};
};

// The body rates that turn q (body_rates.hpp), exact: W = P^T (scale y), or y itself.
struct exact_rates {
  bool identity = true;
  axis_permutation axes;
  std::array<ball, 3> scale{ball(1), ball(1), ball(1)};
};

// A breakpoint of the torque: where the reference ends its segments (`reference`, a number of its
// type, exactly) and a ball that holds both it and every exact breakpoint it stands for (the
// pieces' bounds, in the integrator's time). Between the two the exact solution and the reference
// may follow different formulas (docs/certified.md, "Breakpoints").
struct breakpoint_window {
  ball reference;
  ball hull;
  ball exact;             // the exact breakpoint, when it is one (exact_count == 1)
  std::size_t exact_count = 0;
};

struct certification_problem {
  std::size_t dimension = 3;  // 3, or 7 with q
  slong prec = 0;             // the working precision of every ball
  std::array<ball, 3> a;      // y_i' = a_i y_j y_k + g_i
  std::array<int, 3> unit_a{2, 2, 2};  // a_i when it is exactly -1, 0 or 1 (no product then), else 2
  // The torque's formula sets in the scene's variables: 0 outside every piece, p + 1 in piece p.
  // None for a torque-free problem.
  std::shared_ptr<const torque_law> law;
  std::vector<std::array<detail::ball_formula, 3>> sets;
  std::vector<std::array<ball, 2>> windows;  // piece p applies on [from, to), in the integrator's time
  exact_variables variables;
  exact_rates rates;  // dimension 7
  std::vector<breakpoint_window> breakpoints;
  std::vector<ball> initial;  // y(tau0) (and q(tau0), normalized exactly)
  ball tau0;
};

// The formula set that applies at the time `at` (a ball): the one whose window holds it certainly.
// std::domain_error when it lies within a breakpoint's enclosure.
inline std::size_t formula_set_at(const certification_problem& p, const ball& mid) {
  if (p.sets.size() <= 1) return 0;
  for (std::size_t w = 0; w < p.windows.size(); ++w) {
    const bool after_from = arb_ge(mid.get(), p.windows[w][0].get()) != 0;
    const bool before_to = arb_lt(mid.get(), p.windows[w][1].get()) != 0;
    if (after_from && before_to) return w + 1;
    const bool outside = arb_lt(mid.get(), p.windows[w][0].get()) || arb_ge(mid.get(), p.windows[w][1].get());
    if (!outside) throw std::domain_error("a time lies within a breakpoint's enclosure");
  }
  return 0;
}

// The formula set that applies on the segment [a, b]: the one at its midpoint (a segment never
// straddles a breakpoint of the reference).
inline std::size_t formula_set(const certification_problem& p, const ball& a, const ball& b) {
  ball mid;
  arb_add(mid.get(), a.get(), b.get(), p.prec);
  arb_mul_2exp_si(mid.get(), mid.get(), -1);
  return formula_set_at(p, mid);
}

namespace detail {

// dest = source (the algebra's values are copied, not aliased).
template <class Algebra>
typename Algebra::value product(const Algebra& alg, const typename Algebra::value& x, const typename Algebra::value& y) {
  typename Algebra::value out = x;
  alg.mul(out, y);
  return out;
}

// g(t, y, q) of formula set `set`, in the integrator's variables, added to F[0..2].
template <class Algebra>
void add_torque(const certification_problem& p, std::size_t set, const Algebra& alg, const typename Algebra::value& t,
                const std::vector<typename Algebra::value>& x, std::vector<typename Algebra::value>& F) {
  using value = typename Algebra::value;
  const exact_variables& v = p.variables;
  value ts = t;
  std::array<value, 3> ys;
  if (v.identity) {
    for (int i = 0; i < 3; ++i) ys[i] = x[i];
  } else {
    alg.scale(ts, v.rate_inverse);
    for (int i = 0; i < 3; ++i) {
      value s = x[i];
      alg.scale(s, v.state_scale[i]);
      if (v.axes.sign(i) < 0) alg.neg(s);
      ys[v.axes.axis(i)] = std::move(s);
    }
  }
  formula_variables<Algebra> vars;
  vars.time = &ts;
  for (int i = 0; i < 3; ++i) vars.state[i] = &ys[i];
  if (p.dimension == 7)
    for (int r = 0; r < 4; ++r) vars.attitude[r] = &x[3 + r];
  std::array<value, 3> m;
  for (int u = 0; u < 3; ++u) m[u] = p.sets[set][u](alg, vars);
  for (int i = 0; i < 3; ++i) {
    value g = std::move(m[v.identity ? i : v.axes.axis(i)]);
    if (!v.identity) {
      if (v.axes.sign(i) < 0) alg.neg(g);
      alg.scale(g, v.divisor_inverse[i]);
    }
    alg.add(F[i], g);
  }
}

// q' = 1/2 q (x) (0, W), W the body rates of y in the listed axes (coupled_problem.hpp).
template <class Algebra>
void add_attitude(const certification_problem& p, const Algebra& alg, const std::vector<typename Algebra::value>& x,
                  std::vector<typename Algebra::value>& F) {
  using value = typename Algebra::value;
  const ball half = [] {
    ball h(1);
    arb_mul_2exp_si(h.get(), h.get(), -1);
    return h;
  }();
  std::array<value, 3> W;  // halved
  for (int i = 0; i < 3; ++i) {
    value w = x[i];
    if (!p.rates.identity) {
      alg.scale(w, p.rates.scale[i]);
      if (p.rates.axes.sign(i) < 0) alg.neg(w);
    }
    alg.scale(w, half);
    W[p.rates.identity ? i : p.rates.axes.axis(i)] = std::move(w);
  }
  const auto q = [&](int r) -> const value& { return x[3 + r]; };
  // (q0, q1, q2, q3) (x) (0, W1, W2, W3), term by term.
  const int terms[4][3][3] = {
      {{-1, 1, 0}, {-1, 2, 1}, {-1, 3, 2}},  // q0' = -q1 W1 - q2 W2 - q3 W3
      {{1, 0, 0}, {1, 2, 2}, {-1, 3, 1}},    // q1' = q0 W1 + q2 W3 - q3 W2
      {{1, 0, 1}, {-1, 1, 2}, {1, 3, 0}},    // q2' = q0 W2 - q1 W3 + q3 W1
      {{1, 0, 2}, {1, 1, 1}, {-1, 2, 0}},    // q3' = q0 W3 + q1 W2 - q2 W1
  };
  for (int r = 0; r < 4; ++r) {
    value sum = product(alg, q(terms[r][0][1]), W[terms[r][0][2]]);
    if (terms[r][0][0] < 0) alg.neg(sum);
    for (int t = 1; t < 3; ++t) {
      const value term = product(alg, q(terms[r][t][1]), W[terms[r][t][2]]);
      if (terms[r][t][0] < 0)
        alg.sub(sum, term);
      else
        alg.add(sum, term);
    }
    F[3 + r] = std::move(sum);
  }
}

}  // namespace detail

// F(t, x) of formula set `set` in the algebra (x: the state, dimension p.dimension). Throws
// not_polynomial or undefined_formula from a formula.
template <class Algebra>
void field(const certification_problem& p, std::size_t set, const Algebra& alg, const typename Algebra::value& t,
           const std::vector<typename Algebra::value>& x, std::vector<typename Algebra::value>& F) {
  static constexpr int pair[3][2] = {{1, 2}, {2, 0}, {0, 1}};
  F.resize(p.dimension);
  for (int i = 0; i < 3; ++i) {
    F[i] = detail::product(alg, x[pair[i][0]], x[pair[i][1]]);
    if (p.unit_a[i] == -1)
      alg.neg(F[i]);
    else if (p.unit_a[i] != 1)
      alg.scale(F[i], p.a[i]);
  }
  if (!p.sets.empty()) detail::add_torque(p, set, alg, t, x, F);
  if (p.dimension == 7) detail::add_attitude(p, alg, x, F);
}

// Over a box: with t in `t` and the state in the balls `x`, |F_i(t, x)| <= fabs[i] and, for every e
// with x + e in the box, |W (F(t, x + e) - F(t, x) - DF e)|_2 <= c |W e|_2^2 for the weights W =
// diag(w): the remainder of Taylor's theorem, component i bounded by 1/2 w_i sup ||W^-1 H_i W^-1||
// (the 2-norm bounded by its largest absolute row sum). In 64-bit balls: the box is at least the
// tube wide (2^-20 of the state), and these are bounds.
inline void box_bounds(const certification_problem& p, std::size_t set, const ball& t, const std::vector<ball>& x,
                       const std::vector<double>& w, mag_t c, std::vector<mag_value>& fabs) {
  const std::size_t D = p.dimension;
  const detail::box_algebra alg(64, D);
  std::vector<detail::box_jet> xs;
  xs.reserve(D);
  for (std::size_t k = 0; k < D; ++k) xs.push_back(alg.variable(x[k], k));
  std::vector<detail::box_jet> F;
  field(p, set, alg, alg.independent(t), xs, F);
  mag_t m, row, sum2;
  mag_init(m);
  mag_init(row);
  mag_init(sum2);
  fabs.resize(D);
  for (std::size_t i = 0; i < D; ++i) {
    arb_get_mag(fabs[i].m, F[i].f.get());
    mag_t norm;
    mag_init(norm);
    for (std::size_t r = 0; r < D; ++r) {
      mag_zero(row);
      for (std::size_t k = 0; k < D; ++k) {
        arb_get_mag(m, F[i].H[r * D + k].get());
        mag_mul_2exp_si(m, m, -std::ilogb(w[r]) - std::ilogb(w[k]));
        mag_add(row, row, m);
      }
      mag_max(norm, norm, row);
    }
    mag_mul_2exp_si(norm, norm, std::ilogb(w[i]));
    mag_addmul(sum2, norm, norm);
    mag_clear(norm);
  }
  mag_sqrt(c, sum2);
  mag_mul_2exp_si(c, c, -1);
  mag_clear(m);
  mag_clear(row);
  mag_clear(sum2);
}

}  // namespace eulervop

// A problem as the general path of --certify sees it (docs/certified.md, "The general path"):
// every number exact (a ball that holds it), and the field
//   y_i' = a_i y_j y_k + g_i(t, y[, q]),   (i, j, k) cyclic        (Eq. 5, or Eq. 1: euler_problem.hpp)
//   q'   = 1/2 q (x) (0, W(y))                                       (dimension 7: coupled_problem.hpp)
// g: the scene's formulas of the time, the rates and q (any formula of the grammar), plus the
// gravity gradient 3 n^2 r_b x (I r_b) (model/gravity_gradient.hpp), both in the scene's variables
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
#include <optional>
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

// The gravity gradient (model/gravity_gradient.hpp), its numbers exact.
struct gravity_term {
  ball mean_motion;             // n, per unit of the scene's time
  std::array<ball, 3> moments;  // I in the listed axes
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
  std::optional<gravity_term> gravity;  // dimension 7
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
  typename Algebra::value out;
  alg.product(out, x, y);
  return out;
}

// The gravity gradient at the scene's time ts and attitude q, added to m (the scene's torque):
// b = R(q)^T (cos n ts, sin n ts, 0), m_i += 3 n^2 (I_l - I_j) b_j b_l, (i, j, l) cyclic.
template <class Algebra>
void add_gravity(const gravity_term& g, const Algebra& alg, const typename Algebra::value& ts,
                 const std::vector<typename Algebra::value>& x, std::array<typename Algebra::value, 3>& m) {
  using value = typename Algebra::value;
  value c = ts;
  alg.scale(c, g.mean_motion);
  value sn = c;
  alg.function(elementary::cos, c);
  alg.function(elementary::sin, sn);
  const auto q = [&](int r) -> const value& { return x[static_cast<std::size_t>(3 + r)]; };
  const auto qq = [&](int r, int k) { return product(alg, q(r), q(k)); };
  const ball two(2);
  // 1 - 2 (q_a^2 + q_b^2), and 2 (q_a q_b +- q_c q_d).
  const auto diagonal = [&](int a, int b) {
    value v = qq(a, a);
    alg.add(v, qq(b, b));
    alg.scale(v, two);
    alg.neg(v);
    alg.add(v, alg.constant(ball(1)));
    return v;
  };
  const auto off = [&](int a, int b, int c2, int d, bool plus) {
    value v = qq(a, b);
    if (plus)
      alg.add(v, qq(c2, d));
    else
      alg.sub(v, qq(c2, d));
    alg.scale(v, two);
    return v;
  };
  const auto combine = [&](value along_c, value along_s) {
    alg.mul(along_c, c);
    alg.mul(along_s, sn);
    alg.add(along_c, along_s);
    return along_c;
  };
  std::array<value, 3> b;
  b[0] = combine(diagonal(2, 3), off(1, 2, 0, 3, true));
  b[1] = combine(off(1, 2, 0, 3, false), diagonal(1, 3));
  b[2] = combine(off(1, 3, 0, 2, true), off(2, 3, 0, 1, false));
  ball k;
  arb_mul(k.get(), g.mean_motion.get(), g.mean_motion.get(), alg.prec());
  arb_mul_ui(k.get(), k.get(), 3, alg.prec());
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, l = (i + 2) % 3;
    ball coefficient;
    arb_sub(coefficient.get(), g.moments[static_cast<std::size_t>(l)].get(), g.moments[static_cast<std::size_t>(j)].get(),
            alg.prec());
    arb_mul(coefficient.get(), coefficient.get(), k.get(), alg.prec());
    value term = product(alg, b[static_cast<std::size_t>(j)], b[static_cast<std::size_t>(l)]);
    alg.scale(term, coefficient);
    alg.add(m[static_cast<std::size_t>(i)], term);
  }
}

// g(t, y, q) of formula set `set` (and the gravity gradient), in the integrator's variables,
// added to F[0..2].
template <class Algebra>
void add_torque(const certification_problem& p, std::size_t set, const Algebra& alg, const typename Algebra::value& t,
                const std::vector<typename Algebra::value>& x, std::vector<typename Algebra::value>& F) {
  using value = typename Algebra::value;
  const exact_variables& v = p.variables;
  // The formulas' time and state: t and x themselves in the integrator's own variables (no copy).
  formula_variables<Algebra> vars;
  vars.time = &t;
  for (int i = 0; i < 3; ++i) vars.state[i] = &x[i];
  value ts;
  std::array<value, 3> ys;
  if (!v.identity) {
    ts = t;
    alg.scale(ts, v.rate_inverse);
    vars.time = &ts;
    for (int i = 0; i < 3; ++i) {
      value s = x[i];
      alg.scale(s, v.state_scale[i]);
      if (v.axes.sign(i) < 0) alg.neg(s);
      ys[v.axes.axis(i)] = std::move(s);
    }
    for (int i = 0; i < 3; ++i) vars.state[i] = &ys[i];
  }
  if (p.dimension == 7)
    for (int r = 0; r < 4; ++r) vars.attitude[r] = &x[3 + r];
  std::array<value, 3> m;
  for (int u = 0; u < 3; ++u) {
    if (p.sets.empty()) {
      m[u] = alg.constant(ball(0));
      continue;
    }
    try {
      m[u] = p.sets[set][u](alg, vars);
    } catch (const undefined_formula& e) {
      // Name the torque's component and its piece.
      std::string where = p.law->name + std::to_string(u + 1) + " = " + e.what();
      if (set > 0)
        where += " in the piece [" + p.law->pieces[set - 1].from.text + ", " + p.law->pieces[set - 1].to.text + ")";
      throw undefined_formula(where);
    }
  }
  if (p.gravity) add_gravity(*p.gravity, alg, *vars.time, x, m);
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
  // Scratch kept per thread: the copies and products land in storage that earlier segments left,
  // and the sums in F's own, instead of values made and freed for every segment.
  thread_local std::array<value, 3> W;  // halved
  thread_local value term;
  for (int i = 0; i < 3; ++i) {
    value& w = W[p.rates.identity ? i : p.rates.axes.axis(i)];
    w = x[i];
    if (!p.rates.identity) {
      alg.scale(w, p.rates.scale[i]);
      if (p.rates.axes.sign(i) < 0) alg.neg(w);
    }
    alg.scale(w, half);
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
    value& sum = F[3 + r];
    alg.product(sum, q(terms[r][0][1]), W[terms[r][0][2]]);
    if (terms[r][0][0] < 0) alg.neg(sum);
    for (int t = 1; t < 3; ++t) {
      alg.product(term, q(terms[r][t][1]), W[terms[r][t][2]]);
      if (terms[r][t][0] < 0)
        alg.sub(sum, term);
      else
        alg.add(sum, term);
    }
  }
}

}  // namespace detail

// F(t, x) of formula set `set` in the algebra (x: the state, dimension p.dimension). Throws
// undefined_formula from a formula undefined where its arguments may be.
template <class Algebra>
void field(const certification_problem& p, std::size_t set, const Algebra& alg, const typename Algebra::value& t,
           const std::vector<typename Algebra::value>& x, std::vector<typename Algebra::value>& F) {
  static constexpr int pair[3][2] = {{1, 2}, {2, 0}, {0, 1}};
  F.resize(p.dimension);
  for (int i = 0; i < 3; ++i) {
    alg.product(F[i], x[pair[i][0]], x[pair[i][1]]);  // into F's own storage (a caller's F may be reused)
    if (p.unit_a[i] == -1)
      alg.neg(F[i]);
    else if (p.unit_a[i] != 1)
      alg.scale(F[i], p.a[i]);
  }
  if (!p.sets.empty() || p.gravity) detail::add_torque(p, set, alg, t, x, F);
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

// The general path of --certify (docs/certified.md, "The general path"): a proven bound on the
// distance between the reference and the exact solution of any problem the scenes can state
// (certification_problem.hpp: formulas of time and state, the gravity gradient), in 3 or 7 dimensions, with
// every number of the proof a ball (ball.hpp), so that rounding is bounded by the arithmetic.
//
// The reference is a piecewise polynomial: on each segment [a, b], the interpolant P of the stored
// node values, which define it exactly. Per segment (s in [-1, 1], tau = a + hl (s + 1)):
//   1. P's Chebyshev coefficients, enclosed (detail/ball_node_transform.hpp);
//   2. the field along P and its Jacobian J as Chebyshev models (certification_problem.hpp), and
//      the Picard residual r(s) = P(-1) + hl int F(P) - P(s);
//   3. bounds over the segment: |J|_2 <= jmax (Frobenius), the logarithmic norm mu (Gershgorin on
//      the symmetric part), and over the tube |y - P| <= R_cap the quadratic remainder c and |F|;
//   4. the variational matrix and the signed integral term (detail/ball_linear_flow.hpp);
// then, in order (advance): the a-priori bound R on the segment (Gronwall with e(a), sup|r| and
// the breakpoint term), and the error at b by Lohner's method (detail/ball_lohner_box.hpp):
//   e(b) in Phi(b, a) e(a) + r(b) + u(b) + [ball], ball = |Phi - Phi_num| |e(a)| + |u - u_num|
//   + h exp(mu+ h) c R^2.
// The breakpoint term: between a breakpoint of the reference and the exact one it stands for (a
// window a rounding wide), the exact solution may follow other formulas; their difference
// integrates to at most the window's width times sup |F_other - F| over the tube, component by
// component, and enters as a jump of e where the window lies: at the join of the segments around
// it (and in the rows of both).
// A row inside a segment gets the same statement at its tau, component by component
// (enclose()), so that each group of components (the rates, q) has its own radius.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/certification_problem.hpp>
#include <eulervop/certify/detail/ball_linear_flow.hpp>
#include <eulervop/certify/detail/ball_lohner_box.hpp>
#include <eulervop/certify/detail/ball_node_transform.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/field_algebra.hpp>
#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/segment.hpp>

#include <arb.h>
#include <arb_mat.h>

#include <algorithm>
#include <cstddef>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace eulervop {

// What the certificate proves at a row's tau: y(tau) component by component, and bounds over the
// segment's tube (|y - P| <= R_cap) for moving the statement along tau by a rounding's worth.
struct ball_row {
  std::vector<ball> y;          // each holds y_i(tau)
  std::vector<mag_value> rate;  // |y_i'| <= rate_i on the tube, whichever formulas apply
  mag_value reach;              // <= R_cap - R: how far y may move (2-norm) and stay in the tube
};

// The precision of the error's own arithmetic (the Lohner box, Phi and u at a row): e is about
// 2^-113 of the state or less, and a bound of it needs far fewer than 128 bits (at which Arb's
// numbers need no allocation); the state and the residual keep the problem's precision.
inline constexpr slong error_prec = 128;

// The part of one segment's check that does not depend on the segments before it (steps 1 to 4).
// It owns all its scratch, so that checks of different segments may be prepared on different
// threads.
class ball_segment_check {
 public:
  // `transform`: the node transform of the degree (copied: each check owns its scratch).
  ball_segment_check(const certification_problem& problem, const detail::ball_node_transform& transform);

  // Fails (numerical_failure, certification_failed) where the segment cannot be enclosed.
  template <scalar T, std::size_t D>
  void prepare(const chebyshev_segment<T, D>& seg);

  [[noreturn]] void fail(outcome_kind cause, double value = 0, const std::string& detail = {}) const;

  const certification_problem* problem;
  std::size_t D, n1;
  ball a, hl, h, b;
  std::vector<ball> start, end;  // P(-1) and P(1), from the stored values
  std::vector<detail::chebyshev_model> P, r;
  std::vector<detail::chebyshev_model> J;  // D x D
  std::vector<ball> r1;                     // r(1)
  // The bounds below are in the weighted norm |W v|_2, W = diag(weight): the state's components
  // keep weight 1, q's share a power of two chosen to minimise mu (bounds_of_jacobian); a bound B
  // of |W v| bounds each component |v_i| by B / weight_i.
  std::vector<double> weight;
  mag_value rsup, jmax, mu_plus, c, R_cap, psup;
  // The breakpoint windows (breakpoint_term): the jump of e at a's (signed where one exact
  // breakpoint stands behind it), the bound of the term of b's, and, for rows, each window that
  // touches the segment with its bound.
  std::vector<ball> jump_a;
  std::vector<mag_value> omega_b;
  struct touching_window {
    ball hull;
    std::vector<mag_value> bound;
  };
  std::vector<touching_window> windows;
  std::vector<mag_value> fabs;  // |F_i| over the tube, whichever formula set applies
  std::size_t set = 0;
  detail::ball_linear_flow flow;
  // Filled in order by ball_certifier::advance, for the rows: |e(a)|, R, the box at a.
  mag_value rho_a, R, R_plain;  // |W e(a)|; |W e| <= R and |e|_2 <= R_plain on the segment
  std::unique_ptr<detail::ball_lohner_box> box_at_a;

 private:
  void bounds_of_jacobian();
  void tube_bounds();
  void breakpoint_term();

  detail::ball_node_transform transform_;
  arb_mat_t coefficients_;
  std::vector<ball> X0_;

 public:
  ~ball_segment_check() { arb_mat_clear(coefficients_); }
  ball_segment_check(const ball_segment_check&) = delete;
  ball_segment_check& operator=(const ball_segment_check&) = delete;
};

inline ball_segment_check::ball_segment_check(const certification_problem& p,
                                              const detail::ball_node_transform& transform)
    : problem(&p), D(p.dimension), n1(transform.nodes()), start(D), end(D), P(D), r(D), J(D * D), r1(D),
      weight(D, 1.0), jump_a(D), omega_b(D), flow(D, error_prec), transform_(transform), X0_(D) {
  arb_mat_init(coefficients_, static_cast<slong>(n1), static_cast<slong>(D));
}

inline void ball_segment_check::fail(outcome_kind cause, double value, const std::string& detail) const {
  outcome o;
  o.kind = outcome_kind::certification_failed;
  o.cause = cause;
  o.value = value;
  o.tau = arf_get_d(arb_midref(a.get()), ARF_RND_NEAR);
  throw numerical_failure(o, detail);
}

template <scalar T, std::size_t Dim>
void ball_segment_check::prepare(const chebyshev_segment<T, Dim>& seg) {
  const slong prec = problem->prec;
  if (Dim != D || seg.values.size() != n1) throw std::invalid_argument("ball_segment_check: the segment's shape differs");
  set_exact(a, seg.tau_begin);
  set_exact(hl, seg.half_length);
  arb_mul_2exp_si(h.get(), hl.get(), 1);
  arb_add(b.get(), a.get(), h.get(), prec);
  ball lo;
  for (std::size_t i = 0; i < D; ++i) {
    set_exact(X0_[i], seg.base[i]);
    set_exact(lo, seg.base_lo[i]);
    arb_add(X0_[i].get(), X0_[i].get(), lo.get(), prec);
    for (std::size_t j = 0; j < n1; ++j) {
      ball v;
      set_exact(v, seg.values[j][i]);
      if (!arb_is_finite(v.get())) fail(outcome_kind::certify_non_finite);
      arb_set(transform_.value(j, i), v.get());
    }
    arb_add(start[i].get(), X0_[i].get(), transform_.value(0, i), prec);
    arb_add(end[i].get(), X0_[i].get(), transform_.value(n1 - 1, i), prec);
  }
  if (!arb_is_finite(a.get()) || !arb_is_finite(hl.get())) fail(outcome_kind::certify_non_finite);
  // 1. P's coefficients.
  transform_.apply(coefficients_);
  for (std::size_t i = 0; i < D; ++i) {
    P[i].resize(static_cast<slong>(n1));
    mag_zero(P[i].remainder());
    for (std::size_t k = 0; k < n1; ++k)
      arb_set(P[i].coeff(static_cast<slong>(k)), arb_mat_entry(coefficients_, static_cast<slong>(k), static_cast<slong>(i)));
    arb_add(P[i].coeff(0), P[i].coeff(0), X0_[i].get(), prec);
  }
  // 2. The field along P with its Jacobian, and the residual.
  std::vector<detail::series_jet> F;
  try {
    set = formula_set(*problem, a, b);
    const detail::series_algebra alg(prec, D);
    detail::chebyshev_model t(2);
    arb_add(t.coeff(0), a.get(), hl.get(), prec);
    arb_set(t.coeff(1), hl.get());
    std::vector<detail::series_jet> x;
    x.reserve(D);
    for (std::size_t k = 0; k < D; ++k) x.push_back(alg.variable(P[k], k));
    field(*problem, set, alg, alg.independent(std::move(t)), x, F);
  } catch (const std::domain_error& e) {
    fail(outcome_kind::certify_formula, 0, e.what());
  }
  for (std::size_t i = 0; i < D; ++i) {
    detail::integrate(r[i], F[i].f, hl, prec);
    arb_add(r[i].coeff(0), r[i].coeff(0), start[i].get(), prec);
    detail::subtract_from(r[i], P[i], prec);
    arb_zero(r1[i].get());
    for (slong k = 0; k < r[i].length(); ++k) arb_add(r1[i].get(), r1[i].get(), r[i].coeff(k), prec);
    arb_add_error_mag(r1[i].get(), r[i].remainder());
    for (std::size_t k = 0; k < D; ++k) J[i * D + k] = std::move(F[i].d[k]);
  }
  // 3. Bounds over the segment and the tube, in the weighted norm.
  bounds_of_jacobian();
  mag_value s;
  mag_zero(rsup.m);
  for (std::size_t i = 0; i < D; ++i) {
    detail::sup_bound(s.m, r[i]);
    mag_mul_2exp_si(s.m, s.m, std::ilogb(weight[i]));
    mag_addmul(rsup.m, s.m, s.m);
  }
  mag_sqrt(rsup.m, rsup.m);
  if (!mag_is_finite(rsup.m)) fail(outcome_kind::certify_non_finite);
  tube_bounds();
  breakpoint_term();
  // 4. Phi and u.
  flow.load_jacobian(std::move(J), weight);
  J.assign(D * D, detail::chebyshev_model());
  const double jh = mag_get_d(jmax.m) * arf_get_d(arb_midref(h.get()), ARF_RND_UP);
  if (!flow.variational(hl, jh)) fail(outcome_kind::certify_non_finite);
  if (!flow.integral_term(r, hl)) fail(outcome_kind::certify_non_finite);
}

// In the weighted norm, W J W^-1 has the entries J_ik w_i / w_k. jmax >= its 2-norm (the Frobenius
// norm, from the ranges of the entries); mu >= the largest eigenvalue of its symmetric part
// (Gershgorin's theorem on the ranges of the symmetric part's entries: where w_i = w_k, of the
// range of J_ik + J_ki itself, so that a skew block such as q's adds nothing). q's weight is the
// power of two, from 1 down to 2^-12, with the smallest mu: the rates' error drives q's through a
// coupling that carries the units of the map from the rates to the body's (body_rates.hpp), and
// with the plain norm that coupling alone would set mu.
inline void ball_segment_check::bounds_of_jacobian() {
  const slong prec = problem->prec;
  const auto group = [](std::size_t i) { return i < 3 ? 0 : 1; };
  // |J_ik| over the segment; where i and k share a weight, |J_ik + J_ki| / 2; the range of J_ii.
  std::vector<mag_value> range(D * D), sym(D * D);
  std::vector<ball> diag(D);
  ball x;
  detail::chebyshev_model sum;
  for (std::size_t q = 0; q < D * D; ++q) {
    range_of(x, J[q]);
    arb_get_mag(range[q].m, x.get());
    if (q % (D + 1) == 0) diag[q / D] = x;
  }
  for (std::size_t i = 0; i < D; ++i)
    for (std::size_t k = i + 1; k < D; ++k) {
      if (group(i) != group(k)) continue;
      sum = J[i * D + k];
      detail::add_to(sum, J[k * D + i], prec);
      range_of(x, sum);
      arb_get_mag(sym[i * D + k].m, x.get());
      mag_mul_2exp_si(sym[i * D + k].m, sym[i * D + k].m, -1);
      mag_set(sym[k * D + i].m, sym[i * D + k].m);
    }
  // mu for q's weight 2^-e: Gershgorin's bound, each row's radius summed in mags (upward).
  arf_t up, mu_e;
  arf_init(up);
  arf_init(mu_e);
  mag_value m, other;
  const auto mu_of = [&](int e, arf_t out) {
    const auto scaled = [&](std::size_t i, std::size_t k, mag_t o) {  // |J_ik| w_i / w_k
      mag_mul_2exp_si(o, range[i * D + k].m, (group(k) - group(i)) * e);
    };
    arf_zero(out);
    for (std::size_t i = 0; i < D; ++i) {
      ball row = diag[i];
      for (std::size_t k = 0; k < D; ++k) {
        if (k == i) continue;
        if (group(i) == group(k)) {
          mag_set(m.m, sym[i * D + k].m);
        } else {
          scaled(i, k, m.m);
          scaled(k, i, other.m);
          mag_add(m.m, m.m, other.m);
          mag_mul_2exp_si(m.m, m.m, -1);
        }
        arb_add_error_mag(row.get(), m.m);
      }
      arb_get_ubound_arf(up, row.get(), prec);
      arf_max(out, out, up);  // mu+ = max(mu, 0): exp(mu+ dt) bounds |Phi| for growth and decay alike
    }
  };
  int best_e = 0;
  mu_of(0, mu_e);
  arf_t best;
  arf_init(best);
  arf_set(best, mu_e);
  if (D == 7)
    for (int e = 1; e <= 12; ++e) {
      mu_of(e, mu_e);
      if (arf_cmp(mu_e, best) < 0) {
        arf_set(best, mu_e);
        best_e = e;
      }
    }
  arf_get_mag(mu_plus.m, best);
  for (std::size_t i = 0; i < D; ++i) weight[i] = std::ldexp(1.0, -best_e * group(i));
  mag_zero(jmax.m);
  for (std::size_t i = 0; i < D; ++i)
    for (std::size_t k = 0; k < D; ++k) {
      mag_mul_2exp_si(m.m, range[i * D + k].m, (group(k) - group(i)) * best_e);
      mag_addmul(jmax.m, m.m, m.m);
    }
  mag_sqrt(jmax.m, jmax.m);
  arf_clear(up);
  arf_clear(mu_e);
  arf_clear(best);
  if (!mag_is_finite(jmax.m) || !mag_is_finite(mu_plus.m)) fail(outcome_kind::certify_non_finite);
}

// The tube |y - P| <= R_cap with R_cap = 2^-20 max(1, sup |P|), where the box would fail the
// growth check anyway: c and |F| over it (the largest |F| over every formula set, for rows moved
// across a breakpoint).
inline void ball_segment_check::tube_bounds() {
  const slong prec = problem->prec;
  mag_value m;
  mag_one(psup.m);
  for (const detail::chebyshev_model& p : P) {
    detail::sup_bound(m.m, p);
    mag_max(psup.m, psup.m, m.m);
  }
  mag_mul_2exp_si(R_cap.m, psup.m, -20);
  std::vector<ball> box(D);
  for (std::size_t i = 0; i < D; ++i) {
    detail::range_of(box[i], P[i]);
    arb_add_error_mag(box[i].get(), R_cap.m);
  }
  ball t;
  arb_union(t.get(), a.get(), b.get(), prec);
  try {
    box_bounds(*problem, set, t, box, weight, c.m, fabs);
    for (std::size_t other = 0; other < problem->sets.size(); ++other) {
      if (other == set) continue;
      mag_value c_other;
      std::vector<mag_value> f_other;
      box_bounds(*problem, other, t, box, weight, c_other.m, f_other);
      for (std::size_t i = 0; i < D; ++i) mag_max(fabs[i].m, fabs[i].m, f_other[i].m);
    }
  } catch (const std::domain_error& e) {
    fail(outcome_kind::certify_formula, 0, e.what());
  }
  if (!mag_is_finite(c.m)) fail(outcome_kind::certify_non_finite);
  for (const mag_value& f : fabs)
    if (!mag_is_finite(f.m)) fail(outcome_kind::certify_non_finite);
}

// The breakpoint term of the windows (the hull of a breakpoint of the reference and the exact ones
// it stands for) that touch a or b. On a window the exact solution y' = F_exact(y) differs from the
// reference's y' = F(y) by d, |d_i| <= sup |F_other,i - F_i| over the tube (other any formula set),
// for as long as the window's width; its effect on e is int Phi d, whose component i is at most
// width (sup|d_i| + (exp(|J| width) - 1) sum_k sup|d_k|) (|Phi - I| <= exp(|J| width) - 1 there):
// the window's bound. Where one exact breakpoint B* stands behind the reference's B, with the
// formulas L before and R after, int d = (B* - B) (F_L - F_R)(t, y) for some t in the window and y
// near y(B), whichever side B* lies on: that signed jump of e enters at the join at B (jump_a), the
// bound only as its radius; the rows in the window take the bound (whether the window has passed
// at the row's time is not known). y stays in the tube across the window: it moves by at most
// width |F|, checked below R_cap/4.
inline void ball_segment_check::breakpoint_term() {
  const slong prec = problem->prec;
  for (std::size_t i = 0; i < D; ++i) {
    arb_zero(jump_a[i].get());
    mag_zero(omega_b[i].m);
  }
  windows.clear();
  const detail::box_algebra alg(prec, 0);
  // The field of formula set `s` over the window's time `t` and the states `y`.
  const auto field_over = [&](std::size_t s, const ball& t, const std::vector<ball>& y) {
    std::vector<detail::box_jet> x, F;
    for (const ball& yi : y) x.push_back(alg.independent(yi));
    field(*problem, s, alg, alg.independent(t), x, F);
    return F;
  };
  ball span;
  arb_union(span.get(), a.get(), b.get(), prec);
  for (const breakpoint_window& w : problem->breakpoints) {
    const bool at_a = arb_overlaps(w.hull.get(), a.get()), at_b = arb_overlaps(w.hull.get(), b.get());
    // The reference ends a segment at every breakpoint: one inside a segment means its breakpoints
    // are not the scene's (the formulas would change where nothing accounts for it).
    if (!at_a && !at_b && arb_overlaps(w.hull.get(), span.get()))
      fail(outcome_kind::certify_formula, 0, "a breakpoint of the torque lies inside a segment of the reference");
    if (!at_a && !at_b) continue;
    mag_value width, m, move, sum, spread;
    mag_mul_2exp_si(width.m, arb_radref(w.hull.get()), 1);
    if (mag_is_zero(width.m)) continue;
    std::vector<ball> tube(D), near(D);
    for (std::size_t i = 0; i < D; ++i) {
      detail::range_of(tube[i], P[i]);
      arb_add_error_mag(tube[i].get(), R_cap.m);
      near[i] = at_a ? start[i] : end[i];
      arb_add_error_mag(near[i].get(), R_cap.m);
    }
    std::vector<mag_value> d(D);
    std::vector<ball> signed_jump;
    try {
      const std::vector<detail::box_jet> mine = field_over(set, w.hull, tube);
      for (std::size_t other = 0; other < problem->sets.size(); ++other) {
        if (other == set) continue;
        const std::vector<detail::box_jet> theirs = field_over(other, w.hull, tube);
        for (std::size_t i = 0; i < D; ++i) {
          ball di;
          arb_sub(di.get(), theirs[i].f.get(), mine[i].f.get(), prec);
          arb_get_mag(m.m, di.get());
          mag_max(d[i].m, d[i].m, m.m);
        }
      }
      if (at_a && w.exact_count == 1) {
        // L: the set just before the window (this segment, which starts at B, has R).
        // L: the set at a time 16 window widths before the window (this segment, which starts at B,
        // has R); a formula_set_at that cannot tell throws, and the bound alone stands.
        ball before;
        arf_t lo, lead;
        arf_init(lo);
        arf_init(lead);
        arb_get_lbound_arf(lo, w.hull.get(), prec);
        arf_set_mag(lead, width.m);
        arf_mul_2exp_si(lead, lead, 4);
        arf_sub(lo, lo, lead, prec, ARF_RND_DOWN);
        arb_set_arf(before.get(), lo);
        arf_clear(lo);
        arf_clear(lead);
        std::optional<std::size_t> L;
        try {
          L = formula_set_at(*problem, before);
        } catch (const std::domain_error&) {
        }
        if (L) {
          const std::vector<detail::box_jet> left = field_over(*L, w.hull, near),
                                             right = field_over(set, w.hull, near);
          ball distance;
          arb_sub(distance.get(), w.exact.get(), w.reference.get(), prec);
          signed_jump.resize(D);
          for (std::size_t i = 0; i < D; ++i) {
            arb_sub(signed_jump[i].get(), left[i].f.get(), right[i].f.get(), prec);
            arb_mul(signed_jump[i].get(), signed_jump[i].get(), distance.get(), prec);
          }
        }
      }
    } catch (const std::domain_error& e) {
      fail(outcome_kind::certify_formula, 0, e.what());
    }
    for (std::size_t i = 0; i < D; ++i) {
      mag_add(sum.m, sum.m, d[i].m);
      mag_addmul(move.m, fabs[i].m, fabs[i].m);
    }
    mag_sqrt(move.m, move.m);
    mag_mul(move.m, move.m, width.m);
    mag_mul_2exp_si(m.m, R_cap.m, -2);
    if (mag_cmp(move.m, m.m) > 0) fail(outcome_kind::certify_growth, 0, "a breakpoint's window is too wide");
    // (exp(|J| width) - 1) sum_k d_k, with |J|_2 <= jmax / min w in the plain norm.
    mag_mul(spread.m, jmax.m, width.m);
    mag_mul_2exp_si(spread.m, spread.m, -std::ilogb(*std::min_element(weight.begin(), weight.end())));
    mag_expm1(spread.m, spread.m);
    mag_mul(spread.m, spread.m, sum.m);
    touching_window tw{w.hull, std::vector<mag_value>(D)};
    for (std::size_t i = 0; i < D; ++i) {
      mag_add(m.m, d[i].m, spread.m);
      mag_mul(tw.bound[i].m, m.m, width.m);
      if (at_b) mag_add(omega_b[i].m, omega_b[i].m, tw.bound[i].m);
      if (at_a) {
        if (signed_jump.empty()) {
          arb_add_error_mag(jump_a[i].get(), tw.bound[i].m);
        } else {
          mag_mul(m.m, spread.m, width.m);
          arb_add_error_mag(signed_jump[i].get(), m.m);
          arb_add(jump_a[i].get(), jump_a[i].get(), signed_jump[i].get(), prec);
        }
      }
    }
    windows.push_back(std::move(tw));
  }
}

class ball_certifier {
 public:
  using check = ball_segment_check;

  // `problem`: the exact problem (certification_problem.hpp); `degree`: the reference's N.
  ball_certifier(certification_problem problem, std::size_t degree)
      : problem_(std::make_shared<const certification_problem>(std::move(problem))),
        transform_(problem_->prec, degree, problem_->dimension), box_(problem_->dimension, error_prec),
        prev_end_(problem_->dimension) {}

  const certification_problem& problem() const { return *problem_; }

  // An empty check (safe from any thread: it only reads the problem).
  std::unique_ptr<ball_segment_check> make_segment() const {
    return std::make_unique<ball_segment_check>(*problem_, transform_);
  }
  // The next segment's prepared check, in order; returns the previous segment's check for reuse.
  std::unique_ptr<ball_segment_check> advance(std::unique_ptr<ball_segment_check> prepared);

  template <scalar T, std::size_t D>
  void add_segment(const chebyshev_segment<T, D>& seg) {
    if (!spare_) spare_ = make_segment();
    spare_->prepare(seg);
    spare_ = advance(std::move(spare_));
  }

  // The statement at tau in the latest segment.
  template <scalar T>
  ball_row enclose(const T& tau) const;

 private:
  std::shared_ptr<const certification_problem> problem_;
  detail::ball_node_transform transform_;  // enclosed once, copied into every check
  detail::ball_lohner_box box_;
  std::unique_ptr<ball_segment_check> current_, spare_;
  std::vector<ball> prev_end_;
  ball prev_b_;
  bool started_ = false;
};

namespace detail {
// A bound B of |W v|_2 as bounds of each component: |v_i| <= B / w_i.
inline std::vector<mag_value> per_component(const mag_value& B, const std::vector<double>& weight) {
  std::vector<mag_value> out(weight.size());
  for (std::size_t i = 0; i < weight.size(); ++i) mag_mul_2exp_si(out[i].m, B.m, -std::ilogb(weight[i]));
  return out;
}
// exp(mu+ dt) and the factor (1 + dt exp(mu+ dt) jmax) of a residual's propagated error.
inline void growth_factors(const mag_t mu_plus, const mag_t jmax, const mag_t dt, mag_t expo, mag_t factor) {
  mag_mul(expo, mu_plus, dt);
  mag_exp(expo, expo);
  mag_mul(factor, dt, expo);
  mag_mul(factor, factor, jmax);
  mag_add_ui(factor, factor, 1);
}
}  // namespace detail

inline std::unique_ptr<ball_segment_check> ball_certifier::advance(std::unique_ptr<ball_segment_check> prepared) {
  ball_segment_check& c = *prepared;
  const std::size_t D = problem_->dimension;
  const slong prec = problem_->prec;
  // e(a): the scene's exact initial state less P(a), or the previous segment's box plus the jump
  // between the two polynomials at the join; and a breakpoint window there (breakpoint_term).
  std::vector<ball> e(D);
  for (std::size_t i = 0; i < D; ++i) {
    if (started_)
      arb_sub(e[i].get(), prev_end_[i].get(), c.start[i].get(), prec);
    else
      arb_sub(e[i].get(), problem_->initial[i].get(), c.start[i].get(), prec);
    arb_add(e[i].get(), e[i].get(), c.jump_a[i].get(), prec);
  }
  if (started_) {
    if (!arb_equal(prev_b_.get(), c.a.get())) c.fail(outcome_kind::certify_segment_gap);
    box_.join(e);
  } else {
    box_.start(e);
  }
  if (!c.box_at_a) c.box_at_a = std::make_unique<detail::ball_lohner_box>(box_);
  else *c.box_at_a = box_;
  box_.norm(c.rho_a.m, c.weight);
  // The a-priori bound, in the weighted norm |W .| of the segment. z = e - r solves z' = J z + J r + N(e) (+ the breakpoint term), z(a) = e(a),
  // so while |e| <= R, |z| <= exp(mu+ h) (|e(a)| + omega + h (jmax sup|r| + c R^2)) (the logarithmic
  // norm's comparison theorem) and |e| <= |z| + sup|r|. With R = 2 (exp(mu+ h) (|e(a)| + omega +
  // h jmax sup|r|) + sup|r|), that is below R when exp(mu+ h) h c R < 1/2, and |e| never reaches R
  // (continuity from |e(a)| < R).
  mag_value R, hm, expo, factor, t;
  arb_get_mag(hm.m, c.h.get());
  detail::growth_factors(c.mu_plus.m, c.jmax.m, hm.m, expo.m, factor.m);
  mag_mul(R.m, c.jmax.m, c.rsup.m);
  mag_mul(R.m, R.m, hm.m);
  mag_add(R.m, R.m, c.rho_a.m);
  mag_value omega;
  for (std::size_t i = 0; i < D; ++i) {
    mag_mul_2exp_si(t.m, c.omega_b[i].m, std::ilogb(c.weight[i]));
    mag_addmul(omega.m, t.m, t.m);
  }
  mag_sqrt(omega.m, omega.m);
  mag_add(R.m, R.m, omega.m);
  mag_mul(R.m, R.m, expo.m);
  mag_add(R.m, R.m, c.rsup.m);
  mag_mul_2exp_si(R.m, R.m, 1);
  mag_mul(t.m, expo.m, hm.m);
  mag_mul(t.m, t.m, c.c.m);
  mag_mul(t.m, t.m, R.m);
  mag_mul_2exp_si(t.m, t.m, 1);
  // |e|_2 <= |W e| / min w: the tube of c and |F| must hold it (with room for rows moved along tau).
  mag_value half_cap;
  mag_mul_2exp_si(half_cap.m, c.R_cap.m, -1 + std::ilogb(*std::min_element(c.weight.begin(), c.weight.end())));
  if (!(mag_cmp_2exp_si(t.m, 0) < 0) || mag_cmp(R.m, half_cap.m) > 0) c.fail(outcome_kind::certify_a_priori);
  mag_set(c.R.m, R.m);
  mag_mul_2exp_si(c.R_plain.m, R.m, -std::ilogb(*std::min_element(c.weight.begin(), c.weight.end())));
  // The ball at b: |Phi - Phi_num| |e(a)| + |u - u_num| + h exp(mu+ h) c R^2. (A window at b enters
  // at the next segment's join, whole.)
  mag_value ball_b;
  mag_mul(ball_b.m, c.flow.phi_residual(), factor.m);
  mag_mul(ball_b.m, ball_b.m, c.rho_a.m);
  mag_mul(t.m, c.flow.u_residual(), factor.m);
  mag_add(ball_b.m, ball_b.m, t.m);
  mag_mul(t.m, R.m, R.m);
  mag_mul(t.m, t.m, c.c.m);
  mag_mul(t.m, t.m, hm.m);
  mag_mul(t.m, t.m, expo.m);
  mag_add(ball_b.m, ball_b.m, t.m);
  std::vector<ball> w(D);
  for (std::size_t i = 0; i < D; ++i) arb_add(w[i].get(), c.r1[i].get(), c.flow.u1()[i].get(), prec);
  if (!box_.step(c.flow.Phi1(), w, detail::per_component(ball_b, c.weight))) c.fail(outcome_kind::certify_non_finite);
  // Growth: a box beyond 2^-20 of the state is of no use to anyone (as lohner_box.hpp).
  mag_value size;
  box_.norm(size.m, std::vector<double>(D, 1.0));
  if (!mag_is_finite(size.m)) c.fail(outcome_kind::certify_non_finite);
  if (mag_cmp(size.m, c.R_cap.m) > 0) c.fail(outcome_kind::certify_growth, mag_get_d(size.m) / mag_get_d(c.psup.m));
  for (std::size_t i = 0; i < D; ++i) prev_end_[i] = c.end[i];
  prev_b_ = c.b;
  started_ = true;
  std::swap(current_, prepared);
  return prepared;
}

template <scalar T>
ball_row ball_certifier::enclose(const T& tau) const {
  const ball_segment_check& c = *current_;
  const std::size_t D = problem_->dimension;
  const slong prec = problem_->prec;
  ball dt, s, tb;
  set_exact(tb, tau);
  set_exact(dt, tau);
  arb_sub(dt.get(), dt.get(), c.a.get(), prec);
  arb_div(s.get(), dt.get(), c.hl.get(), prec);
  arb_sub_ui(s.get(), s.get(), 1, prec);
  // e(tau) in Phi(tau, a) B x + r(tau) + u(tau) + ball(dt), at the error's precision; P(tau) at
  // the problem's.
  slong n = c.flow.max_length(), np = 1;
  for (std::size_t i = 0; i < D; ++i) {
    n = std::max(n, c.r[i].length());
    np = std::max(np, c.P[i].length());
  }
  const detail::chebyshev_values Ts(n, s, error_prec), Tp(np, s, prec);
  std::vector<ball> Phi, u, e;
  c.flow.Phi_at(Ts, Phi);
  c.flow.u_at(Ts, u);
  c.box_at_a->image(Phi, e);
  mag_value dtm, expo, factor, rowball, t;
  arb_get_mag(dtm.m, dt.get());
  detail::growth_factors(c.mu_plus.m, c.jmax.m, dtm.m, expo.m, factor.m);
  mag_mul(rowball.m, c.flow.phi_residual(), factor.m);
  mag_mul(rowball.m, rowball.m, c.rho_a.m);
  mag_mul(t.m, c.flow.u_residual(), factor.m);
  mag_add(rowball.m, rowball.m, t.m);
  mag_mul(t.m, c.R.m, c.R.m);
  mag_mul(t.m, t.m, c.c.m);
  mag_mul(t.m, t.m, dtm.m);
  mag_mul(t.m, t.m, expo.m);
  mag_add(rowball.m, rowball.m, t.m);
  ball_row out;
  out.y.resize(D);
  ball v;
  const std::vector<mag_value> radius = detail::per_component(rowball, c.weight);
  for (std::size_t i = 0; i < D; ++i) {
    detail::evaluate(v, c.r[i], Ts, error_prec);
    arb_add(e[i].get(), e[i].get(), v.get(), error_prec);
    arb_add(e[i].get(), e[i].get(), u[i].get(), error_prec);
    arb_add_error_mag(e[i].get(), radius[i].m);
    for (const ball_segment_check::touching_window& w : c.windows)
      if (arb_overlaps(w.hull.get(), tb.get())) arb_add_error_mag(e[i].get(), w.bound[i].m);
    detail::evaluate(out.y[i], c.P[i], Tp, prec);
    arb_add(out.y[i].get(), out.y[i].get(), e[i].get(), prec);
  }
  out.rate = c.fabs;
  mag_sub_lower(out.reach.m, c.R_cap.m, c.R_plain.m);
  return out;
}

}  // namespace eulervop

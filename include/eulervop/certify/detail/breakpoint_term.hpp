// The breakpoint term of the general path (ball_certifier.hpp; docs/certified.md, "The general
// path"): the windows (the hull of a breakpoint of the reference and the exact ones it stands for)
// that touch a segment's ends a or b. On a window the exact solution y' = F_exact(y) differs from
// the reference's y' = F(y) by d, |d_i| <= sup |F_other,i - F_i| over the tube (other any formula
// set), for as long as the window's width; its effect on e is int Phi d, whose component i is at
// most width (sup|d_i| + (exp(|J| width) - 1) sum_k sup|d_k|) (|Phi - I| <= exp(|J| width) - 1
// there): the window's bound. Where one exact breakpoint B* stands behind the reference's B, with
// the formulas L before and R after, int d = (B* - B) (F_L - F_R)(t, y) for some t in the window
// and y near y(B), whichever side B* lies on: that signed jump of e enters at the join at B
// (jump_a), the bound only as its radius; the rows in the window take the bound (whether the
// window has passed at the row's time is not known). y stays in the tube across the window: it
// moves by at most width |F|, checked below R_cap/4.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/certification_problem.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/field_algebra.hpp>
#include <eulervop/core/numerical_failure.hpp>

#include <arb.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

namespace eulervop::detail {

class breakpoint_term {
 public:
  explicit breakpoint_term(std::size_t D) : jump_a(D), omega_b(D) {}

  // `s`: the segment's check (ball_certifier.hpp's ball_segment_check; a template only because
  // the check holds this term), with P, its ends, the tube (R_cap, fabs) and jmax and the weights
  // of step 3. Fails through s.fail (certification_failed).
  template <class Segment>
  void compute(const Segment& s);

  // The jump of e at a (signed where one exact breakpoint stands behind it), the bound of the term
  // at b, and, for rows, each window that touches the segment with its bound.
  std::vector<ball> jump_a;
  std::vector<mag_value> omega_b;
  struct touching_window {
    ball hull;
    std::vector<mag_value> bound;
  };
  std::vector<touching_window> windows;

 private:
  template <class Segment>
  static std::vector<box_jet> field_over(const Segment& s, const box_algebra& alg, std::size_t set, const ball& t,
                                         const std::vector<ball>& y);
  template <class Segment>
  static void formula_difference(const Segment& s, const box_algebra& alg, const breakpoint_window& w,
                                 const std::vector<ball>& tube, std::vector<mag_value>& d);
  template <class Segment>
  static void signed_jump_at(const Segment& s, const box_algebra& alg, const breakpoint_window& w,
                             const mag_value& width, const std::vector<ball>& near, std::vector<ball>& signed_jump);
  template <class Segment>
  void add_window(const Segment& s, const breakpoint_window& w, bool at_a, bool at_b, const mag_value& width,
                  const std::vector<mag_value>& d, std::vector<ball>& signed_jump);
};

template <class Segment>
void breakpoint_term::compute(const Segment& s) {
  const std::size_t D = s.D;
  const slong prec = s.problem->prec;
  for (std::size_t i = 0; i < D; ++i) {
    arb_zero(jump_a[i].get());
    mag_zero(omega_b[i].m);
  }
  windows.clear();
  const box_algebra alg(prec, 0);
  ball span;
  arb_union(span.get(), s.a.get(), s.b.get(), prec);
  for (const breakpoint_window& w : s.problem->breakpoints) {
    const bool at_a = arb_overlaps(w.hull.get(), s.a.get()), at_b = arb_overlaps(w.hull.get(), s.b.get());
    // The reference ends a segment at every breakpoint: one inside a segment means its breakpoints
    // are not the scene's (the formulas would change where nothing accounts for it).
    if (!at_a && !at_b && arb_overlaps(w.hull.get(), span.get()))
      s.fail(outcome_kind::certify_formula, 0, "a breakpoint of the torque lies inside a segment of the reference");
    if (!at_a && !at_b) continue;
    mag_value width;
    mag_mul_2exp_si(width.m, arb_radref(w.hull.get()), 1);
    if (mag_is_zero(width.m)) continue;
    std::vector<ball> tube(D), near(D);
    for (std::size_t i = 0; i < D; ++i) {
      range_of(tube[i], s.P[i]);
      arb_add_error_mag(tube[i].get(), s.R_cap.m);
      near[i] = at_a ? s.start[i] : s.end[i];
      arb_add_error_mag(near[i].get(), s.R_cap.m);
    }
    std::vector<mag_value> d(D);
    std::vector<ball> signed_jump;
    try {
      formula_difference(s, alg, w, tube, d);
      if (at_a && w.exact_count == 1) signed_jump_at(s, alg, w, width, near, signed_jump);
    } catch (const std::domain_error& e) {
      s.fail(outcome_kind::certify_formula, 0, e.what());
    }
    add_window(s, w, at_a, at_b, width, d, signed_jump);
  }
}

// The field of formula set `set` over the window's time `t` and the states `y`.
template <class Segment>
std::vector<box_jet> breakpoint_term::field_over(const Segment& s, const box_algebra& alg, std::size_t set,
                                                 const ball& t, const std::vector<ball>& y) {
  std::vector<box_jet> x, F;
  for (const ball& yi : y) x.push_back(alg.independent(yi));
  field(*s.problem, set, alg, alg.independent(t), x, F);
  return F;
}

// d_i >= sup |F_other,i - F_i| over the window and the tube, every other formula set.
template <class Segment>
void breakpoint_term::formula_difference(const Segment& s, const box_algebra& alg, const breakpoint_window& w,
                                         const std::vector<ball>& tube, std::vector<mag_value>& d) {
  const std::vector<box_jet> mine = field_over(s, alg, s.set, w.hull, tube);
  mag_value m;
  for (std::size_t other = 0; other < s.problem->sets.size(); ++other) {
    if (other == s.set) continue;
    const std::vector<box_jet> theirs = field_over(s, alg, other, w.hull, tube);
    for (std::size_t i = 0; i < s.D; ++i) {
      ball di;
      arb_sub(di.get(), theirs[i].f.get(), mine[i].f.get(), s.problem->prec);
      arb_get_mag(m.m, di.get());
      mag_max(d[i].m, d[i].m, m.m);
    }
  }
}

// The signed jump (B* - B) (F_L - F_R) at a window with one exact breakpoint B* that starts the
// segment (whose formulas are R): L is the set at a time 16 window widths before the window; a
// formula_set_at that cannot tell throws, and the bound alone stands (signed_jump stays empty).
template <class Segment>
void breakpoint_term::signed_jump_at(const Segment& s, const box_algebra& alg, const breakpoint_window& w,
                                     const mag_value& width, const std::vector<ball>& near,
                                     std::vector<ball>& signed_jump) {
  const slong prec = s.problem->prec;
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
    L = formula_set_at(*s.problem, before);
  } catch (const std::domain_error&) {
  }
  if (!L) return;
  const std::vector<box_jet> left = field_over(s, alg, *L, w.hull, near), right = field_over(s, alg, s.set, w.hull, near);
  ball distance;
  arb_sub(distance.get(), w.exact.get(), w.reference.get(), prec);
  signed_jump.resize(s.D);
  for (std::size_t i = 0; i < s.D; ++i) {
    arb_sub(signed_jump[i].get(), left[i].f.get(), right[i].f.get(), prec);
    arb_mul(signed_jump[i].get(), signed_jump[i].get(), distance.get(), prec);
  }
}

// The window's bound width (d_i + (exp(|J| width) - 1) sum_k d_k) into omega_b, jump_a and the
// rows' windows, after the check that y stays in the tube across it.
template <class Segment>
void breakpoint_term::add_window(const Segment& s, const breakpoint_window& w, bool at_a, bool at_b,
                                 const mag_value& width, const std::vector<mag_value>& d,
                                 std::vector<ball>& signed_jump) {
  const std::size_t D = s.D;
  mag_value m, move, sum, spread;
  for (std::size_t i = 0; i < D; ++i) {
    mag_add(sum.m, sum.m, d[i].m);
    mag_addmul(move.m, s.fabs[i].m, s.fabs[i].m);
  }
  mag_sqrt(move.m, move.m);
  mag_mul(move.m, move.m, width.m);
  mag_mul_2exp_si(m.m, s.R_cap.m, -2);
  if (mag_cmp(move.m, m.m) > 0) s.fail(outcome_kind::certify_growth, 0, "a breakpoint's window is too wide");
  // (exp(|J| width) - 1) sum_k d_k, with |J|_2 <= jmax / min w in the plain norm.
  mag_mul(spread.m, s.jmax.m, width.m);
  mag_mul_2exp_si(spread.m, spread.m, -std::ilogb(*std::min_element(s.weight.begin(), s.weight.end())));
  mag_expm1(spread.m, spread.m);
  mag_mul(spread.m, spread.m, sum.m);
  touching_window tw{w.hull, std::vector<mag_value>(D)};
  for (std::size_t i = 0; i < D; ++i) {
    mag_add(m.m, d[i].m, spread.m);
    mag_mul(tw.bound[i].m, m.m, width.m);
    if (at_b) mag_add(omega_b[i].m, omega_b[i].m, tw.bound[i].m);
    if (!at_a) continue;
    if (signed_jump.empty()) {
      arb_add_error_mag(jump_a[i].get(), tw.bound[i].m);
    } else {
      mag_mul(m.m, spread.m, width.m);
      arb_add_error_mag(signed_jump[i].get(), m.m);
      arb_add(jump_a[i].get(), jump_a[i].get(), signed_jump[i].get(), s.problem->prec);
    }
  }
  windows.push_back(std::move(tw));
}

}  // namespace eulervop::detail

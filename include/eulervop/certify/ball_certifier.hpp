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
#include <eulervop/certify/detail/breakpoint_term.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/field_algebra.hpp>
#include <eulervop/certify/detail/residual_model.hpp>
#include <eulervop/certify/detail/weighted_jacobian_bounds.hpp>
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

// What a row at tau takes from its segment alone (s = (tau - a) / hl - 1): Phi(s), r(s) and
// u_num(s) at the error's precision, P(s) at the problem's, and |tau - a|.
struct ball_row_part {
  ball tau;
  std::vector<ball> Phi, r, u, P;
  mag_value dt;
};

// The precision of the error's own arithmetic (the Lohner box, Phi and u at a row): e is about
// 2^-113 of the state or less, and a bound of it needs far fewer than 128 bits (at which Arb's
// numbers need no allocation); the state and the residual keep the problem's precision.
inline constexpr slong error_prec = 128;
// A row's e, from the box and the models at its tau, is a bound only: 64 bits (one limb) hold it
// to far below its last printed digit (its T_k(s) rounded from the working precision's, where a
// recurrence at 64 bits widens like 2.4^k 2^-64).
inline constexpr slong row_error_prec = 64;

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
  // The ball of e at a + dt (after ball_certifier::advance): |Phi - Phi_num| |W e(a)| +
  // |W (u - u_num)|, each propagated, + dt exp(mu+ dt) c R^2.
  void error_ball(const mag_t dt, mag_t out) const;
  // A row's part at tau (an exact ball), and the one prepared with the segment, if any.
  void evaluate_row(ball_row_part& out, const ball& tau) const;
  const ball_row_part* prepared_row(const ball& tau) const;

  const certification_problem* problem;
  std::size_t D, n1;
  ball a, hl, h, b;
  std::vector<ball> start, end;  // P(-1) and P(1), from the stored values
  std::vector<detail::chebyshev_model> P, r;
  std::vector<detail::chebyshev_model> J;  // D x D
  std::vector<ball> r1;                     // r(1)
  // For the rows: how much of r and of u_num they sum, and the bound of the rest (row_models()).
  struct row_sum {
    slong length = 0;
    mag_value tail;
  };
  std::vector<row_sum> r_row, u_row;
  // The bounds below are in the weighted norm |W v|_2, W = diag(weight): the state's components
  // keep weight 1, q's share a power of two chosen to minimise mu (bounds_of_jacobian); a bound B
  // of |W v| bounds each component |v_i| by B / weight_i.
  std::vector<double> weight;
  mag_value rsup, jmax, mu_plus, c, R_cap, psup;
  detail::breakpoint_term breakpoints;  // the windows that touch a or b (detail/breakpoint_term.hpp)
  std::vector<mag_value> fabs;  // |F_i| over the tube, whichever formula set applies
  std::size_t set = 0;
  detail::ball_linear_flow flow;
  // Filled in order by ball_certifier::advance, for the rows: |e(a)|, R, the box at a.
  mag_value rho_a, R, R_plain;  // |W e(a)|; |W e| <= R and |e|_2 <= R_plain on the segment
  std::unique_ptr<detail::ball_lohner_box> box_at_a;
  // The times of the rows to come (exact, increasing), if known: prepare() evaluates the parts of
  // those in [a, b] while the segment's models are in the cache (a row that ran after the
  // preparation of other segments took a quarter more time).
  std::shared_ptr<const std::vector<ball>> row_times;

 private:
  template <scalar T, std::size_t Dim>
  void load(const chebyshev_segment<T, Dim>& seg);
  void polynomial();
  void field_and_residual();
  void bounds_of_jacobian();
  void residual_sup();
  void tube_bounds();
  void row_models();

  detail::ball_node_transform transform_;
  arb_mat_t coefficients_;
  std::vector<ball> X0_;
  detail::weighted_jacobian_bounds jacobian_bounds_;
  std::vector<ball> tube_;  // tube_bounds' box
  // field_and_residual's jets (the state along P, the field), kept so that their models' storage
  // serves every segment.
  std::vector<detail::series_jet> x_, F_;
  detail::integral_weights weights_;  // hl / (2k), shared by the components' residuals
  slong residual_span_ = 0;            // r's length before F's tail went into its remainder
  std::vector<ball_row_part> rows_;    // the first row_count_ hold the rows in [a, b]
  std::size_t row_count_ = 0;
  static constexpr std::size_t max_prepared_rows = 64;  // beyond, a row is evaluated when it runs
  void prepare_rows();

 public:
  ~ball_segment_check() { arb_mat_clear(coefficients_); }
  ball_segment_check(const ball_segment_check&) = delete;
  ball_segment_check& operator=(const ball_segment_check&) = delete;
};

inline ball_segment_check::ball_segment_check(const certification_problem& p,
                                              const detail::ball_node_transform& transform)
    : problem(&p), D(p.dimension), n1(transform.nodes()), start(D), end(D), P(D), r(D), J(D * D), r1(D), r_row(D), u_row(D),
      weight(D, 1.0), breakpoints(D), flow(D), transform_(transform), X0_(D) {
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
  if (Dim != D || seg.values.size() != n1) throw std::invalid_argument("ball_segment_check: the segment's shape differs");
  row_count_ = 0;  // a reused check's rows belong to its last segment, even if this one fails
  load(seg);
  // 1. P's coefficients.
  polynomial();
  // 2. The field along P with its Jacobian, and the residual.
  field_and_residual();
  // 3. Bounds over the segment and the tube, in the weighted norm.
  bounds_of_jacobian();
  residual_sup();
  tube_bounds();
  breakpoints.compute(*this);
  // 4. Phi and u. (J's models keep their storage for the next segment's field.)
  flow.load_jacobian_in_place(J, weight);
  const double jh = mag_get_d(jmax.m) * arf_get_d(arb_midref(h.get()), ARF_RND_UP);
  if (!flow.variational(hl, jh)) fail(outcome_kind::certify_non_finite);
  if (!flow.integral_term(r, hl, residual_span_)) fail(outcome_kind::certify_non_finite);
  row_models();
  prepare_rows();
}

inline void ball_segment_check::prepare_rows() {
  if (!row_times) return;
  const auto below = [](const ball& t, const ball& x) { return arf_cmp(arb_midref(t.get()), arb_midref(x.get())) < 0; };
  auto t = std::lower_bound(row_times->begin(), row_times->end(), a, below);
  for (; t != row_times->end() && !below(b, *t) && row_count_ < max_prepared_rows; ++t) {
    if (row_count_ == rows_.size()) rows_.emplace_back();
    evaluate_row(rows_[row_count_++], *t);
  }
}

inline const ball_row_part* ball_segment_check::prepared_row(const ball& tau) const {
  for (std::size_t k = 0; k < row_count_; ++k)
    if (arf_equal(arb_midref(rows_[k].tau.get()), arb_midref(tau.get()))) return &rows_[k];
  return nullptr;
}

inline void ball_segment_check::evaluate_row(ball_row_part& out, const ball& tau) const {
  const slong prec = problem->prec;
  ball s;
  arb_set(out.tau.get(), tau.get());
  arb_sub(s.get(), tau.get(), a.get(), prec);
  arb_get_mag(out.dt.m, s.get());
  arb_div(s.get(), s.get(), hl.get(), prec);
  arb_sub_ui(s.get(), s.get(), 1, prec);
  slong n = flow.phi_length(), np = 1;
  for (std::size_t i = 0; i < D; ++i) {
    n = std::max({n, r_row[i].length, u_row[i].length});
    np = std::max(np, P[i].length());
  }
  // The tables are the thread's, kept from row to row. The error's table takes P's values rounded,
  // and runs its own recurrence only beyond P's degree: tighter than the recurrence at 64 bits,
  // whose widths grow like 2.4^k 2^-64 (the mpfr:256 runs' largest radii went down by a fifth),
  // and cheaper.
  thread_local detail::chebyshev_values Ts, Tp;
  Tp.assign(np, s, prec);
  Ts.assign_rounded(n, s, Tp, row_error_prec);
  flow.Phi_at(Ts, out.Phi, row_error_prec);
  out.r.resize(D);
  out.u.resize(D);
  out.P.resize(D);
  for (std::size_t i = 0; i < D; ++i) {
    detail::evaluate_head(out.r[i], r[i], r_row[i].length, r_row[i].tail.m, Ts, row_error_prec);
    detail::evaluate_head(out.u[i], flow.u()[i], u_row[i].length, u_row[i].tail.m, Ts, row_error_prec);
    detail::evaluate(out.P[i], P[i], Tp, prec);
  }
}

// A row evaluates e's parts r(s) and u_num(s) from their models. Their coefficients fall off fast
// past P's degree (the residual's tail is that of F(P) at twice the degree); a row sums only
// those before a tail of at most 2^-(prec - 28) sup |P| each, and adds the tails as error: a row's
// radius moves by at most 2^-37 of the state's last bit (in quad, 2^-150 sup |P|), and its sums
// are shorter by a third or more.
inline void ball_segment_check::row_models() {
  mag_value level;
  mag_mul_2exp_si(level.m, psup.m, -(problem->prec - 28));
  for (std::size_t i = 0; i < D; ++i) {
    r_row[i].length = detail::length_above(r[i], level.m, r_row[i].tail.m);
    u_row[i].length = detail::length_above(flow.u()[i], level.m, u_row[i].tail.m);
  }
}

// The segment's ends and the stored node values, which define P exactly.
template <scalar T, std::size_t Dim>
void ball_segment_check::load(const chebyshev_segment<T, Dim>& seg) {
  const slong prec = problem->prec;
  set_exact(a, seg.tau_begin);
  set_exact(hl, seg.half_length);
  arb_mul_2exp_si(h.get(), hl.get(), 1);
  arb_add(b.get(), a.get(), h.get(), prec);
  ball lo, v;
  for (std::size_t i = 0; i < D; ++i) {
    set_exact(X0_[i], seg.base[i]);
    set_exact(lo, seg.base_lo[i]);
    arb_add(X0_[i].get(), X0_[i].get(), lo.get(), prec);
    for (std::size_t j = 0; j < n1; ++j) {
      set_exact(v, seg.values[j][i]);
      if (!arb_is_finite(v.get())) fail(outcome_kind::certify_non_finite);
      arb_set(transform_.value(j, i), v.get());
    }
    arb_add(start[i].get(), X0_[i].get(), transform_.value(0, i), prec);
    arb_add(end[i].get(), X0_[i].get(), transform_.value(n1 - 1, i), prec);
  }
  if (!arb_is_finite(a.get()) || !arb_is_finite(hl.get())) fail(outcome_kind::certify_non_finite);
}

inline void ball_segment_check::polynomial() {
  const slong prec = problem->prec;
  transform_.apply(coefficients_);
  for (std::size_t i = 0; i < D; ++i) {
    P[i].resize(static_cast<slong>(n1));
    mag_zero(P[i].remainder());
    for (std::size_t k = 0; k < n1; ++k)  // swapped: coefficients_ is scratch for the next segment
      arb_swap(P[i].coeff(static_cast<slong>(k)), arb_mat_entry(coefficients_, static_cast<slong>(k), static_cast<slong>(i)));
    arb_add(P[i].coeff(0), P[i].coeff(0), X0_[i].get(), prec);
  }
  mag_value m;
  mag_one(psup.m);
  for (const detail::chebyshev_model& p : P) {
    detail::sup_bound(m.m, p);
    mag_max(psup.m, psup.m, m.m);
  }
}

// F along P (its Jacobian into J), r = P(-1) + hl int F(P) - P and r(1).
inline void ball_segment_check::field_and_residual() {
  const slong prec = problem->prec;
  std::vector<detail::series_jet>& F = F_;
  try {
    set = formula_set(*problem, a, b);
    const detail::series_algebra alg(prec, D);
    detail::chebyshev_model t(2);
    arb_add(t.coeff(0), a.get(), hl.get(), prec);
    arb_set(t.coeff(1), hl.get());
    x_.resize(D);
    for (std::size_t k = 0; k < D; ++k) alg.set_variable(x_[k], P[k], k);
    field(*problem, set, alg, alg.independent(std::move(t)), x_, F);
  } catch (const std::domain_error& e) {
    fail(outcome_kind::certify_formula, 0, e.what());
  }
  // F's coefficients fall off past P's degree as fast as P's do (a product's tail reaches down to
  // the square of P's last coefficient). The trailing ones whose magnitudes sum to at most
  // 2^-(prec - 27) sup |P| / hl go into F's remainder, which adds at most twice hl times that to
  // r's: 2^-(prec - 28) sup |P|, the level at which the rows cut r (row_models()). r, u and their
  // bounds are then a third shorter on a quadratic field (the paper scene: 84 coefficients to
  // about 52, and 4% fewer instructions in all; no row's radius moved by 1%).
  mag_value level, hl_low;
  arb_get_mag_lower(hl_low.m, hl.get());
  mag_mul_2exp_si(level.m, psup.m, -(prec - 27));
  mag_div(level.m, level.m, hl_low.m);
  residual_span_ = 0;
  for (std::size_t i = 0; i < D; ++i) {
    residual_span_ = std::max(residual_span_, F[i].f.length() + 1);
    detail::truncate_below(F[i].f, level.m);
  }
  slong n = 0;
  for (std::size_t i = 0; i < D; ++i) n = std::max(n, F[i].f.length());
  weights_.set(hl, n, prec);
  for (std::size_t i = 0; i < D; ++i) {
    detail::picard_residual_model(r[i], r1[i], F[i].f, hl, weights_, ball(), P[i], prec);  // r(-1) = 0
    for (std::size_t k = 0; k < D; ++k) J[i * D + k].swap(F[i].d[k]);  // F's jets take J's old storage
  }
}

// 3. The bounds of J in the weighted norm (detail/weighted_jacobian_bounds.hpp).
inline void ball_segment_check::bounds_of_jacobian() {
  if (!jacobian_bounds_.compute(J, D, problem->prec, weight, jmax.m, mu_plus.m)) fail(outcome_kind::certify_non_finite);
}

// sup |W r| over the segment.
inline void ball_segment_check::residual_sup() {
  mag_value s;
  mag_zero(rsup.m);
  for (std::size_t i = 0; i < D; ++i) {
    detail::sup_bound(s.m, r[i]);
    mag_mul_2exp_si(s.m, s.m, std::ilogb(weight[i]));
    mag_addmul(rsup.m, s.m, s.m);
  }
  mag_sqrt(rsup.m, rsup.m);
  if (!mag_is_finite(rsup.m)) fail(outcome_kind::certify_non_finite);
}

// The tube |y - P| <= R_cap with R_cap = 2^-20 max(1, sup |P|), where the box would fail the
// growth check anyway: c and |F| over it (the largest |F| over every formula set, for rows moved
// across a breakpoint).
inline void ball_segment_check::tube_bounds() {
  const slong prec = problem->prec;
  mag_mul_2exp_si(R_cap.m, psup.m, -20);
  tube_.resize(D);
  for (std::size_t i = 0; i < D; ++i) {
    detail::range_of(tube_[i], P[i]);
    arb_add_error_mag(tube_[i].get(), R_cap.m);
  }
  ball t;
  arb_union(t.get(), a.get(), b.get(), prec);
  try {
    box_bounds(*problem, set, t, tube_, weight, c.m, fabs);
    for (std::size_t other = 0; other < problem->sets.size(); ++other) {
      if (other == set) continue;
      mag_value c_other;
      std::vector<mag_value> f_other;
      box_bounds(*problem, other, t, tube_, weight, c_other.m, f_other);
      for (std::size_t i = 0; i < D; ++i) mag_max(fabs[i].m, fabs[i].m, f_other[i].m);
    }
  } catch (const std::domain_error& e) {
    fail(outcome_kind::certify_formula, 0, e.what());
  }
  if (!mag_is_finite(c.m)) fail(outcome_kind::certify_non_finite);
  for (const mag_value& f : fabs)
    if (!mag_is_finite(f.m)) fail(outcome_kind::certify_non_finite);
}

class ball_certifier {
 public:
  using check = ball_segment_check;

  // `problem`: the exact problem (certification_problem.hpp); `degree`: the reference's N.
  ball_certifier(certification_problem problem, std::size_t degree)
      : problem_(std::make_shared<const certification_problem>(std::move(problem))),
        transform_(problem_->prec, degree, problem_->dimension), box_(problem_->dimension, error_prec),
        prev_end_(problem_->dimension), e_(problem_->dimension), w_(problem_->dimension),
        plain_(problem_->dimension, 1.0) {}

  const certification_problem& problem() const { return *problem_; }

  // An empty check (safe from any thread: it only reads the problem).
  std::unique_ptr<ball_segment_check> make_segment() const {
    auto c = std::make_unique<ball_segment_check>(*problem_, transform_);
    c->row_times = row_times_;
    return c;
  }
  // The times of the rows to come (exact balls, increasing), before the first check is made.
  void expect_rows(std::shared_ptr<const std::vector<ball>> taus) { row_times_ = std::move(taus); }
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
  std::shared_ptr<const std::vector<ball>> row_times_;
  std::vector<ball> prev_end_;
  ball prev_b_;
  bool started_ = false;
  // advance's scratch, kept between segments: e(a), the signed part at b, the plain norm's weights.
  std::vector<ball> e_, w_;
  std::vector<mag_value> ball_b_;
  std::vector<double> plain_;

  void error_at_a(ball_segment_check& c);
  void a_priori_bound(ball_segment_check& c) const;
};

namespace detail {
// A bound B of |W v|_2 as bounds of each component: |v_i| <= B / w_i.
inline void per_component(const mag_value& B, const std::vector<double>& weight, std::vector<mag_value>& out) {
  out.resize(weight.size());
  for (std::size_t i = 0; i < weight.size(); ++i) mag_mul_2exp_si(out[i].m, B.m, -std::ilogb(weight[i]));
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

inline void ball_segment_check::error_ball(const mag_t dt, mag_t out) const {
  mag_value expo, factor, t;
  detail::growth_factors(mu_plus.m, jmax.m, dt, expo.m, factor.m);
  mag_mul(out, flow.phi_residual(), factor.m);
  mag_mul(out, out, rho_a.m);
  mag_mul(t.m, flow.u_residual(), factor.m);
  mag_add(out, out, t.m);
  mag_mul(t.m, R.m, R.m);
  mag_mul(t.m, t.m, c.m);
  mag_mul(t.m, t.m, dt);
  mag_mul(t.m, t.m, expo.m);
  mag_add(out, out, t.m);
}

inline std::unique_ptr<ball_segment_check> ball_certifier::advance(std::unique_ptr<ball_segment_check> prepared) {
  ball_segment_check& c = *prepared;
  const std::size_t D = problem_->dimension;
  error_at_a(c);
  a_priori_bound(c);
  // The box at b: Phi(b, a) e(a) + r(b) + u(b) + [the ball at b]. (A window at b enters at the
  // next segment's join, whole.)
  mag_value hm, ball_b;
  arb_get_mag(hm.m, c.h.get());
  c.error_ball(hm.m, ball_b.m);
  for (std::size_t i = 0; i < D; ++i) arb_add(w_[i].get(), c.r1[i].get(), c.flow.u1()[i].get(), problem_->prec);
  detail::per_component(ball_b, c.weight, ball_b_);
  if (!box_.step(c.flow.Phi1(), w_, ball_b_)) c.fail(outcome_kind::certify_non_finite);
  // Growth: a box beyond 2^-20 of the state is of no use to anyone.
  mag_value size;
  box_.norm(size.m, plain_);
  if (!mag_is_finite(size.m)) c.fail(outcome_kind::certify_non_finite);
  if (mag_cmp(size.m, c.R_cap.m) > 0) c.fail(outcome_kind::certify_growth, mag_get_d(size.m) / mag_get_d(c.psup.m));
  for (std::size_t i = 0; i < D; ++i) prev_end_[i] = c.end[i];
  prev_b_ = c.b;
  started_ = true;
  std::swap(current_, prepared);
  return prepared;
}

// e(a): the scene's exact initial state less P(a), or the previous segment's box plus the jump
// between the two polynomials at the join; and a breakpoint window there (breakpoint_term). The
// box at a and |W e(a)| into the check.
inline void ball_certifier::error_at_a(ball_segment_check& c) {
  const slong prec = problem_->prec;
  for (std::size_t i = 0; i < problem_->dimension; ++i) {
    if (started_)
      arb_sub(e_[i].get(), prev_end_[i].get(), c.start[i].get(), prec);
    else
      arb_sub(e_[i].get(), problem_->initial[i].get(), c.start[i].get(), prec);
    arb_add(e_[i].get(), e_[i].get(), c.breakpoints.jump_a[i].get(), prec);
  }
  if (started_) {
    if (!arb_equal(prev_b_.get(), c.a.get())) c.fail(outcome_kind::certify_segment_gap);
    box_.join(e_);
  } else {
    box_.start(e_);
  }
  if (!c.box_at_a) c.box_at_a = std::make_unique<detail::ball_lohner_box>(box_);
  else *c.box_at_a = box_;
  box_.norm(c.rho_a.m, c.weight);
}

// The a-priori bound, in the weighted norm |W .| of the segment. z = e - r solves
// z' = J z + J r + N(e) (+ the breakpoint term), z(a) = e(a), so while |e| <= R,
// |z| <= exp(mu+ h) (|e(a)| + omega + h (jmax sup|r| + c R^2)) (the logarithmic norm's comparison
// theorem) and |e| <= |z| + sup|r|. With R = 2 (exp(mu+ h) (|e(a)| + omega + h jmax sup|r|) +
// sup|r|), that is below R when exp(mu+ h) h c R < 1/2, and |e| never reaches R (continuity from
// |e(a)| < R). Into c.R, and c.R_plain >= |e|_2.
inline void ball_certifier::a_priori_bound(ball_segment_check& c) const {
  mag_value R, hm, expo, factor, t, omega;
  arb_get_mag(hm.m, c.h.get());
  detail::growth_factors(c.mu_plus.m, c.jmax.m, hm.m, expo.m, factor.m);
  mag_mul(R.m, c.jmax.m, c.rsup.m);
  mag_mul(R.m, R.m, hm.m);
  mag_add(R.m, R.m, c.rho_a.m);
  for (std::size_t i = 0; i < problem_->dimension; ++i) {
    mag_mul_2exp_si(t.m, c.breakpoints.omega_b[i].m, std::ilogb(c.weight[i]));
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
  const int min_w = std::ilogb(*std::min_element(c.weight.begin(), c.weight.end()));
  mag_value half_cap;
  mag_mul_2exp_si(half_cap.m, c.R_cap.m, -1 + min_w);
  if (!(mag_cmp_2exp_si(t.m, 0) < 0) || mag_cmp(R.m, half_cap.m) > 0) c.fail(outcome_kind::certify_a_priori);
  mag_set(c.R.m, R.m);
  mag_mul_2exp_si(c.R_plain.m, R.m, -min_w);
}

template <scalar T>
ball_row ball_certifier::enclose(const T& tau) const {
  const ball_segment_check& c = *current_;
  const std::size_t D = problem_->dimension;
  const slong prec = problem_->prec;
  ball tb;
  set_exact(tb, tau);
  thread_local ball_row_part evaluated;  // where the segment did not prepare this row
  const ball_row_part* part = c.prepared_row(tb);
  if (part == nullptr) {
    c.evaluate_row(evaluated, tb);
    part = &evaluated;
  }
  // e(tau) in Phi(tau, a) B x + r(tau) + u(tau) + ball(dt), at the error's precision; P(tau) at
  // the problem's.
  std::vector<ball> e;
  c.box_at_a->image(part->Phi, e, row_error_prec);
  mag_value rowball;
  c.error_ball(part->dt.m, rowball.m);
  ball_row out;
  out.y.resize(D);
  std::vector<mag_value> radius;
  detail::per_component(rowball, c.weight, radius);
  for (std::size_t i = 0; i < D; ++i) {
    arb_add(e[i].get(), e[i].get(), part->r[i].get(), row_error_prec);
    arb_add(e[i].get(), e[i].get(), part->u[i].get(), row_error_prec);
    arb_add_error_mag(e[i].get(), radius[i].m);
    for (const detail::breakpoint_term::touching_window& w : c.breakpoints.windows)
      if (arb_overlaps(w.hull.get(), tb.get())) arb_add_error_mag(e[i].get(), w.bound[i].m);
    arb_add(out.y[i].get(), part->P[i].get(), e[i].get(), prec);
  }
  out.rate = c.fabs;
  mag_sub_lower(out.reach.m, c.R_cap.m, c.R_plain.m);
  return out;
}

}  // namespace eulervop

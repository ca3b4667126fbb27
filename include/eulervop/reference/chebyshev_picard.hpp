// Chebyshev-Picard reference integrator for Euler's equations (Eq. 5, or Eq. 1 in its direct
// form: model/euler_problem.hpp), with dense output.
//
// Each segment [tau_a, tau_a + L] carries the degree-N interpolant of y' at the N+1
// Chebyshev-Gauss-Lobatto nodes; its exact integral gives y at the nodes (the Picard map,
// Clenshaw & Norton 1963; Bai & Junkins 2011). The fixed point is reached by mixed precision
// defect correction (docs/design.md section 3.2):
//   1. the residual of the Picard map, r = x0 + (L/2) S f(X) - X, is computed in T
//      (detail/picard_residuals.hpp);
//   2. the correction delta solves delta = r + (L/2) S [f(X + delta) - f(X)] in double. Eqs. 1
//      and 5 are quadratic, so f(X + delta) - f(X) = J(X) delta + f_2(delta) exactly for a torque
//      that does not depend on the state, and the double solve is a Gauss-Seidel sweep over the
//      nodes on that small correction (detail/picard_correction.hpp), to no more accuracy than
//      the residual it corrects needs;
//   3. X += delta in T.
// Step 2 is accurate to double precision relative to delta, so each pass through step 1 gains
// about 15 digits: from a warm start (detail/warm_start.hpp), a residual in double, one in
// double-double and one in T per segment for quad (MPFR at B bits: about B/50 more), instead of
// the ~30 Picard sweeps in T of the cold-start loop. Where the increment is exact, the
// correction of a residual far below 1e-16 leaves one at its own rounding, and the segment ends
// without a residual to confirm it (settled_by_correction). No operation in T per node happens
// before the residual in T when Euler's equations have a double-double form (euler_field.hpp):
// the narrow passes then keep the iterate in double-double, and a torque of time is evaluated at
// the nodes once per segment.
//
// Segment length: from the geometric decay of the Chebyshev coefficients of the solution (the
// Bernstein-ellipse rate scales with L), fitted above the rounding floor, so the predicted
// truncation term stays below the tolerance (detail/tail_estimator.hpp, length_control.hpp).
// Segment states are accumulated with TwoSum compensation, so rounding does not grow with the
// number of segments.
//
// The problem is a template parameter (model/problem.hpp): its torque's traits choose the paths
// at compile time. A torque of time is evaluated at the nodes' times; a torque of the state
// enters the correction through its Jacobian and turns the MPFR residual updates off. A torque
// of the attitude makes the rates and q one problem of 7 states (model/coupled_problem.hpp),
// solved the same way, with the whole Jacobian in the correction (detail/coupled_field.hpp).
#pragma once

#include <eulervop/core/error_free.hpp>
#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/core/outcome.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/reference/dense_trajectory.hpp>
#include <eulervop/reference/detail/length_control.hpp>
#include <eulervop/reference/detail/picard_field.hpp>
#include <eulervop/reference/detail/picard_correction.hpp>
#include <eulervop/reference/detail/picard_matrices.hpp>
#include <eulervop/reference/detail/picard_residuals.hpp>
#include <eulervop/reference/detail/picard_workspace.hpp>
#include <eulervop/reference/detail/tail_estimator.hpp>
#include <eulervop/reference/detail/warm_start.hpp>
#include <eulervop/reference/segment.hpp>
#include <eulervop/reference/segment_sampler.hpp>
#include <eulervop/reference/settings.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace eulervop {

// The integrator and its workspace for problems of type P. One instance per thread; run() may be
// called many times.
template <picard_problem P>
class chebyshev_picard {
 public:
  using T = typename P::value_type;
  static constexpr std::size_t D = P::dimension;
  using segment_type = chebyshev_segment<T, D>;

  explicit chebyshev_picard(const picard_settings& settings = {})
      : settings_(settings),
        N_(settings.degree ? settings.degree : detail::default_degree(detail::effective_bits<T>(settings))),
        n1_(N_ + 1),
        matrices_(N_, detail::effective_bits<T>(settings)),
        eps_log_(detail::log_abs(epsilon<T>())),
        // A tolerance below the rounding of T cannot be met: the run holds itself to epsilon, and
        // its statistics say so (picard_stats::tolerance).
        tol_log_(settings.tolerance > 0 ? std::max(std::log(settings.tolerance), eps_log_) : eps_log_),
        // Each segment's truncation is held to a sixteenth of the tolerance (never below
        // epsilon), so that the error accumulated over thousands of segments stays near the
        // tolerance: with the tolerance itself, mpfr:256 at 1e-60 ended 6.6e-60 from the truth
        // on the paper scene.
        tail_(N_, eps_log_, std::max(tol_log_ - std::log(16.0), eps_log_)),
        warm_start_(N_),
        work_(n1_) {}

  unsigned degree() const { return static_cast<unsigned>(N_); }

  // Integrates from problem.tau0 to tau_end (> tau0) segment by segment: each solved from the
  // previous one's extrapolation (attempt_segment), shortened and retried until it passes, then
  // handed to `sink` (accept_segment). Only the latest segment is kept. `check`, if set, sees
  // each segment that passed before it is accepted, and may refuse it: the segment is then
  // shortened and solved again (the attitude cascade refuses a segment too long for q). Throws
  // numerical_failure when the segments cannot pass.
  void run_segments(const P& problem, const T& tau_end, const segment_sink<T, D>& sink,
                    const progress_callback& progress = {}, picard_stats* stats = nullptr,
                    const segment_check<T, D>& check = {});

  // The same, keeping every segment: the dense output on the whole span.
  dense_trajectory<T, D> run(const P& problem, const T& tau_end, const progress_callback& progress = {},
                             picard_stats* stats = nullptr) {
    std::vector<segment_type> segs;
    run_segments(
        problem, tau_end, [&](const segment_type& seg, const std::vector<T>&) { segs.push_back(seg); }, progress,
        stats);
    return dense_trajectory<T, D>(std::move(segs), matrices_.basis.nodes);
  }

 private:
  using state = std::array<T, D>;
  // Where the next segment starts: y = x + x_lo (TwoSum compensation) at tau.
  struct origin {
    state x, x_lo;
    T tau;
  };
  struct solve_result {
    outcome failure;       // success when the iteration converged
    double scale_log = 0;  // log of the state scale max |y| on the segment
    bool settled = false;  // ended by a correction: f at the nodes is F + g (settled_by_correction)
  };

  static double to_d(const T& x) { return static_cast<double>(x); }
  static bool isfinite_(const T& x) {
    using std::isfinite;
    using boost::multiprecision::isfinite;
    return isfinite(x);
  }
  static double log_of(double r) { return r > 0 ? std::log(r) : -std::numeric_limits<double>::infinity(); }

  // One attempt at the segment of the current length from `at`: true when it was accepted (and
  // `at` moved to its end), false when it was refused and the length shortened. Throws
  // numerical_failure when the length cannot shorten any more.
  // A segment ends at the next breakpoint of the torque, if it would pass one, or at tau_end.
  bool next_segment(origin& at, const T& tau_end, detail::segment_length_control& length, bool have_previous,
                    bool& last, picard_stats& st) {
    const bool to_break = next_break_ < breaks_.size();
    bool reached = false;
    const T tau_b = segment_end(at.tau, to_break ? breaks_[next_break_] : tau_end, length.length(), reached);
    last = reached && !to_break;
    work_.field.pin_at(at.tau);
    const T hl = (tau_b - at.tau) / 2;
    warm_start_(matrices_, have_previous ? &segment_ : nullptr, hl, work_.warm);
    outcome verdict = attempt_segment(at, hl, to_d(tau_b - at.tau), length, st);
    if (verdict.ok() && check_) {
      fill_segment(candidate_, at, tau_b, hl);
      if (!(*check_)(candidate_, matrices_.basis.nodes)) {
        length.failed(to_d(tau_b - at.tau));
        verdict = {outcome_kind::segment_collapse};
      }
    }
    if (!verdict.ok()) {
      ++st.rejected;
      verdict.tau = to_d(at.tau);
      if (!length.retry(*verdict.tau)) throw numerical_failure(verdict);
      return false;
    }
    accept_segment(at, tau_b, hl);
    if (reached && to_break) ++next_break_;
    return true;
  }

  // The end of the segment of length L from tau, in T; a segment that would reach `stop` (the end
  // of the span or a breakpoint) ends exactly there (`reached`), also when it would leave a
  // sliver of less than L / 1000.
  static T segment_end(const T& tau, const T& stop, double L, bool& reached) {
    const T tau_b = tau + T(L);
    reached = !(tau_b < stop) || to_d(stop - tau_b) < 1e-3 * L;
    return reached ? stop : tau_b;
  }

  // The torque's breakpoints inside (tau0, tau_end): every segment ends on the ones it meets, so
  // that no segment interpolates across a change of formula (docs/design.md, "Breakpoints").
  void set_breakpoints(const P& problem, const T& tau_end) {
    breaks_.clear();
    next_break_ = 0;
    if constexpr (piecewise_torque<typename P::torque_type>)
      for (const T& b : problem.torque.breakpoints())
        if (b > problem.tau0 && b < tau_end) breaks_.push_back(b);
  }

  // The first segment length: from the settings, or half a turn of the fastest rate in sight
  // (the field's first_rate).
  double first_length(const origin& at) const {
    if (settings_.initial_step > 0) return settings_.initial_step;
    std::array<double, D> x0;
    for (std::size_t i = 0; i < D; ++i) x0[i] = to_d(at.x[i]);
    const double rate = work_.field.first_rate(to_d(at.tau), x0);
    return rate > 0 ? 0.5 / rate : 1.0;
  }

  // Solves the segment of half length hl from `at` (warm start in work_.warm) and judges its
  // length: success to accept it, otherwise why it is refused, as the failure to report should
  // the segments shrink to nothing (no_convergence, or segment_collapse for a tail too large).
  outcome attempt_segment(const origin& at, const T& hl, double length_used, detail::segment_length_control& length,
                          picard_stats& st) {
    set_node_times(at.tau, hl);
    const solve_result res = solve_segment(at.x, at.x_lo, hl, st);
    if (!res.failure.ok()) {
      length.failed(length_used);
      return {.kind = outcome_kind::no_convergence, .cause = res.failure.kind, .value = res.failure.value,
              .count = res.failure.count};
    }
    if (length.converged(length_used,
                         tail_.excess_log(matrices_, work_.F, hl, res.scale_log, res.settled ? &work_.g : nullptr)))
      return {};
    return {outcome_kind::segment_collapse};
  }

  // t_j = tau + hl (s_j + 1) at the nodes, for a torque of time.
  void set_node_times(const T& tau, const T& hl) {
    if constexpr (torque_traits<typename P::torque_type>::depends_on_time)
      for (std::size_t j = 0; j < n1_; ++j) {
        work_.t[j] = tau + hl * matrices_.nodes_plus_one[j];
        work_.t_d[j] = to_d(work_.t[j]);
      }
    if constexpr (torque_traits<typename P::torque_type>::depends_on_time) {
      T mid, mid_lo, scratch;  // the midpoint tau + hl exactly, as a sum of two
      two_sum(tau, hl, mid, mid_lo, scratch);
      work_.field.set_node_times(work_.t, mid, mid_lo, hl);
    }
  }

  // The solved segment [at.tau, tau_b] (increments in work_.Yn), stored in segment_ (already
  // filled in candidate_ when a check saw it); `at` moves to its end, the last increment added
  // with compensated summation (TwoSum).
  void accept_segment(origin& at, const T& tau_b, const T& hl) {
    if (check_)
      std::swap(segment_, candidate_);
    else
      fill_segment(segment_, at, tau_b, hl);
    state x1, c1;
    for (std::size_t i = 0; i < D; ++i) {
      const T y = work_.Yn[i][N_] + at.x_lo[i];
      T bb;
      two_sum(at.x[i], y, x1[i], c1[i], bb);
      if (!isfinite_(x1[i])) throw numerical_failure({outcome_kind::segment_non_finite, to_d(tau_b)});
    }
    at.x = x1;
    at.x_lo = c1;
    at.tau = tau_b;
  }

  void fill_segment(segment_type& seg, const origin& at, const T& tau_b, const T& hl) const {
    seg.tau_begin = at.tau;
    seg.tau_end = tau_b;
    seg.half_length = hl;
    seg.base = at.x;
    seg.base_lo = at.x_lo;
    seg.values.resize(n1_);
    for (std::size_t j = 0; j < n1_; ++j)
      for (std::size_t i = 0; i < D; ++i) seg.values[j][i] = work_.Yn[i][j];
  }

  // Solves the collocation problem on one segment from the warm start. On success work_.Yn holds
  // the increments at the nodes and work_.F the derivative there.
  solve_result solve_segment(const state& x0, const state& c0, const T& hl, picard_stats& st) {
    const double hl_d = to_d(hl);
    double r_prev_log = std::numeric_limits<double>::infinity();
    if constexpr (!std::is_same_v<T, double>) {
      if (const outcome o = narrow_passes(x0, c0, hl, st, r_prev_log); !o.ok()) return {o};
    } else {
      for (std::size_t i = 0; i < D; ++i)
        for (std::size_t j = 0; j < n1_; ++j) work_.Yc[i][j] = work_.warm[i][j];
    }
    const std::size_t max_passes = 4 + significand_bits<T>() / 40;
    for (std::size_t pass = 1;; ++pass) {
      const double scale = detail::evaluate_nodes(work_, x0, c0);
      if (!std::isfinite(scale)) return {{outcome_kind::iterate_non_finite}};
      solve_result out;
      out.scale_log = std::log(std::max(scale, 1e-300));
      ++st.wide_residuals;
      // MPFR's first residual comes after double-double's, at about 2^-106 of the state, and its
      // correction (in double) reaches about 2^-159: products on three limbs (188 bits) resolve
      // that. It never ends the segment; the next residual, in full, decides.
      const bool first = pass == 1 && matrices_.has_first_residual_matrix();
      const double r_max = detail::wide_residual(matrices_, work_, hl, first);
      if (!std::isfinite(r_max)) return {{outcome_kind::residual_non_finite}};
      const double r_log = log_of(r_max);
      if (first) {
        r_prev_log = r_log;
        if (const outcome o = detail::solve_correction(matrices_, work_, hl_d, wide_floor(out.scale_log),
                                                       detail::correction_stop::predicted, st);
            !o.ok())
          return {o};
        detail::add_correction(work_);
        continue;
      }
      // A converged residual is corrected too where that settles the segment (and it is not
      // already below the correction's floor): the corrected iterate is within about 1e-16 |r|
      // of the collocation solution, the Picard image Yn only within about |r|, up to the
      // rounding floor of `converged`, and that adds up over thousands of segments.
      const bool done = converged(r_log, r_prev_log, out.scale_log);
      if (done && !(settles(r_max, out.scale_log) && r_max > wide_floor(out.scale_log))) return out;
      if (!done && (pass >= max_passes || (r_prev_log < std::numeric_limits<double>::infinity() &&
                                           r_log > r_prev_log - std::log(2.0))))
        return {{.kind = outcome_kind::residual_stalled, .value = r_max, .count = pass}};
      r_prev_log = r_log;
      if (const outcome o = detail::solve_correction(matrices_, work_, hl_d, wide_floor(out.scale_log),
                                                     detail::correction_stop::measured, st);
          !o.ok())
        return {o};
      if (settled_by_correction(r_max, out.scale_log, hl_d)) {  // Yc is not needed any more
        out.settled = true;
        return out;
      }
      detail::add_correction(work_);
      if (const auto done = refine_by_updates(hl, r_log, r_prev_log, out, st)) return *done;
    }
  }

  // For MPFR, residual updates (detail::update_residual) instead of full residuals while their
  // error, about 2^-100 of this residual, stays 2^-20 below the tolerance: that error repeats from
  // segment to segment (it is mostly the rounding of S to double-double), so it must stay far
  // below what one segment may contribute. A full residual in T when they stop decreasing. Only
  // for MPFR, where a full residual costs several double-double ones, and only where the
  // increment is exact (a torque that does not depend on the state). Returns the segment's
  // result when it is decided, nothing to go on with a full residual.
  std::optional<solve_result> refine_by_updates(const T& hl, double r_log, double& r_prev_log, const solve_result& out,
                                                picard_stats& st) {
    if constexpr (std::is_same_v<T, mpfr_real> && !torque_traits<typename P::torque_type>::depends_on_state) {
      const double update_floor_log = r_log - 100 * std::log(2.0);
      if (update_floor_log > tol_log_ + out.scale_log - 20 * std::log(2.0)) return std::nullopt;
      for (;;) {
        ++st.residual_updates;
        const double r_up = detail::update_residual(matrices_, work_, hl);
        if (!std::isfinite(r_up)) return solve_result{{outcome_kind::residual_non_finite}};
        const double r_up_log = log_of(r_up);
        if (converged(r_up_log, r_prev_log, out.scale_log)) return out;
        if (r_up_log > r_prev_log - std::log(2.0)) return std::nullopt;
        r_prev_log = r_up_log;
        if (const outcome o = detail::correct(matrices_, work_, r_up, to_d(hl), wide_floor(out.scale_log),
                                                     detail::correction_stop::measured, st); !o.ok())
          return solve_result{o};
        if (settled_by_correction(r_up, out.scale_log, to_d(hl))) {
          solve_result settled = out;
          settled.settled = true;
          return settled;
        }
      }
    }
    return std::nullopt;
  }

  // Where the increment f(X + delta) - f(X) is exact (euler_field.hpp: a torque that does not
  // read the state) and T is wider than double, the correction of a residual r in T (or of its
  // update, exact to 2^-100 of the last full one) leaves a residual of at most its own
  // error: the sweeps' stop (below wide_floor), and double's rounding of r, of the increments and
  // of the sums, about 1e-16 |r| each. When that is below wide_floor, a further residual in T
  // would only confirm convergence: the corrected iterate becomes the segment's values (Yn) and
  // the residual is not evaluated again. Otherwise false (a new residual decides). The tail
  // estimate then reads F + g, with g the increment the last sweep left (f(X + delta) - f(X) to
  // 1e-16 of itself), the derivative of the values it judges: F alone would carry an error of
  // about |r|, which a tolerance far below 1e-32 (MPFR) reads as a slow tail.
  bool settles(double r_max, double scale_log) const {
    if constexpr (!detail::field_of<P>::has_double_double_rhs || std::is_same_v<T, double>)
      return false;
    else
      return 64 * 0x1p-53 * r_max <= wide_floor(scale_log);
  }
  bool settled_by_correction(double r_max, double scale_log, double hl_d) {
    if (!settles(r_max, scale_log)) return false;
    // Yn += hl S g in double: the Picard image of the corrected iterate, to 1e-16 of |hl S g|,
    // about |r|. The image rather than the corrected iterate itself: its values are the integral
    // of one polynomial, which is what the certificate's residual bound measures.
    matrices_.double_integral(work_.g, work_.Sg);
    for (std::size_t i = 0; i < D; ++i)
      for (std::size_t j = 1; j < n1_; ++j) work_.add_double(work_.Yn[i][j], hl_d * work_.Sg[i][j]);
    return true;
  }

  // The accuracy a correction needs after a residual in double-double or T: 2^-20 of the
  // tolerance at the state's scale (log). Each segment's error adds to the run's: with a
  // sixteenth, a body spinning about one axis (k = 1e-6, increments a millionth of the state)
  // ended 1.7e-33 from its exact solution to tau = 1000 instead of 2e-34.
  double wide_floor(double scale_log) const { return std::exp(tol_log_ + scale_log) * 0x1p-20; }

  // Converged: residual within the tolerance or at the rounding level of one residual
  // evaluation (a sum of N+1 rounded terms: ~sqrt(N+1) eps), or stagnant near that floor.
  bool converged(double r_log, double r_prev_log, double scale_log) const {
    const double rounding_log = eps_log_ + std::log(4.0 * std::sqrt(double(n1_))) + scale_log;
    const double floor_log = eps_log_ + std::log(64.0 * n1_) + scale_log;
    return r_log <= std::max(tol_log_ + scale_log, rounding_log) ||
           (r_log <= floor_log && r_log > r_prev_log - std::log(16.0));
  }

  // For wide T, the passes before the first residual in T: one in double from the warm start and
  // one in double-double, each followed by its correction; they leave the iterate in Yc. Sets
  // r_log to the log of the last residual. Where the field has a double-double right-hand side,
  // the iterate stays in double-double until the end (Ydd), and these passes make no operation
  // in T per node.
  outcome narrow_passes(const state& x0, const state& c0, const T& hl, picard_stats& st, double& r_log) {
    constexpr bool in_double_double = detail::field_of<P>::has_double_double_rhs;
    const double hl_d = to_d(hl);
    load_warm_start();
    const double r_double = detail::double_residual(matrices_, work_, x0, c0, hl_d);
    double scale = 0, increments = 0;
    for (std::size_t i = 0; i < D; ++i)
      for (std::size_t j = 0; j < n1_; ++j) {
        scale = std::max(scale, std::abs(work_.Xd[i][j]));
        increments = std::max(increments, std::abs(work_.warm[i][j]));
      }
    // The residual in double errs by about double's rounding of the increments it integrates
    // (the warm start's; none from a cold start): no need to solve its correction any closer.
    const double floor_double = 0x1p-53 * increments, floor_wide = wide_floor(std::log(scale));
    double r_dd = 0;
    if constexpr (in_double_double) {
      if (!std::isfinite(r_double)) return {outcome_kind::residual_non_finite};
      if (const outcome o =
              detail::solve_correction(matrices_, work_, hl_d, floor_double, detail::correction_stop::predicted, st);
          !o.ok())
        return o;
      detail::add_correction_double_double(work_);
      r_dd = detail::double_double_residual(matrices_, work_, start_double_double(x0, c0), to_double_double(hl));
      if (!std::isfinite(r_dd)) return {outcome_kind::residual_non_finite};
      if (const outcome o =
              detail::solve_correction(matrices_, work_, hl_d, floor_wide, detail::correction_stop::predicted, st);
          !o.ok())
        return o;
      detail::add_correction_double_double(work_);
      for (std::size_t i = 0; i < D; ++i)
        for (std::size_t j = 0; j < n1_; ++j) {
          work_.Yc[i][j] = work_.Ydd_hi[i][j];
          work_.add_double(work_.Yc[i][j], work_.Ydd_lo[i][j]);
        }
    } else {
      if (const outcome o = detail::correct(matrices_, work_, r_double, hl_d, floor_double,
                                            detail::correction_stop::predicted, st);
          !o.ok())
        return o;
      r_dd = detail::double_double_residual(matrices_, work_, x0, c0, hl);
      if (const outcome o =
              detail::correct(matrices_, work_, r_dd, hl_d, floor_wide, detail::correction_stop::predicted, st);
          !o.ok())
        return o;
    }
    if (log_of(r_dd) > log_of(r_double) - std::log(2.0)) return {outcome_kind::residual_not_decreasing};
    r_log = log_of(r_dd);
    return {};
  }

  // The iterate of the narrow passes from the warm start: in double-double where the field has
  // a double-double right-hand side, else in T.
  void load_warm_start() {
    for (std::size_t i = 0; i < D; ++i)
      for (std::size_t j = 0; j < n1_; ++j) {
        if constexpr (detail::field_of<P>::has_double_double_rhs) {
          work_.Ydd_hi[i][j] = work_.warm[i][j];
          work_.Ydd_lo[i][j] = 0;
        } else {
          work_.Yc[i][j] = T(work_.warm[i][j]);
        }
      }
  }

  // x0 + c0 in double-double: the leading double of x0, then the rest of x0 and c0 summed in T.
  std::array<double_double, D> start_double_double(const state& x0, const state& c0) {
    std::array<double_double, D> x0dd;
    for (std::size_t i = 0; i < D; ++i) {
      x0dd[i].hi = to_d(x0[i]);
      work_.acc = x0[i];
      work_.acc -= x0dd[i].hi;
      work_.acc += c0[i];
      x0dd[i].lo = to_d(work_.acc);
    }
    return x0dd;
  }

  picard_settings settings_;
  std::size_t N_, n1_;  // the degree, and the number of nodes N + 1
  detail::picard_matrices<T> matrices_;
  double eps_log_, tol_log_;  // log epsilon of T; log of the relative tolerance
  detail::tail_estimator<T> tail_;
  detail::warm_start<T, D> warm_start_;
  detail::picard_workspace<P> work_;
  segment_type segment_;  // the latest accepted segment (the next one's warm start)
  segment_type candidate_;  // a segment before its check (only with a check)
  const segment_check<T, D>* check_ = nullptr;
  std::vector<T> breaks_;       // the torque's breakpoints in the span
  std::size_t next_break_ = 0;  // the first one not yet reached
};

// Out of the class, so that a unit that declares it extern (reference/integrate.hpp) compiles none
// of the segment loop the compiled kernels hold.
template <picard_problem P>
void chebyshev_picard<P>::run_segments(const P& problem, const T& tau_end, const segment_sink<T, D>& sink,
                                       const progress_callback& progress, picard_stats* stats,
                                       const segment_check<T, D>& check) {
  check_ = check ? &check : nullptr;
  picard_stats st;
  st.degree = static_cast<unsigned>(N_);
  st.tolerance = std::exp(tol_log_);
  work_.field = detail::field_of<P>(problem);
  if (!(tau_end > problem.initial_time()))
    throw std::invalid_argument("integrate_reference: tau_end must exceed tau0");
  set_breakpoints(problem, tau_end);
  origin at{problem.initial_state(), {}, problem.initial_time()};
  at.x_lo.fill(T(0));
  for (std::size_t i = 0; i < D; ++i)
    if (!isfinite_(at.x[i])) throw numerical_failure({outcome_kind::initial_non_finite, to_d(at.tau)});
  detail::segment_length_control length(first_length(at), N_);
  bool have_previous = false;
  std::size_t since_progress = 0;
  while (at.tau < tau_end) {
    bool last = false;
    if (!next_segment(at, tau_end, length, have_previous, last, st)) continue;
    have_previous = true;
    sink(segment_, matrices_.basis.nodes);
    if (++st.segments > settings_.max_segments)
      throw numerical_failure(
          {.kind = outcome_kind::segment_limit, .tau = to_d(at.tau), .count = settings_.max_segments});
    // Every few segments: a display redraws at most ten times a second anyway, and a call
    // costs far less than a segment.
    if (progress && (++since_progress >= 4 || last)) {
      progress(to_d(at.tau), st.segments);
      since_progress = 0;
    }
    length.accepted();
    if (last) break;
  }
  if (stats) *stats = st;
}

}  // namespace eulervop

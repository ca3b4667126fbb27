// Chebyshev-Picard reference integrator for Eq. 5 (or Eq. 1 in its direct form, euler_problem)
// with dense output.
//
// Each segment [tau_a, tau_a + L] carries the degree-N interpolant of Omega' at the N+1
// Chebyshev-Gauss-Lobatto nodes; its exact integral gives Omega at the nodes (the Picard map,
// Clenshaw & Norton 1963; Bai & Junkins 2011). The fixed point is reached by mixed precision
// defect correction (docs/design.md section 3.2):
//   1. the residual of the Picard map, r = x0 + (L/2) S f(X) - X, is computed in T;
//   2. the correction delta solves delta = r + (L/2) S [f(X + delta) - f(X)] in double. Eqs. 1
//      and 5 are quadratic, so f(X + delta) - f(X) = J(X) delta + f_2(delta) exactly, and the double
//      solve is a plain Picard sweep on that small correction;
//   3. X += delta in T.
// Step 2 is accurate to double precision relative to delta, so each pass through step 1 gains
// about 15 digits: from a warm start, quad needs three residuals in T per segment and MPFR at B
// bits about B/50 + 2, instead of the ~30 Picard sweeps in T of the cold-start loop.
//
// Segment length: from the geometric decay of the Chebyshev coefficients of the solution (the
// Bernstein-ellipse rate scales with L), fitted above the rounding floor, so the predicted
// truncation term stays below the tolerance. Segment states are accumulated with TwoSum
// compensation, so rounding does not grow with the number of segments.
#pragma once

#include <eulervop/reference/detail/chebyshev_basis.hpp>
#include <eulervop/reference/detail/double_double_matvec.hpp>
#include <eulervop/reference/detail/fixed_point_matvec.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/core/outcome.hpp>
#include <eulervop/core/scalar.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

namespace eulervop {

// Knobs of the reference integrator. Zero means "derive from the precision of T".
struct picard_settings {
  unsigned degree = 0;       // Chebyshev degree N (N+1 Gauss-Lobatto nodes per segment)
  double tolerance = 0;      // relative tolerance (truncation per segment: a sixteenth of it); 0: epsilon of T
  double initial_step = 0;   // first segment length in tau; 0: from the initial rotation rate
  std::size_t max_segments = 50'000'000;
};

// Counters of one integration, for reports and benchmarks.
struct picard_stats {
  unsigned degree = 0;
  double tolerance = 0;
  std::size_t segments = 0;        // accepted segments
  std::size_t rejected = 0;        // segments shrunk and retried
  std::size_t wide_residuals = 0;  // residual evaluations in T (each one matrix product in T)
  std::size_t residual_updates = 0;  // residuals updated in double-double after a correction
  std::size_t double_sweeps = 0;   // Picard sweeps of the double-precision correction
};

// One segment of the dense output: Omega(tau) = base + (base_lo + p(s)), where p is the
// polynomial through the increments `values` at the Chebyshev-Lobatto nodes s_j = -cos(j pi/N)
// and s = (tau - tau_begin) / half_length - 1 in [-1, 1]. base_lo is the TwoSum compensation.
template <scalar T>
struct chebyshev_segment {
  T tau_begin, tau_end, half_length;
  vec3<T> base, base_lo;
  std::vector<vec3<T>> values;  // Omega(tau_j) - Omega(tau_begin) at the N+1 nodes
};

// Omega(tau) on one segment (tau in [seg.tau_begin, seg.tau_end]), from its node values: by
// barycentric Lagrange interpolation (second form) on the Lobatto nodes, with weights (-1)^j,
// halved at the ends: backward stable for these nodes (Higham 2004, Berrut & Trefethen 2004) and
// O(N) per call. At a node, and at the segment's start, the stored value is returned exactly.
template <scalar T>
vec3<T> evaluate_segment(const chebyshev_segment<T>& seg, const std::vector<T>& nodes, const T& tau) {
  vec3<T> out;
  const std::size_t n1 = nodes.size();
  T s = (tau - seg.tau_begin) / seg.half_length - 1;
  if (s > 1) s = 1;
  std::size_t hit = n1;
  if (tau == seg.tau_begin) hit = 0;  // the segment's start is known exactly
  for (std::size_t j = 0; j < n1 && hit == n1; ++j)
    if (s == nodes[j]) hit = j;
  if (hit < n1) {
    for (int i = 0; i < 3; ++i) out[i] = seg.base[i] + (seg.base_lo[i] + seg.values[hit][i]);
    return out;
  }
  T den = 0;
  vec3<T> num{T(0), T(0), T(0)};
  for (std::size_t j = 0; j < n1; ++j) {
    T w = 1 / (s - nodes[j]);
    if (j % 2) w = -w;
    if (j == 0 || j + 1 == n1) w /= 2;
    den += w;
    for (int i = 0; i < 3; ++i) num[i] += w * seg.values[j][i];
  }
  for (int i = 0; i < 3; ++i) out[i] = seg.base[i] + (seg.base_lo[i] + num[i] / den);
  return out;
}

// The reference solution on [tau_begin, tau_end], evaluable anywhere in it to full precision.
// It keeps every segment, so its memory grows with the span; a caller who knows its sample
// times in advance can use segment_sampler instead, which keeps one.
template <scalar T>
class dense_trajectory {
 public:
  dense_trajectory() = default;
  dense_trajectory(std::vector<chebyshev_segment<T>> segs, std::vector<T> nodes)
      : segs_(std::move(segs)), nodes_(std::move(nodes)) {}

  const T& tau_begin() const { return segs_.front().tau_begin; }
  const T& tau_end() const { return segs_.back().tau_end; }
  std::size_t segments() const { return segs_.size(); }
  const std::vector<chebyshev_segment<T>>& segment_list() const { return segs_; }

  // Omega(tau), from the last segment whose start is <= tau. Throws std::out_of_range outside
  // [tau_begin, tau_end].
  vec3<T> operator()(const T& tau) const {
    if (segs_.empty() || !(tau >= tau_begin() && tau <= tau_end()))
      throw std::out_of_range("dense_trajectory: tau outside the integrated span");
    auto it = std::upper_bound(segs_.begin(), segs_.end(), tau,
                               [](const T& t, const chebyshev_segment<T>& s) { return t < s.tau_begin; });
    return evaluate_segment(*(it - 1), nodes_, tau);
  }

 private:
  std::vector<chebyshev_segment<T>> segs_;
  std::vector<T> nodes_;
};

// Receives each accepted segment in order, with the Lobatto nodes s_j of the run (the same for
// every segment). The segment is only valid during the call.
template <scalar T>
using segment_sink = std::function<void(const chebyshev_segment<T>& segment, const std::vector<T>& nodes)>;

// Evaluates the dense output at sample times given in advance, in non-decreasing order, as the
// segments arrive, keeping only the latest segment: memory does not grow with the span. Each
// sample comes from the same segment dense_trajectory would use (the last one starting at or
// before it), so the values are identical. `emit(index, tau, Omega)` receives them in order.
template <scalar T>
class segment_sampler {
 public:
  using emit_function = std::function<void(std::size_t index, const T& tau, const vec3<T>& Omega)>;

  segment_sampler(const std::vector<T>& taus, emit_function emit) : taus_(taus), emit_(std::move(emit)) {
    for (std::size_t i = 1; i < taus_.size(); ++i)
      if (taus_[i] < taus_[i - 1]) throw std::invalid_argument("segment_sampler: sample times must not decrease");
  }

  // The sink to pass to chebyshev_picard::run_segments.
  void operator()(const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
    if (!held_) {
      if (next_ < taus_.size() && taus_[next_] < seg.tau_begin)
        throw std::out_of_range("segment_sampler: a sample time precedes the integrated span");
      nodes_ = nodes;
      held_ = true;
    } else {
      emit_before(seg.tau_begin);
    }
    last_ = seg;
  }

  // After the run: the samples up to the end of the last segment. Throws std::out_of_range if a
  // sample lies beyond it.
  void finish() {
    if (!held_) throw std::logic_error("segment_sampler: no segment was integrated");
    for (; next_ < taus_.size() && taus_[next_] <= last_.tau_end; ++next_)
      emit_(next_, taus_[next_], evaluate_segment(last_, nodes_, taus_[next_]));
    if (next_ < taus_.size()) throw std::out_of_range("segment_sampler: a sample time lies beyond the integrated span");
  }

 private:
  void emit_before(const T& tau) {
    for (; next_ < taus_.size() && taus_[next_] < tau; ++next_)
      emit_(next_, taus_[next_], evaluate_segment(last_, nodes_, taus_[next_]));
  }

  const std::vector<T>& taus_;
  emit_function emit_;
  std::size_t next_ = 0;
  bool held_ = false;
  chebyshev_segment<T> last_;
  std::vector<T> nodes_;
};

// Progress callback: the tau reached so far.
using progress_callback = std::function<void(double tau_reached)>;

namespace detail {

// log|x| in double for any T, also where |x| underflows double (MPFR at thousands of bits).
template <scalar T>
double log_abs(const T& x) {
  using std::frexp;
  using std::abs;
  using std::log;
  if (x == 0) return -std::numeric_limits<double>::infinity();
  int e = 0;
  T m = frexp(T(abs(x)), &e);
  return std::log(static_cast<double>(m)) + e * 0.69314718055994531;
}

// Default Chebyshev degree: the truncation term of a segment is ~ rho^-N for a Bernstein ellipse
// rho; the cost per unit tau is ~ N^2 / L(rho), minimal near N ln(rho) = 1.9 N, hence
// N ~ digits * ln(10) / 1.9 ~ 1.2 digits (the constant was then tuned on the paper scene).
inline unsigned default_degree(unsigned bits) {
  const double digits = bits * 0.30102999566398120;
  return static_cast<unsigned>(std::clamp(std::lround(1.2 * digits), 12L, 600L));
}

// The segment length of the reference integrator (its step-size control). After a converged
// segment the length follows the tail estimate's excess over the tolerance: the terms decay like
// rho^-(N+1), so the length scales by exp(-excess / (N+1)), times a safety factor of 0.85 (0.8
// after a refusal). The tail varies along an orbit, and with 0.9 a quarter of the segments of a
// long weakly torqued run were refused (each costing a whole solve); 0.85 refuses under 10% there
// for 2-4% more segments on the paper scene (docs/benchmarks.md). After a failed iteration it halves, and the length that failed caps
// growth, relaxing by 5% per accepted segment, so the tail estimate cannot push segments back
// into non-convergence every step.
class segment_length_control {
 public:
  segment_length_control(double first, std::size_t degree)
      : length_(first), nodes_(static_cast<double>(degree + 1)) {}

  double length() const { return length_; }

  // A segment of length `used` converged with the tail estimate's excess (the log of estimate
  // over tolerance): accepted unless the excess exceeds 8.
  bool converged(double used, double excess_log) {
    if (excess_log > std::log(8.0)) {
      next_ = used * std::max(0.2, 0.8 * std::exp(-excess_log / nodes_));
      return false;
    }
    next_ = used * std::clamp(0.85 * std::exp(-excess_log / nodes_), 0.5, 2.0);
    return true;
  }
  // The Picard iteration did not converge on a segment of length `used`.
  void failed(double used) {
    next_ = used * 0.5;
    cap_ = 0.8 * used;
  }
  // After a refused segment starting at tau: takes the shorter length, or returns false when the
  // length collapsed (below 1e-14 relative) or more than 40 segments in a row were refused.
  bool retry(double tau) {
    if (++refusals_ > 40 || next_ < 1e-14 * std::max(1.0, std::abs(tau))) return false;
    length_ = next_;
    return true;
  }
  void accepted() {
    refusals_ = 0;
    cap_ *= 1.05;
    length_ = std::min(next_, cap_);
  }

 private:
  double length_;
  double nodes_;  // N + 1
  double next_ = 0;
  double cap_ = std::numeric_limits<double>::infinity();
  int refusals_ = 0;
};

}  // namespace detail

// The integrator and its workspace. One instance per thread; run() may be called many times.
template <scalar T>
class chebyshev_picard {
 public:
  explicit chebyshev_picard(const picard_settings& settings = {})
      : settings_(settings),
        N_(settings.degree ? settings.degree : detail::default_degree(effective_bits(settings))),
        n1_(N_ + 1),
        basis_(N_) {
    eps_log_ = detail::log_abs(epsilon<T>());
    tol_log_ = settings.tolerance > 0 ? std::log(settings.tolerance) : eps_log_;
    // Each segment's truncation is held to a sixteenth of the tolerance (never below epsilon),
    // so that the error accumulated over thousands of segments stays near the tolerance: with
    // the tolerance itself, mpfr:256 at 1e-60 ended 6.6e-60 from the truth on the paper scene.
    truncation_target_log_ = std::max(tol_log_ - std::log(16.0), eps_log_);
    S_dt_.resize(n1_ * n1_);  // transposed: column k of S is contiguous
    for (std::size_t j = 0; j < n1_; ++j)
      for (std::size_t k = 0; k < n1_; ++k) S_dt_[k * n1_ + j] = static_cast<double>(basis_.integral[j * n1_ + k]);
    Q_d_.resize((N_ + 2) * n1_);
    for (std::size_t k = 0; k < (N_ + 2) * n1_; ++k) Q_d_[k] = static_cast<double>(basis_.to_coeffs[k]);
    C_d_.resize(n1_ * n1_);
    for (std::size_t k = 0; k < n1_ * n1_; ++k) C_d_[k] = static_cast<double>(basis_.coeffs[k]);
    if constexpr (!std::is_same_v<T, double>) S_dd_ = detail::double_double_matrix(basis_.integral, n1_, n1_);
    if constexpr (std::is_same_v<T, quad>) {
      S_fx_ = detail::fixed_point_matrix<T>(basis_.integral, n1_, n1_);
      Q_fx_ = detail::fixed_point_matrix<T>(basis_.to_coeffs, N_ + 2, n1_);
    } else if constexpr (std::is_same_v<T, mpfr_real>) {
      // The products resolve the bits the run must resolve and 24 more (the sums of N+1 terms
      // lose a few): with a tolerance looser than the precision, fewer limbs per product.
      const unsigned bits = std::min(significand_bits<T>(), effective_bits(settings) + 24);
      S_fx_ = detail::fixed_point_matrix<T>(basis_.integral, n1_, n1_, bits);
      Q_fx_ = detail::fixed_point_matrix<T>(basis_.to_coeffs, N_ + 2, n1_, bits);
    }
    for (int i = 0; i < 3; ++i) {
      F_[i].resize(n1_); Yc_[i].resize(n1_); Yn_[i].resize(n1_);
      r_[i].resize(n1_); delta_[i].resize(n1_); delta_new_[i].resize(n1_); g_[i].resize(n1_);
      Xd_[i].resize(n1_); warm_[i].resize(n1_);
      Xl_[i].resize(n1_); df_hi_[i].resize(n1_); df_lo_[i].resize(n1_);
    }
    acc_ = T(0);
    bd_.resize(N_ + 2);
    for (auto* v : {&F_hi_, &F_lo_, &Y_hi_, &Y_lo_}) v->resize(n1_);
    Fd_.resize(n1_);
    coeff_log_.resize(N_ + 2);
    if constexpr (!std::is_same_v<T, double>) tail_.resize(N_ + 2);
    noise_log_.resize(N_ + 2);
  }

  unsigned degree() const { return static_cast<unsigned>(N_); }

  // The bits the run must resolve: those of T, or fewer when a looser tolerance is asked. The
  // default degree follows them, so a loose tolerance gets short cheap segments rather than
  // long ones on which the Picard sweeps stop contracting.
  static unsigned effective_bits(const picard_settings& s) {
    const unsigned bits = significand_bits<T>();
    if (!(s.tolerance > 0)) return bits;
    const double tol_bits = -std::log2(s.tolerance);
    return static_cast<unsigned>(std::clamp(tol_bits, 8.0, static_cast<double>(bits)));
  }

  // Integrates Eq. 5 from problem.tau0 to tau_end (> tau0) segment by segment: each solved from
  // the previous one's extrapolation (attempt_segment), shortened and retried until it passes,
  // then handed to `sink` (accept_segment). Only the latest segment is kept. Throws
  // numerical_failure when the segments cannot pass.
  void run_segments(const euler_problem<T>& problem, const T& tau_end, const segment_sink<T>& sink,
                    const progress_callback& progress = {}, picard_stats* stats = nullptr) {
    picard_stats st;
    st.degree = static_cast<unsigned>(N_);
    st.tolerance = std::exp(tol_log_);
    problem_ = problem;
    a_d_ = {-1.0, 1.0, -1.0};
    a_lo_ = {0.0, 0.0, 0.0};
    a_max_ = 1;
    if (!problem.normalized()) {
      a_max_ = 0;
      for (int i = 0; i < 3; ++i) {
        a_d_[i] = to_d(problem.a[i]);
        a_lo_[i] = to_d(T(problem.a[i] - T(a_d_[i])));
        a_max_ = std::max(a_max_, std::abs(a_d_[i]));
      }
    }
    if (!(tau_end > problem.tau0))
      throw std::invalid_argument("integrate_reference: tau_end must exceed tau0");
    origin at{problem.Omega0, {T(0), T(0), T(0)}, problem.tau0};
    for (int i = 0; i < 3; ++i)
      if (!isfinite_(at.x[i])) throw numerical_failure({outcome_kind::initial_non_finite, to_d(at.tau)});
    detail::segment_length_control length(first_length(at.x), N_);
    bool have_previous = false;
    std::size_t since_progress = 0;
    while (at.tau < tau_end) {
      bool last = false;
      const T tau_b = segment_end(at.tau, tau_end, length.length(), last);
      const T hl = (tau_b - at.tau) / 2;
      make_warm_start(have_previous ? &segment_ : nullptr, hl);
      outcome verdict = attempt_segment(at, hl, to_d(tau_b - at.tau), length, st);
      if (!verdict.ok()) {
        ++st.rejected;
        verdict.tau = to_d(at.tau);
        if (!length.retry(*verdict.tau)) throw numerical_failure(verdict);
        continue;
      }
      accept_segment(at, tau_b, hl);
      have_previous = true;
      sink(segment_, basis_.nodes);
      if (++st.segments > settings_.max_segments)
        throw numerical_failure(
            {.kind = outcome_kind::segment_limit, .tau = to_d(at.tau), .count = settings_.max_segments});
      if (progress && (++since_progress >= 64 || last)) {
        progress(to_d(at.tau));
        since_progress = 0;
      }
      length.accepted();
      if (last) break;
    }
    if (stats) *stats = st;
  }

  // The same, keeping every segment: the dense output on the whole span.
  dense_trajectory<T> run(const euler_problem<T>& problem, const T& tau_end,
                          const progress_callback& progress = {}, picard_stats* stats = nullptr) {
    std::vector<chebyshev_segment<T>> segs;
    run_segments(
        problem, tau_end, [&](const chebyshev_segment<T>& seg, const std::vector<T>&) { segs.push_back(seg); },
        progress, stats);
    return dense_trajectory<T>(std::move(segs), basis_.nodes);
  }

 private:
  // Where the next segment starts: Omega = x + x_lo (TwoSum compensation) at tau.
  struct origin {
    vec3<T> x, x_lo;
    T tau;
  };
  struct solve_result {
    outcome failure;       // success when the iteration converged
    double scale_log = 0;  // log of the state scale max |Omega| on the segment
  };
  struct tail_estimate {
    double excess_log = 0;  // log(estimated truncation / (tol * scale)); <= 0 is within tolerance
  };

  static double to_d(const T& x) { return static_cast<double>(x); }
  static bool isfinite_(const T& x) {
    using std::isfinite;
    using boost::multiprecision::isfinite;
    return isfinite(x);
  }
  // x += d, in place (for MPFR without a temporary, which would allocate).
  static void add_double(T& x, double d) {
    if constexpr (std::is_same_v<T, mpfr_real>)
      mpfr_add_d(x.backend().data(), x.backend().data(), d, MPFR_RNDN);
    else
      x += d;
  }
  static double log_of(double r) { return r > 0 ? std::log(r) : -std::numeric_limits<double>::infinity(); }

  // The end of the segment of length L from tau, in T; the last segment (`last`) ends exactly at
  // tau_end, also when it would leave a sliver of less than L / 1000.
  static T segment_end(const T& tau, const T& tau_end, double L, bool& last) {
    const T tau_b = tau + T(L);
    last = !(tau_b < tau_end) || to_d(tau_end - tau_b) < 1e-3 * L;
    return last ? tau_end : tau_b;
  }

  // The first segment length: from the settings, or half a turn of the fastest rate in sight
  // (|a| |Omega_i|, and sqrt(|a| |G_i|) for the spin-up from rest; |a| = 1 in Eq. 5).
  double first_length(const vec3<T>& x0) const {
    if (settings_.initial_step > 0) return settings_.initial_step;
    double rate = 0;
    for (int i = 0; i < 3; ++i)
      rate = std::max({rate, a_max_ * std::abs(to_d(x0[i])), std::sqrt(a_max_ * std::abs(to_d(problem_.torque.G[i])))});
    return rate > 0 ? 0.5 / rate : 1.0;
  }

  // Solves the segment of half length hl from `at` (warm start in warm_) and judges its length:
  // success to accept it, otherwise why it is refused, as the failure to report should the
  // segments shrink to nothing (no_convergence, or segment_collapse for a tail too large).
  outcome attempt_segment(const origin& at, const T& hl, double length_used,
                          detail::segment_length_control& length, picard_stats& st) {
    const solve_result res = solve_segment(at.x, at.x_lo, hl, st);
    if (!res.failure.ok()) {
      length.failed(length_used);
      return {.kind = outcome_kind::no_convergence, .cause = res.failure.kind, .value = res.failure.value,
              .count = res.failure.count};
    }
    if (length.converged(length_used, estimate_tail(hl, res.scale_log).excess_log)) return {};
    return {outcome_kind::segment_collapse};
  }

  // The solved segment [at.tau, tau_b] (increments in Yn_), stored in segment_; `at` moves to its
  // end, the last increment added with compensated summation (TwoSum).
  void accept_segment(origin& at, const T& tau_b, const T& hl) {
    chebyshev_segment<T>& seg = segment_;
    seg.tau_begin = at.tau;
    seg.tau_end = tau_b;
    seg.half_length = hl;
    seg.base = at.x;
    seg.base_lo = at.x_lo;
    seg.values.resize(n1_);
    for (std::size_t j = 0; j < n1_; ++j)
      for (int i = 0; i < 3; ++i) seg.values[j][i] = Yn_[i][j];
    vec3<T> x1, c1;
    for (int i = 0; i < 3; ++i) {
      const T y = Yn_[i][N_] + at.x_lo[i];
      const T s = at.x[i] + y;
      const T bb = s - at.x[i];
      c1[i] = (at.x[i] - (s - bb)) + (y - bb);
      x1[i] = s;
      if (!isfinite_(s)) throw numerical_failure({outcome_kind::segment_non_finite, to_d(tau_b)});
    }
    at.x = x1;
    at.x_lo = c1;
    at.tau = tau_b;
  }

  // Increments at the new nodes extrapolated from the previous segment's interpolant, in double.
  void make_warm_start(const chebyshev_segment<T>* prev, const T& hl_new) {
    for (int i = 0; i < 3; ++i) std::fill(warm_[i].begin(), warm_[i].end(), 0.0);
    if (!prev) return;
    const double ratio = to_d(hl_new / prev->half_length);
    double ymax = 0;
    for (int i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < n1_; ++j) Fd_[j] = to_d(prev->values[j][i]);
      // Chebyshev coefficients of the degree-N interpolant through the node values.
      double cmax = 0;
      for (std::size_t k = 0; k < n1_; ++k) {
        const double* row = &C_d_[k * n1_];
        double a = 0;
        for (std::size_t j = 0; j < n1_; ++j) a += row[j] * Fd_[j];
        bd_[k] = a;
        cmax = std::max(cmax, std::abs(a));
      }
      ymax = std::max(ymax, cmax);
      // Coefficients at the double noise floor only amplify under extrapolation: drop them.
      for (std::size_t k = 1; k < n1_; ++k)
        if (std::abs(bd_[k]) < 1e-15 * cmax) bd_[k] = 0;
      const double p1 = detail::clenshaw<double>(bd_.data(), n1_, 1, 1.0);
      for (std::size_t j = 0; j < n1_; ++j) {
        const double s = 1.0 + ratio * (static_cast<double>(basis_.nodes[j]) + 1.0);
        warm_[i][j] = detail::clenshaw<double>(bd_.data(), n1_, 1, s) - p1;
      }
    }
    // A wild extrapolation is worse than a cold start.
    for (int i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < n1_; ++j)
        if (!std::isfinite(warm_[i][j]) || std::abs(warm_[i][j]) > 8 * (1 + ratio) * ymax + 1) {
          for (int m = 0; m < 3; ++m) std::fill(warm_[m].begin(), warm_[m].end(), 0.0);
          return;
        }
  }

  // Solves the collocation problem on one segment from the warm start. On success Yn_ holds the
  // increments at the nodes and F_ the derivative there.
  solve_result solve_segment(const vec3<T>& x0, const vec3<T>& c0, const T& hl, picard_stats& st) {
    const double hl_d = to_d(hl);
    for (int i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < n1_; ++j) Yc_[i][j] = T(warm_[i][j]);
    double r_prev_log = std::numeric_limits<double>::infinity();
    if constexpr (!std::is_same_v<T, double>) {
      if (const outcome o = narrow_passes(x0, c0, hl, st, r_prev_log); !o.ok()) return {o};
    }
    const std::size_t max_passes = 4 + significand_bits<T>() / 40;
    for (std::size_t pass = 1;; ++pass) {
      const double scale = evaluate_nodes(x0, c0);
      if (!std::isfinite(scale)) return {{outcome_kind::iterate_non_finite}};
      solve_result out;
      out.scale_log = std::log(std::max(scale, 1e-300));
      ++st.wide_residuals;
      const double r_max = wide_residual(hl);
      if (!std::isfinite(r_max)) return {{outcome_kind::residual_non_finite}};
      const double r_log = log_of(r_max);
      if (converged(r_log, r_prev_log, out.scale_log)) return out;
      if (pass >= max_passes || (r_prev_log < std::numeric_limits<double>::infinity() &&
                                 r_log > r_prev_log - std::log(2.0)))
        return {{.kind = outcome_kind::residual_stalled, .value = r_max, .count = pass}};
      r_prev_log = r_log;
      if (const outcome o = correct(r_max, hl_d, st); !o.ok()) return {o};
      if constexpr (std::is_same_v<T, mpfr_real>) {
        // Residual updates (update_residual) instead of full residuals while their error, about
        // 2^-100 of this residual, stays 2^-20 below the tolerance: that error repeats from
        // segment to segment (it is mostly the rounding of S to double-double), so it must stay
        // far below what one segment may contribute. A full residual in T when they stop
        // decreasing. Only for MPFR, where a full residual costs several double-double ones.
        const double update_floor_log = r_log - 100 * std::log(2.0);
        if (update_floor_log > tol_log_ + out.scale_log - 20 * std::log(2.0)) continue;
        for (;;) {
          ++st.residual_updates;
          const double r_up = update_residual(hl);
          if (!std::isfinite(r_up)) return {{outcome_kind::residual_non_finite}};
          const double r_up_log = log_of(r_up);
          if (converged(r_up_log, r_prev_log, out.scale_log)) return out;
          if (r_up_log > r_prev_log - std::log(2.0)) break;
          r_prev_log = r_up_log;
          if (const outcome o = correct(r_up, hl_d, st); !o.ok()) return {o};
        }
      }
    }
  }

  // Converged: residual within the tolerance or at the rounding level of one residual
  // evaluation (a sum of N+1 rounded terms: ~sqrt(N+1) eps), or stagnant near that floor.
  bool converged(double r_log, double r_prev_log, double scale_log) const {
    const double rounding_log = eps_log_ + std::log(4.0 * std::sqrt(double(n1_))) + scale_log;
    const double floor_log = eps_log_ + std::log(64.0 * n1_) + scale_log;
    return r_log <= std::max(tol_log_ + scale_log, rounding_log) ||
           (r_log <= floor_log && r_log > r_prev_log - std::log(16.0));
  }

  // For wide T, the passes before the first residual in T: one in double from the warm start
  // and one in double-double, each followed by its correction. Sets r_log to the log of the
  // last residual.
  outcome narrow_passes(const vec3<T>& x0, const vec3<T>& c0, const T& hl, picard_stats& st, double& r_log) {
    const double hl_d = to_d(hl);
    const double r_double = double_residual(x0, c0, hl_d);
    if (const outcome o = correct(r_double, hl_d, st); !o.ok()) return o;
    const double r_dd = double_double_residual(x0, c0, hl);
    if (const outcome o = correct(r_dd, hl_d, st); !o.ok()) return o;
    if (log_of(r_dd) > log_of(r_double) - std::log(2.0)) return {outcome_kind::residual_not_decreasing};
    r_log = log_of(r_dd);
    return {};
  }

  // X = x0 + (c0 + Yc) and F = f(X) (Eq. 1 or 5) at the nodes, X also in double (Xd_). Returns the
  // state scale max |X|.
  double evaluate_nodes(const vec3<T>& x0, const vec3<T>& c0) {
    double scale = 0;
    vec3<T>& x = node_x_;
    vec3<T>& dx = node_f_;
    for (std::size_t j = 0; j < n1_; ++j) {
      for (int i = 0; i < 3; ++i) {
        x[i] = x0[i] + (c0[i] + Yc_[i][j]);
        Xd_[i][j] = to_d(x[i]);
        scale = std::max(scale, std::abs(Xd_[i][j]));
        if constexpr (!std::is_same_v<T, double>) {
          acc_ = x[i];
          acc_ -= Xd_[i][j];
          Xl_[i][j] = to_d(acc_);
        }
      }
      problem_.rhs(problem_.tau0, x, dx);
      for (int i = 0; i < 3; ++i) F_[i][j] = dx[i];
    }
    return scale;
  }

  // The Picard map Yn = hl S F in T, and the residual r = Yn - Yc. Returns max |r|. For wide T
  // the product S F is exact integer arithmetic rounded once (fixed_point_matrix), several times
  // faster than the same sums in T and no less accurate.
  double wide_residual(const T& hl) {
    double r_max = 0;
    for (int i = 0; i < 3; ++i) {
      Yn_[i][0] = 0;
      if constexpr (!std::is_same_v<T, double>) {
        S_fx_.multiply(F_[i].data(), Yn_[i].data(), 1);
        for (std::size_t j = 1; j < n1_; ++j) Yn_[i][j] *= hl;
      } else {
        for (std::size_t j = 1; j < n1_; ++j) {
          const T* row = &basis_.integral[j * n1_];
          acc_ = 0;
          for (std::size_t k = 0; k < n1_; ++k) acc_ += row[k] * F_[i][k];
          acc_ *= hl;
          Yn_[i][j] = acc_;
        }
      }
      for (std::size_t j = 1; j < n1_; ++j) {
        acc_ = Yn_[i][j];
        acc_ -= Yc_[i][j];
        r_[i][j] = to_d(acc_);
        r_max = std::max(r_max, std::abs(r_[i][j]));
      }
      r_[i][0] = 0;
    }
    return r_max;
  }

  // The residual from the warm start, all in double: it is far above double rounding, so
  // computing it in T would buy nothing (for T = double the first wide residual is this pass).
  // Returns max |r|.
  double double_residual(const vec3<T>& x0, const vec3<T>& c0, double hl_d) {
    vec3<double> x0d, dx;
    for (int i = 0; i < 3; ++i) x0d[i] = to_d(x0[i]) + to_d(c0[i]);
    const vec3<double> Gd{to_d(problem_.torque.G[0]), to_d(problem_.torque.G[1]), to_d(problem_.torque.G[2])};
    for (std::size_t j = 0; j < n1_; ++j) {
      vec3<double> x;
      for (int i = 0; i < 3; ++i) x[i] = Xd_[i][j] = x0d[i] + warm_[i][j];
      direct_rhs(a_d_, x, Gd, dx);
      for (int i = 0; i < 3; ++i) g_[i][j] = dx[i];
    }
    double r_max = 0;
    double_integral(g_, r_);
    for (int i = 0; i < 3; ++i) {
      r_[i][0] = 0;
      for (std::size_t j = 1; j < n1_; ++j) {
        r_[i][j] = hl_d * r_[i][j] - warm_[i][j];
        r_max = std::max(r_max, std::abs(r_[i][j]));
      }
    }
    return r_max;
  }

  // The second residual, for wide T: in double-double (~1e-32 relative), enough to drive the
  // correction that follows to that level, at a fraction of a residual in T. The next residual,
  // in T, decides convergence. Returns max |r|.
  double double_double_residual(const vec3<T>& x0, const vec3<T>& c0, const T& hl) {
    vec3<T>& x = node_x_;
    vec3<T>& dx = node_f_;
    for (std::size_t j = 0; j < n1_; ++j) {
      for (int i = 0; i < 3; ++i) {
        x[i] = x0[i] + (c0[i] + Yc_[i][j]);
        Xd_[i][j] = to_d(x[i]);
      }
      problem_.rhs(problem_.tau0, x, dx);
      for (int i = 0; i < 3; ++i) F_[i][j] = dx[i] * hl;  // scaled by hl here, once
    }
    double r_max = 0;
    for (int i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < n1_; ++j) {
        F_hi_[j] = to_d(F_[i][j]);
        F_lo_[j] = to_d(T(F_[i][j] - T(F_hi_[j])));
      }
      S_dd_.multiply(F_hi_.data(), F_lo_.data(), Y_hi_.data(), Y_lo_.data(), 1);
      r_[i][0] = 0;
      for (std::size_t j = 1; j < n1_; ++j) {
        acc_ = T(Y_hi_[j]);
        acc_ -= Yc_[i][j];
        acc_ += T(Y_lo_[j]);
        r_[i][j] = to_d(acc_);
        r_max = std::max(r_max, std::abs(r_[i][j]));
      }
    }
    return r_max;
  }

  // For wide T, the residual after the correction delta_ (already added to Yc_) without a new
  // residual in T. Eq. 1 is quadratic, so with X the nodes' state before the correction
  //   f(X + delta) - f(X) = g = (a1 (x2 d3 + x3 d2 + d2 d3), a2 (x1 d3 + x3 d1 + d1 d3), a3 (x1 d2 + x2 d1 + d1 d2))
  // exactly (a = (-1, 1, -1) in Eq. 5), and the Picard map moves by hl S g: Yn += hl S g, F += g, r = Yn - Yc. g and
  // hl S g are formed in double-double from X in double-double (Xd_ + Xl_, moved by delta
  // here), so the update errs by about 2^-100 |delta|: a residual at the level of the last full
  // one times 2^-100 is resolved, at a fraction of the cost of a full residual. Returns max |r|.
  double update_residual(const T& hl) {
    const double hl_hi = to_d(hl);
    acc_ = hl;
    acc_ -= hl_hi;
    const double hl_lo = to_d(acc_);
    for (std::size_t j = 0; j < n1_; ++j) {
      const double d1 = delta_[0][j], d2 = delta_[1][j], d3 = delta_[2][j];
      const dd x1{Xd_[0][j], Xl_[0][j]}, x2{Xd_[1][j], Xl_[1][j]}, x3{Xd_[2][j], Xl_[2][j]};
      dd g[3] = {add(add(mul(x2, d3), mul(x3, d2)), product(d2, d3)),
                 add(add(mul(x1, d3), mul(x3, d1)), product(d1, d3)),
                 add(add(mul(x1, d2), mul(x2, d1)), product(d1, d2))};
      for (int i = 0; i < 3; ++i) g[i] = mul(g[i], dd{a_d_[i], a_lo_[i]});  // exact for a = +-1 (Eq. 5)
      for (int i = 0; i < 3; ++i) {
        df_hi_[i][j] = g[i].hi;
        df_lo_[i][j] = g[i].lo;
        const dd x = add(dd{Xd_[i][j], Xl_[i][j]}, dd{delta_[i][j], 0});
        Xd_[i][j] = x.hi;
        Xl_[i][j] = x.lo;
      }
    }
    double r_max = 0;
    for (int i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < n1_; ++j) {
        const dd hg = mul(dd{df_hi_[i][j], df_lo_[i][j]}, dd{hl_hi, hl_lo});
        F_hi_[j] = hg.hi;
        F_lo_[j] = hg.lo;
        add_double(F_[i][j], df_hi_[i][j]);
        add_double(F_[i][j], df_lo_[i][j]);
      }
      S_dd_.multiply(F_hi_.data(), F_lo_.data(), Y_hi_.data(), Y_lo_.data(), 1);
      r_[i][0] = 0;
      for (std::size_t j = 1; j < n1_; ++j) {
        add_double(Yn_[i][j], Y_hi_[j]);
        add_double(Yn_[i][j], Y_lo_[j]);
        acc_ = Yn_[i][j];
        acc_ -= Yc_[i][j];
        r_[i][j] = to_d(acc_);
        r_max = std::max(r_max, std::abs(r_[i][j]));
      }
    }
    return r_max;
  }

  // Double-double arithmetic for update_residual: Dekker's exact product (no hardware FMA
  // assumed) and Knuth's TwoSum (Dekker 1971; Knuth, TAOCP vol. 2, 4.2.2).
  struct dd {
    double hi, lo;
  };
  static dd quick_sum(double a, double b) {
    const double s = a + b;
    return {s, b - (s - a)};
  }
  static dd two_sum(double a, double b) {
    const double s = a + b;
    const double bb = s - a;
    return {s, (a - (s - bb)) + (b - bb)};
  }
  static void split(double a, double& a1, double& a2) {
    const double t = 134217729.0 * a;  // 2^27 + 1
    a1 = t - (t - a);
    a2 = a - a1;
  }
  static dd product(double a, double b) {
    double a1, a2, b1, b2;
    split(a, a1, a2);
    split(b, b1, b2);
    const double p = a * b;
    return {p, ((a1 * b1 - p) + a1 * b2 + a2 * b1) + a2 * b2};
  }
  static dd mul(const dd& x, double b) {
    const dd p = product(x.hi, b);
    return quick_sum(p.hi, p.lo + x.lo * b);
  }
  static dd mul(const dd& x, const dd& y) {
    const dd p = product(x.hi, y.hi);
    return quick_sum(p.hi, p.lo + (x.hi * y.lo + x.lo * y.hi));
  }
  static dd add(const dd& x, const dd& y) {
    const dd s = two_sum(x.hi, y.hi);
    return quick_sum(s.hi, s.lo + (x.lo + y.lo));
  }

  // Solves for the correction of the residual in r_ (largest entry r_max) and adds it to Yc_.
  outcome correct(double r_max, double hl_d, picard_stats& st) {
    if (!std::isfinite(r_max)) return {outcome_kind::residual_non_finite};
    if (const outcome o = solve_correction(hl_d, st); !o.ok()) return o;
    for (int i = 0; i < 3; ++i)
      for (std::size_t j = 1; j < n1_; ++j) add_double(Yc_[i][j], delta_[i][j]);
    return {};
  }

  // y_i = S g_i (rows 1..N) for the three components in double. Column order (y += S[:,k] g[k])
  // keeps the rows independent, so the compiler vectorizes across them without reassociating
  // any sum (a row-by-row dot product is bound by the latency of its serial additions); four
  // columns per pass over y quarter its loads and stores, which bound the plain column loop.
  void double_integral(const std::array<std::vector<double>, 3>& g, std::array<std::vector<double>, 3>& y) const {
    for (int i = 0; i < 3; ++i) {
      double* out = y[i].data();
      const double* gi = g[i].data();
      std::fill(out, out + n1_, 0.0);
      std::size_t k = 0;
      for (; k + 4 <= n1_; k += 4) {
        const double* c0 = &S_dt_[k * n1_];
        const double* c1 = c0 + n1_;
        const double* c2 = c1 + n1_;
        const double* c3 = c2 + n1_;
        const double g0 = gi[k], g1 = gi[k + 1], g2 = gi[k + 2], g3 = gi[k + 3];
        for (std::size_t j = 0; j < n1_; ++j) out[j] += (c0[j] * g0 + c1[j] * g1) + (c2[j] * g2 + c3[j] * g3);
      }
      for (; k < n1_; ++k) {
        const double* col = &S_dt_[k * n1_];
        const double gk = gi[k];
        for (std::size_t j = 0; j < n1_; ++j) out[j] += col[j] * gk;
      }
    }
  }

  // delta = r + hl S [J(Xd) delta + f_2(delta)] by Picard sweeps in double (correction_sweep).
  // Done when the sweep's change is at double rounding, or stagnant near it; a growing change
  // means the segment is too long.
  outcome solve_correction(double hl_d, picard_stats& st) {
    constexpr std::size_t max_sweeps = 200;
    for (int i = 0; i < 3; ++i) delta_[i] = r_[i];
    double prev_diff = std::numeric_limits<double>::infinity();
    double first_diff = -1;
    for (std::size_t sweep = 0; sweep < max_sweeps; ++sweep) {
      ++st.double_sweeps;
      double dmax = 0;
      const double diff = correction_sweep(hl_d, dmax);
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

  // One sweep delta <- r + hl S g(delta), where
  // g = f(x + d) - f(x) = (a1 (x2 d3 + x3 d2 + d2 d3), a2 (x1 d3 + x3 d1 + d1 d3), a3 (x1 d2 + x2 d1 + d1 d2))
  // (in Eq. 5 a = (-1, 1, -1), and the products by +-1 are exact).
  // Returns the largest change; dmax is the largest entry of the new delta.
  double correction_sweep(double hl_d, double& dmax) {
    for (std::size_t k = 0; k < n1_; ++k) {
      const double d1 = delta_[0][k], d2 = delta_[1][k], d3 = delta_[2][k];
      const double x1 = Xd_[0][k], x2 = Xd_[1][k], x3 = Xd_[2][k];
      g_[0][k] = a_d_[0] * (x2 * d3 + x3 * d2 + d2 * d3);
      g_[1][k] = a_d_[1] * (x1 * d3 + x3 * d1 + d1 * d3);
      g_[2][k] = a_d_[2] * (x1 * d2 + x2 * d1 + d1 * d2);
    }
    double diff = 0;
    double_integral(g_, delta_new_);
    for (int i = 0; i < 3; ++i) {
      delta_new_[i][0] = 0;
      for (std::size_t j = 1; j < n1_; ++j) {
        const double v = r_[i][j] + hl_d * delta_new_[i][j];
        diff = std::max(diff, std::abs(v - delta_[i][j]));
        dmax = std::max(dmax, std::abs(v));
        delta_new_[i][j] = v;
      }
    }
    std::swap(delta_, delta_new_);
    return diff;
  }

  // Truncation estimate from the decay of the Chebyshev coefficients b_k of the increment
  // (b = hl Q F): a least-squares line through log max_i |b_k| over the coefficients above their
  // rounding floor, evaluated at k = N+1, and the last coefficients themselves; compared with
  // tol * scale.
  tail_estimate estimate_tail(const T& hl, double scale_log) {
    const std::size_t nb = N_ + 2, tail_from = N_ - 2;
    const double head_max = coefficient_logs(hl, tail_from);
    const double head_noise = std::log(std::max(head_max, 1e-300) * 8.0 * n1_ * 2.2e-16);
    const double tail_noise = eps_log_ + scale_log + std::log(4.0 * n1_);
    for (std::size_t k = 0; k < nb; ++k) noise_log_[k] = k < tail_from ? std::max(head_noise, tail_noise) : tail_noise;
    // Envelope over neighbours: odd/even parts of the series vanish alternately.
    for (std::size_t k = 1; k + 1 < nb; ++k) coeff_log_[k] = std::max(coeff_log_[k], coeff_log_[k + 1]);
    const double target = truncation_target_log_ + scale_log;
    const double margin = std::log(100.0);
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (std::size_t k = 1; k < nb; ++k) {
      if (coeff_log_[k] > noise_log_[k] + margin) {
        const double x = static_cast<double>(k);
        sx += x; sy += coeff_log_[k]; sxx += x * x; sxy += x * coeff_log_[k];
        ++n;
      }
    }
    tail_estimate te;
    const double last = coeff_log_[nb - 1];
    const bool last_resolved = last > tail_noise + margin;
    if (n >= 3) {
      const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
      const double icpt = (sy - slope * sx) / n;
      double pred = icpt + slope * static_cast<double>(nb - 1);
      if (slope >= 0) pred = last;  // no decay seen: trust only the actual tail
      te.excess_log = std::max(pred, last_resolved ? last : pred) - target;
    } else {
      // Everything but the first coefficients is at the rounding floor: the series converges
      // much faster than needed, so let the segment grow (the caller caps growth at 2x).
      te.excess_log = last_resolved ? last - target : -std::log(4.0) * double(N_ + 1);
    }
    return te;
  }

  // coeff_log_[k] = log max_i |b_k| for k >= 1. The head b_1..b_{tail_from - 1} is formed in
  // double (it only has to show the decay rate); the tail in T, since it must be resolved down
  // to the tolerance. Returns the largest head coefficient.
  double coefficient_logs(const T& hl, std::size_t tail_from) {
    const std::size_t nb = N_ + 2;
    const double hl_d = to_d(hl);
    std::fill(coeff_log_.begin(), coeff_log_.end(), -std::numeric_limits<double>::infinity());
    double head_max = 0;
    for (int i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < n1_; ++j) Fd_[j] = to_d(F_[i][j]);
      for (std::size_t k = 1; k < tail_from; ++k) {
        const double* row = &Q_d_[k * n1_];
        double a = 0;
        for (std::size_t j = 0; j < n1_; ++j) a += row[j] * Fd_[j];
        a = std::abs(a * hl_d);
        head_max = std::max(head_max, a);
        coeff_log_[k] = std::max(coeff_log_[k], a > 0 ? std::log(a) : -std::numeric_limits<double>::infinity());
      }
      if constexpr (!std::is_same_v<T, double>) {
        Q_fx_.multiply(F_[i].data(), tail_.data(), tail_from);
        for (std::size_t k = tail_from; k < nb; ++k)
          coeff_log_[k] = std::max(coeff_log_[k], detail::log_abs(T(tail_[k] * hl)));
      } else {
        for (std::size_t k = tail_from; k < nb; ++k) {
          const T* row = &basis_.to_coeffs[k * n1_];
          acc_ = 0;
          for (std::size_t j = 0; j < n1_; ++j) acc_ += row[j] * F_[i][j];
          acc_ *= hl;
          coeff_log_[k] = std::max(coeff_log_[k], detail::log_abs(acc_));
        }
      }
    }
    return head_max;
  }

  picard_settings settings_;
  std::size_t N_, n1_;  // the degree, and the number of nodes N + 1
  detail::chebyshev_basis<T> basis_;
  double eps_log_ = 0, tol_log_ = 0;  // log epsilon of T; log of the relative tolerance
  double truncation_target_log_ = 0;  // log of the relative truncation bound per segment
  euler_problem<T> problem_;  // the equations of the run (Eq. 5, or Eq. 1 in the direct form)
  // Its coefficients a in double ((-1, 1, -1) for Eq. 5), the rest of them (a - a_d_, for the
  // double-double updates) and max |a_i|.
  std::array<double, 3> a_d_{-1.0, 1.0, -1.0}, a_lo_{};
  double a_max_ = 1;
  // The workspace. Per component i of Omega and node j (arrays of three vectors over the nodes):
  //   Yc_    the iterate: increments X - x0 at the nodes, in T (X the state at the nodes)
  //   Yn_    the Picard map hl S f(X) of the iterate, in T: the segment's values once converged
  //   F_     f(X) by Eq. 1 or 5, in T (times hl in the double-double residual)
  //   Xd_    X in double, where the correction linearizes f
  //   warm_  the warm start's increments, in double
  //   r_     the residual hl S f(X) - Yc, in double
  //   delta_, delta_new_  the correction of Yc and its next sweep, in double
  //   g_     f(X + delta) - f(X) in a sweep (f(X) in the double residual), in double
  std::array<std::vector<T>, 3> F_, Yc_, Yn_;
  std::array<std::vector<double>, 3> r_, delta_, delta_new_, g_, Xd_, warm_;
  // For wide T: X in double-double (Xd_ + Xl_) and g = f(X + delta) - f(X) in double-double
  // (df_hi_ + df_lo_),
  // for the residual updates.
  std::array<std::vector<double>, 3> Xl_, df_hi_, df_lo_;
  // The basis matrices in double: S transposed (column k contiguous), Q (values to the
  // integral's coefficients) and C (values to the interpolant's coefficients); S in
  // double-double for wide T.
  std::vector<double> S_dt_, Q_d_, C_d_;
  detail::double_double_matrix S_dd_;
  // For wide T: S and Q in fixed point, and the coefficients Q F of one component.
  struct no_fixed_point {};
  using fixed_point = std::conditional_t<std::is_same_v<T, double>, no_fixed_point, detail::fixed_point_matrix<T>>;
  fixed_point S_fx_, Q_fx_;
  std::vector<T> tail_;
  // One component at a time: F and S F split into double-double hi + lo; F in double and its
  // Chebyshev coefficients bd_ (warm start); log |b_k| of the increment's coefficients and
  // their rounding floor (tail estimate).
  std::vector<double> F_hi_, F_lo_, Y_hi_, Y_lo_;
  std::vector<double> bd_, Fd_, coeff_log_, noise_log_;
  T acc_;  // accumulator in T: in place, no temporary per operation for MPFR
  vec3<T> node_x_, node_f_;  // the state and f at one node, reused (no allocation per node)
  chebyshev_segment<T> segment_;  // the latest accepted segment (the next one's warm start)
};

// Integrates Eq. 5 from problem.tau0 to tau_end (> tau0). Throws numerical_failure.
template <scalar T>
dense_trajectory<T> integrate_reference(const euler_problem<T>& problem, const T& tau_end,
                                        const picard_settings& settings = {},
                                        const progress_callback& progress = {},
                                        picard_stats* stats = nullptr) {
  chebyshev_picard<T> integrator(settings);
  return integrator.run(problem, tau_end, progress, stats);
}

// Integrates Eq. 5 from problem.tau0 to tau_end and evaluates the dense output at `taus`
// (non-decreasing, within [tau0, tau_end]) as the run goes, in constant memory: `emit(index, tau,
// Omega)` receives each sample in order. The values equal those of integrate_reference's
// trajectory at the same times. `after_segment`, if set, sees each segment after the samples
// before its start were emitted, so a segment's samples come between it and the next one.
// Throws numerical_failure.
template <scalar T>
void integrate_reference_samples(const euler_problem<T>& problem, const T& tau_end, const std::vector<T>& taus,
                                 const typename segment_sampler<T>::emit_function& emit,
                                 const picard_settings& settings = {}, const progress_callback& progress = {},
                                 picard_stats* stats = nullptr, const segment_sink<T>& after_segment = {}) {
  segment_sampler<T> sampler(taus, emit);
  chebyshev_picard<T> integrator(settings);
  integrator.run_segments(
      problem, tau_end,
      [&](const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
        sampler(seg, nodes);
        if (after_segment) after_segment(seg, nodes);
      },
      progress, stats);
  sampler.finish();
}

}  // namespace eulervop

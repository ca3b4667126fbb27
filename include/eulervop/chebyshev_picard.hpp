// Chebyshev-Picard reference integrator for Eq. 5 with dense output.
//
// Each segment [tau_a, tau_a + L] carries the degree-N interpolant of Omega' at the N+1
// Chebyshev-Gauss-Lobatto nodes; its exact integral gives Omega at the nodes (the Picard map,
// Clenshaw & Norton 1963; Bai & Junkins 2011). The fixed point is reached by mixed precision
// defect correction (DESIGN.md section 5):
//   1. the residual of the Picard map, r = x0 + (L/2) S f(X) - X, is computed in T;
//   2. the correction delta solves delta = r + (L/2) S [f(X + delta) - f(X)] in double. Eq. 5 is
//      quadratic, so f(X + delta) - f(X) = J(X) delta + f_2(delta) exactly, and the double
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

#include <eulervop/detail/chebyshev_basis.hpp>
#include <eulervop/detail/double_double_matvec.hpp>
#include <eulervop/model.hpp>
#include <eulervop/scalar.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace eulervop {

// Knobs of the reference integrator. Zero means "derive from the precision of T".
struct picard_settings {
  unsigned degree = 0;       // Chebyshev degree N (N+1 Gauss-Lobatto nodes per segment)
  double tolerance = 0;      // relative truncation bound per segment; 0: epsilon of T
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
  std::size_t double_sweeps = 0;   // Picard sweeps of the double-precision correction
};

// A numerical failure of the integrator: where (tau) and why. The CLI maps it to exit code 3.
class numerical_failure : public std::runtime_error {
 public:
  numerical_failure(double tau, const std::string& why)
      : std::runtime_error("numerical failure at tau=" + format_tau(tau) + ": " + why), tau_(tau),
        why_(why) {}
  double tau() const { return tau_; }
  const std::string& why() const { return why_; }

 private:
  static std::string format_tau(double tau) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", tau);
    return buf;
  }
  double tau_;
  std::string why_;
};

// One segment of the dense output: Omega(tau) = base + (base_lo + p(s)), where p is the
// polynomial through the increments `values` at the Chebyshev-Lobatto nodes s_j = -cos(j pi/N)
// and s = (tau - tau_begin) / half_length - 1 in [-1, 1]. base_lo is the TwoSum compensation.
template <class T>
struct chebyshev_segment {
  T tau_begin, tau_end, half_length;
  vec3<T> base, base_lo;
  std::vector<vec3<T>> values;  // Omega(tau_j) - Omega(tau_begin) at the N+1 nodes
};

// The reference solution on [tau_begin, tau_end], evaluable anywhere in it to full precision.
// Evaluation is barycentric Lagrange interpolation (second form) on the Lobatto nodes, with
// weights (-1)^j, halved at the ends: backward stable for these nodes (Higham 2004, Berrut &
// Trefethen 2004) and O(N) per call.
template <class T>
class dense_trajectory {
 public:
  dense_trajectory() = default;
  dense_trajectory(std::vector<chebyshev_segment<T>> segs, std::vector<T> nodes)
      : segs_(std::move(segs)), nodes_(std::move(nodes)) {}

  const T& tau_begin() const { return segs_.front().tau_begin; }
  const T& tau_end() const { return segs_.back().tau_end; }
  std::size_t segments() const { return segs_.size(); }
  const std::vector<chebyshev_segment<T>>& segment_list() const { return segs_; }

  // Omega(tau). Throws std::out_of_range outside [tau_begin, tau_end].
  vec3<T> operator()(const T& tau) const {
    if (segs_.empty() || !(tau >= tau_begin() && tau <= tau_end()))
      throw std::out_of_range("dense_trajectory: tau outside the integrated span");
    // The last segment whose start is <= tau.
    auto it = std::upper_bound(segs_.begin(), segs_.end(), tau,
                               [](const T& t, const chebyshev_segment<T>& s) { return t < s.tau_begin; });
    const chebyshev_segment<T>& seg = *(it - 1);
    vec3<T> out;
    const std::size_t n1 = nodes_.size();
    T s = (tau - seg.tau_begin) / seg.half_length - 1;
    if (s > 1) s = 1;
    std::size_t hit = n1;
    if (tau == seg.tau_begin) hit = 0;  // the segment's start is known exactly
    for (std::size_t j = 0; j < n1 && hit == n1; ++j)
      if (s == nodes_[j]) hit = j;
    if (hit < n1) {
      for (int i = 0; i < 3; ++i) out[i] = seg.base[i] + (seg.base_lo[i] + seg.values[hit][i]);
      return out;
    }
    T den = 0;
    vec3<T> num{T(0), T(0), T(0)};
    for (std::size_t j = 0; j < n1; ++j) {
      T w = 1 / (s - nodes_[j]);
      if (j % 2) w = -w;
      if (j == 0 || j + 1 == n1) w /= 2;
      den += w;
      for (int i = 0; i < 3; ++i) num[i] += w * seg.values[j][i];
    }
    for (int i = 0; i < 3; ++i) out[i] = seg.base[i] + (seg.base_lo[i] + num[i] / den);
    return out;
  }

 private:
  std::vector<chebyshev_segment<T>> segs_;
  std::vector<T> nodes_;
};

// Progress callback: the tau reached so far.
using progress_callback = std::function<void(double tau_reached)>;

namespace detail {

// log|x| in double for any T, also where |x| underflows double (MPFR at thousands of bits).
template <class T>
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

}  // namespace detail

// The integrator and its workspace. One instance per thread; run() may be called many times.
template <class T>
class chebyshev_picard {
 public:
  explicit chebyshev_picard(const picard_settings& settings = {})
      : settings_(settings),
        N_(settings.degree ? settings.degree : detail::default_degree(effective_bits(settings))),
        n1_(N_ + 1),
        basis_(N_) {
    eps_ = static_cast<double>(epsilon<T>());  // 0 for MPFR beyond double's range is harmless
    eps_log_ = detail::log_abs(epsilon<T>());
    tol_log_ = settings.tolerance > 0 ? std::log(settings.tolerance) : eps_log_;
    S_dt_.resize(n1_ * n1_);  // transposed: column k of S is contiguous
    for (std::size_t j = 0; j < n1_; ++j)
      for (std::size_t k = 0; k < n1_; ++k) S_dt_[k * n1_ + j] = static_cast<double>(basis_.integral[j * n1_ + k]);
    Q_d_.resize((N_ + 2) * n1_);
    for (std::size_t k = 0; k < (N_ + 2) * n1_; ++k) Q_d_[k] = static_cast<double>(basis_.to_coeffs[k]);
    C_d_.resize(n1_ * n1_);
    for (std::size_t k = 0; k < n1_ * n1_; ++k) C_d_[k] = static_cast<double>(basis_.coeffs[k]);
    if constexpr (!std::is_same_v<T, double>) S_dd_ = detail::double_double_matrix(basis_.integral, n1_, n1_);
    for (int i = 0; i < 3; ++i) {
      X_[i].resize(n1_); F_[i].resize(n1_); Yc_[i].resize(n1_); Yn_[i].resize(n1_);
      r_[i].resize(n1_); delta_[i].resize(n1_); delta_new_[i].resize(n1_); g_[i].resize(n1_);
      Xd_[i].resize(n1_); warm_[i].resize(n1_);
    }
    acc_ = T(0);
    bd_.resize(N_ + 2);
    for (auto* v : {&F_hi_, &F_lo_, &Y_hi_, &Y_lo_}) v->resize(n1_);
    Fd_.resize(n1_);
    coeff_log_.resize(N_ + 2);
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

  dense_trajectory<T> run(const normalized_problem<T>& problem, const T& tau_end,
                          const progress_callback& progress = {}, picard_stats* stats = nullptr) {
    using std::abs;
    using std::sqrt;
    picard_stats st;
    st.degree = static_cast<unsigned>(N_);
    st.tolerance = std::exp(tol_log_);
    G_ = problem.G;
    if (!(tau_end > problem.tau0))
      throw std::invalid_argument("integrate_reference: tau_end must exceed tau0");

    std::vector<chebyshev_segment<T>> segs;
    vec3<T> x0 = problem.Omega0, c0{T(0), T(0), T(0)};
    T tau = problem.tau0;
    for (int i = 0; i < 3; ++i)
      if (!isfinite_(x0[i])) throw numerical_failure(to_d(tau), "initial state is not finite");

    double L = settings_.initial_step;
    if (!(L > 0)) {
      double rate = 0;
      for (int i = 0; i < 3; ++i)
        rate = std::max({rate, std::abs(to_d(x0[i])), std::sqrt(std::abs(to_d(G_[i])))});
      L = rate > 0 ? 0.5 / rate : 1.0;
    }
    bool have_prev = false;
    int consecutive_rejects = 0;
    // Length at which the iteration last failed to converge: growth stays below it, relaxing
    // slowly, so the tail estimate cannot push segments back into non-convergence every step.
    double L_cap = std::numeric_limits<double>::infinity();
    std::size_t since_progress = 0;

    while (tau < tau_end) {
      // Segment end in T; the final segment ends exactly at tau_end.
      T tau_b = tau + T(L);
      bool last = false;
      if (!(tau_b < tau_end) || to_d(tau_end - tau_b) < 1e-3 * L) {
        tau_b = tau_end;
        last = true;
      }
      const T hl = (tau_b - tau) / 2;
      const double L_used = to_d(tau_b - tau);
      make_warm_start(have_prev ? &segs.back() : nullptr, hl);

      const solve_result res = solve_segment(x0, c0, hl, st);
      double next_L = L_used;
      bool accept = res.converged;
      if (accept) {
        const tail_estimate te = estimate_tail(hl, res.scale_log);
        if (te.excess_log > std::log(8.0)) {
          accept = false;
          next_L = L_used * std::max(0.2, 0.8 * std::exp(-te.excess_log / double(N_ + 1)));
        } else {
          next_L = L_used * std::clamp(0.9 * std::exp(-te.excess_log / double(N_ + 1)), 0.5, 2.0);
        }
      } else {
        next_L = L_used * 0.5;
        L_cap = 0.8 * L_used;
      }
      if (!accept) {
        ++st.rejected;
        if (++consecutive_rejects > 40 || next_L < 1e-14 * std::max(1.0, std::abs(to_d(tau))))
          throw numerical_failure(
              to_d(tau), res.converged ? "segment length collapsed while the Chebyshev series would not converge"
                                       : "Picard iteration does not converge: " + res.why);
        L = next_L;
        continue;
      }
      consecutive_rejects = 0;

      // Accept: store the segment and advance with compensated summation (TwoSum).
      chebyshev_segment<T> seg;
      seg.tau_begin = tau;
      seg.tau_end = tau_b;
      seg.half_length = hl;
      seg.base = x0;
      seg.base_lo = c0;
      seg.values.resize(n1_);
      for (std::size_t j = 0; j < n1_; ++j)
        for (int i = 0; i < 3; ++i) seg.values[j][i] = Yn_[i][j];
      vec3<T> x1, c1;
      for (int i = 0; i < 3; ++i) {
        const T y = Yn_[i][N_] + c0[i];
        const T s = x0[i] + y;
        const T bb = s - x0[i];
        c1[i] = (x0[i] - (s - bb)) + (y - bb);
        x1[i] = s;
        if (!isfinite_(s)) throw numerical_failure(to_d(tau_b), "state is not finite");
      }
      segs.push_back(std::move(seg));
      have_prev = true;
      x0 = x1;
      c0 = c1;
      tau = tau_b;
      ++st.segments;
      if (st.segments > settings_.max_segments)
        throw numerical_failure(to_d(tau), "more than " + std::to_string(settings_.max_segments) + " segments");
      if (progress && (++since_progress >= 64 || last)) {
        progress(to_d(tau));
        since_progress = 0;
      }
      L_cap *= 1.05;
      L = std::min(next_L, L_cap);
      if (last) break;
    }
    if (stats) *stats = st;
    return dense_trajectory<T>(std::move(segs), basis_.nodes);
  }

 private:
  struct solve_result {
    bool converged = false;
    double scale_log = 0;  // log of the state scale max |Omega| on the segment
    std::string why;
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

  // Solves for the correction of the residual in r_ (largest entry r_max) and applies it to Yc.
  // Returns log(r_max), or NaN (with why) when the residual or the correction is not usable.
  double correct_from_residual(double r_max, double hl_d, picard_stats& st, std::string& why) {
    if (!std::isfinite(r_max)) {
      why = "non-finite residual";
      return std::numeric_limits<double>::quiet_NaN();
    }
    if (!solve_correction(hl_d, st, why)) return std::numeric_limits<double>::quiet_NaN();
    for (int i = 0; i < 3; ++i)
      for (std::size_t j = 1; j < n1_; ++j) Yc_[i][j] += T(delta_[i][j]);
    return r_max > 0 ? std::log(r_max) : -std::numeric_limits<double>::infinity();
  }

  // The first pass from the warm start, all in double: its residual is far above double
  // rounding, so computing it in T would buy nothing (for T = double this is the T pass itself).
  // Returns log of the residual, or NaN on failure.
  double double_pass(const vec3<T>& x0, const vec3<T>& c0, double hl_d, picard_stats& st, std::string& why) {
    vec3<double> x0d, dx;
    for (int i = 0; i < 3; ++i) x0d[i] = to_d(x0[i]) + to_d(c0[i]);
    const vec3<double> Gd{to_d(G_[0]), to_d(G_[1]), to_d(G_[2])};
    for (std::size_t j = 0; j < n1_; ++j) {
      vec3<double> x;
      for (int i = 0; i < 3; ++i) x[i] = Xd_[i][j] = x0d[i] + warm_[i][j];
      euler_rhs(x, Gd, dx);
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
    return correct_from_residual(r_max, hl_d, st, why);
  }

  // The second pass, for wide T: the residual in double-double (~1e-32 relative), enough to
  // drive the correction that follows to that level, at a fraction of a residual in T. The next
  // residual, in T, decides convergence. Returns log of the residual, or NaN on failure.
  double double_double_pass(const vec3<T>& x0, const vec3<T>& c0, const T& hl, picard_stats& st,
                            std::string& why) {
    const double hl_d = to_d(hl);
    for (std::size_t j = 0; j < n1_; ++j) {
      vec3<T> x, dx;
      for (int i = 0; i < 3; ++i) {
        x[i] = x0[i] + (c0[i] + Yc_[i][j]);
        Xd_[i][j] = to_d(x[i]);
      }
      euler_rhs(x, G_, dx);
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
    return correct_from_residual(r_max, hl_d, st, why);
  }

  // Solves the collocation problem on one segment from the warm start. On success Yn_ holds the
  // increments at the nodes and F_ the derivative there.
  solve_result solve_segment(const vec3<T>& x0, const vec3<T>& c0, const T& hl, picard_stats& st) {
    using std::abs;
    solve_result out;
    const double hl_d = to_d(hl);
    const std::size_t max_outer = 4 + significand_bits<T>() / 40;
    for (int i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < n1_; ++j) Yc_[i][j] = T(warm_[i][j]);

    double r_prev_log = std::numeric_limits<double>::infinity();
    if constexpr (!std::is_same_v<T, double>) {
      r_prev_log = double_pass(x0, c0, hl_d, st, out.why);
      if (std::isnan(r_prev_log)) return out;
      const double r_dd_log = double_double_pass(x0, c0, hl, st, out.why);
      if (std::isnan(r_dd_log)) return out;
      if (r_dd_log > r_prev_log - std::log(2.0)) {
        out.why = "residual does not decrease";
        return out;
      }
      r_prev_log = r_dd_log;
    }
    for (std::size_t outer = 0;; ++outer) {
      // X = x0 + (c0 + Yc);  F = f(X)  (Eq. 5).
      double scale = 0;
      for (std::size_t j = 0; j < n1_; ++j) {
        vec3<T> x, dx;
        for (int i = 0; i < 3; ++i) {
          x[i] = x0[i] + (c0[i] + Yc_[i][j]);
          Xd_[i][j] = to_d(x[i]);
          scale = std::max(scale, std::abs(Xd_[i][j]));
        }
        euler_rhs(x, G_, dx);
        for (int i = 0; i < 3; ++i) F_[i][j] = dx[i];
      }
      if (!std::isfinite(scale)) {
        out.why = "non-finite state in the iteration";
        return out;
      }
      scale = std::max(scale, 1e-300);
      out.scale_log = std::log(scale);
      // Yn = hl S F in T; r = Yn - Yc.
      ++st.wide_residuals;
      double r_max = 0;
      for (int i = 0; i < 3; ++i) {
        Yn_[i][0] = 0;
        for (std::size_t j = 1; j < n1_; ++j) {
          const T* row = &basis_.integral[j * n1_];
          acc_ = 0;
          for (std::size_t k = 0; k < n1_; ++k) acc_ += row[k] * F_[i][k];
          acc_ *= hl;
          Yn_[i][j] = acc_;
          acc_ -= Yc_[i][j];
          r_[i][j] = to_d(acc_);
          r_max = std::max(r_max, std::abs(r_[i][j]));
        }
        r_[i][0] = 0;
      }
      if (!std::isfinite(r_max)) {
        out.why = "non-finite residual";
        return out;
      }
      const double r_log = r_max > 0 ? std::log(r_max) : -std::numeric_limits<double>::infinity();
      // Converged: residual within the tolerance or at the rounding level of one residual
      // evaluation (a sum of N+1 rounded terms: ~sqrt(N+1) eps), or stagnant near that floor.
      const double rounding_log = eps_log_ + std::log(4.0 * std::sqrt(double(n1_))) + out.scale_log;
      const double floor_log = eps_log_ + std::log(64.0 * n1_) + out.scale_log;
      if (r_log <= std::max(tol_log_ + out.scale_log, rounding_log) ||
          (r_log <= floor_log && r_log > r_prev_log - std::log(16.0))) {
        out.converged = true;
        break;
      }
      if (outer + 1 >= max_outer || (r_prev_log < std::numeric_limits<double>::infinity() &&
                                     r_log > r_prev_log - std::log(2.0))) {
        out.why = "residual " + std::to_string(r_max) + " after " + std::to_string(outer + 1) + " passes";
        return out;
      }
      r_prev_log = r_log;
      if (std::isnan(correct_from_residual(r_max, hl_d, st, out.why))) return out;
    }
    return out;
  }

  // y_i = S g_i (rows 1..N) for the three components in double. Column order (y += S[:,k] g[k])
  // keeps the rows independent, so the compiler vectorizes across them without reassociating
  // any sum (a row-by-row dot product is bound by the latency of its serial additions).
  void double_integral(const std::array<std::vector<double>, 3>& g, std::array<std::vector<double>, 3>& y) const {
    for (int i = 0; i < 3; ++i) {
      double* out = y[i].data();
      std::fill(out, out + n1_, 0.0);
      for (std::size_t k = 0; k < n1_; ++k) {
        const double* col = &S_dt_[k * n1_];
        const double gk = g[i][k];
        for (std::size_t j = 0; j < n1_; ++j) out[j] += col[j] * gk;
      }
    }
  }

  // delta = r + hl S [J(Xd) delta + f_2(delta)] by Picard sweeps in double, where for Eq. 5
  // f(x + d) - f(x) = (-(x2 d3 + x3 d2 + d2 d3), x1 d3 + x3 d1 + d1 d3, -(x1 d2 + x2 d1 + d1 d2)).
  bool solve_correction(double hl_d, picard_stats& st, std::string& why) {
    for (int i = 0; i < 3; ++i) delta_[i] = r_[i];
    double prev_diff = std::numeric_limits<double>::infinity();
    double first_diff = -1;
    for (int sweep = 0; sweep < 200; ++sweep) {
      ++st.double_sweeps;
      for (std::size_t k = 0; k < n1_; ++k) {
        const double d1 = delta_[0][k], d2 = delta_[1][k], d3 = delta_[2][k];
        const double x1 = Xd_[0][k], x2 = Xd_[1][k], x3 = Xd_[2][k];
        g_[0][k] = -(x2 * d3 + x3 * d2 + d2 * d3);
        g_[1][k] = x1 * d3 + x3 * d1 + d1 * d3;
        g_[2][k] = -(x1 * d2 + x2 * d1 + d1 * d2);
      }
      double diff = 0, dmax = 0;
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
      if (!std::isfinite(diff)) {
        why = "double-precision correction diverged";
        return false;
      }
      if (first_diff < 0) first_diff = diff;
      if (diff <= 4e-16 * dmax) return true;
      // Stagnant at double rounding: done. Growing: the segment is too long.
      if (sweep > 4 && diff >= 0.7 * prev_diff) {
        if (diff <= 1e-12 * dmax) return true;
        if (diff > first_diff) {
          why = "double-precision correction diverged";
          return false;
        }
      }
      prev_diff = diff;
    }
    why = "double-precision correction did not converge in 200 sweeps";
    return false;
  }

  // Truncation estimate from the decay of the Chebyshev coefficients b_k of the increment
  // (b = hl Q F): a least-squares line through log max_i |b_k| over the coefficients above their
  // rounding floor, evaluated at k = N+1, and the last coefficients themselves; compared with
  // tol * scale. The head b_0..b_{N-3} is formed in double (it only has to show the decay rate);
  // the last four in T, since they must be resolved down to the tolerance.
  tail_estimate estimate_tail(const T& hl, double scale_log) {
    const std::size_t nb = N_ + 2, tail_from = N_ - 2;
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
      for (std::size_t k = tail_from; k < nb; ++k) {
        const T* row = &basis_.to_coeffs[k * n1_];
        acc_ = 0;
        for (std::size_t j = 0; j < n1_; ++j) acc_ += row[j] * F_[i][j];
        acc_ *= hl;
        coeff_log_[k] = std::max(coeff_log_[k], detail::log_abs(acc_));
      }
    }
    const double head_noise = std::log(std::max(head_max, 1e-300) * 8.0 * n1_ * 2.2e-16);
    const double tail_noise = eps_log_ + scale_log + std::log(4.0 * n1_);
    for (std::size_t k = 0; k < nb; ++k) noise_log_[k] = k < tail_from ? std::max(head_noise, tail_noise) : tail_noise;
    // Envelope over neighbours: odd/even parts of the series vanish alternately.
    for (std::size_t k = 1; k + 1 < nb; ++k) coeff_log_[k] = std::max(coeff_log_[k], coeff_log_[k + 1]);
    const double target = tol_log_ + scale_log;
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

  picard_settings settings_;
  std::size_t N_, n1_;
  detail::chebyshev_basis<T> basis_;
  double eps_ = 0, eps_log_ = 0, tol_log_ = 0;
  std::vector<double> S_dt_;
  vec3<T> G_{};
  std::array<std::vector<T>, 3> X_, F_, Yc_, Yn_;
  std::array<std::vector<double>, 3> r_, delta_, delta_new_, g_, Xd_, warm_;
  std::vector<double> Q_d_, C_d_;
  detail::double_double_matrix S_dd_;
  std::vector<double> F_hi_, F_lo_, Y_hi_, Y_lo_;
  std::vector<double> bd_, Fd_, coeff_log_, noise_log_;
  T acc_;
};

// Integrates Eq. 5 from problem.tau0 to tau_end (> tau0). Throws numerical_failure.
template <class T>
dense_trajectory<T> integrate_reference(const normalized_problem<T>& problem, const T& tau_end,
                                        const picard_settings& settings = {},
                                        const progress_callback& progress = {},
                                        picard_stats* stats = nullptr) {
  chebyshev_picard<T> integrator(settings);
  return integrator.run(problem, tau_end, progress, stats);
}

}  // namespace eulervop

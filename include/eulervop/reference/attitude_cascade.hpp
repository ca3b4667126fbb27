// The attitude beside the rates (docs/attitude.md): q' = 1/2 q (x) (0, omega), omega in body
// axes, integrated segment by segment on the rates' own Chebyshev-Picard segments.
//
// For a body-fixed torque the rates do not depend on q, so the two form a cascade: once a rates
// segment is accepted, its node values give omega at the nodes, and q on the segment solves the
// linear problem Q = q_a + hl S (1/2 Q (x) W) at the same Lobatto nodes (W = omega per unit of the
// integrator's time). It is solved as the rates are (docs/design.md section 3.2): Picard sweeps
// in double from the previous segment's extrapolation, a residual in double-double, then residuals
// in T, each followed by a correction solved in double; since the problem is linear in q, a
// residual after a correction is also the previous one moved exactly by the correction's image
// (formed in double-double, used where its error lies far below the tolerance, as in quad). The end value is
// carried to the next segment with TwoSum compensation. Where q varies faster than the rates (a
// body spinning about a nearly symmetric axis turns much faster than its rates change), q's
// series on the segment is checked like the rates' (tail_estimator): the integrator asks
// try_segment before it accepts a segment, and a segment too long for q is shortened and solved
// again, as one too long for the rates would be.
//
// The output is the combined segment of dimension 7, (y, q), for the same samplers as the rates.
#pragma once

#include <eulervop/core/error_free.hpp>
#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/model/body_rates.hpp>
#include <eulervop/reference/detail/length_control.hpp>
#include <eulervop/reference/detail/picard_matrices.hpp>
#include <eulervop/reference/detail/tail_estimator.hpp>
#include <eulervop/reference/detail/warm_start.hpp>
#include <eulervop/reference/segment.hpp>
#include <eulervop/reference/settings.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace eulervop {

struct attitude_stats {
  std::size_t segments = 0;        // segments on which q was solved (refused ones included)
  std::size_t refused = 0;         // rates segments q found too long
  std::size_t wide_residuals = 0;  // residuals of q in T
};

template <scalar T>
class attitude_cascade {
 public:
  using combined_segment = chebyshev_segment<T, 7>;

  // q0: the attitude at the rates' start, normalized by the caller; `settings`: the rates' (the
  // same tolerance holds for q).
  attitude_cascade(const quaternion<T>& q0, const body_rates<T>& rates, const picard_settings& settings)
      : rates_(rates), settings_(settings) {
    q_ = {q0.w, q0.x, q0.y, q0.z};
    q_lo_.fill(T(0));
    // Half the rates once here: q' = q (x) (0, W/2), with no halving per node (exact: by 2).
    if (rates_.identity) rates_.scale = {T(1), T(1), T(1)};
    rates_.identity = false;
    for (int i = 0; i < 3; ++i) rates_.scale[i] /= 2;
  }

  const attitude_stats& stats() const { return stats_; }

  // Solves q on a candidate rates segment (not yet accepted); true when q converged on it and
  // its series is resolved, false when the segment is too long for q (or q does not converge).
  bool try_segment(const chebyshev_segment<T>& seg, const std::vector<T>& nodes);

  // The accepted segment `seg` (after a successful try_segment on it): the combined (y, q)
  // segment, valid until the next call; q moves to the segment's end.
  const combined_segment& commit(const chebyshev_segment<T>& seg);

 private:
  using quat4 = std::array<T, 4>;
  using narrow = std::array<std::vector<double>, 4>;
  using wide = std::array<std::vector<T>, 4>;

  void init(const std::vector<T>& nodes) {
    n1_ = nodes.size();
    N_ = n1_ - 1;
    const unsigned bits = detail::effective_bits<T>(settings_);
    matrices_.emplace(N_, bits);
    eps_log_ = detail::log_abs(epsilon<T>());
    tol_log_ = settings_.tolerance > 0 ? std::log(settings_.tolerance) : eps_log_;
    tail_.emplace(N_, eps_log_, std::max(tol_log_ - std::log(16.0), eps_log_));
    warm_.emplace(N_);
    for (auto* set : {&Zd_, &G_, &R_, &next_, &warm_d_, &c_, &Fhi_, &Flo_, &Wd_, &Wl_})
      for (auto& v : *set) v.assign(n1_, 0.0);
    Yhi_.assign(n1_, 0.0);
    Ylo_.assign(n1_, 0.0);
    q_node_.fill(T(0));
    for (auto* set : {&Z_, &F_, &Yn_})
      for (auto& v : *set) v.assign(n1_, T(0));
    W_.assign(n1_, vec3<T>{T(0), T(0), T(0)});
    y_.assign(n1_, vec3<T>{T(0), T(0), T(0)});
    acc_ = T(0);
    ready_ = true;
  }

  // Solves q on a segment of half length hl from q_ with y at its nodes; true when its residual
  // converged and its series passes the tail test (then Yn_ holds the increments). The passes
  // climb as the rates' do: Picard sweeps in double from the warm start, a residual in
  // double-double and its correction, then residuals in T, each with its correction, until one
  // converges.
  bool solve_piece(const std::vector<vec3<T>>& y, const T& hl) {
    for (std::size_t j = 0; j < n1_; ++j) {
      W_[j] = rates_(y[j]);  // W/2: the scale was halved at construction
      for (std::size_t i = 0; i < 3; ++i) {
        Wd_[i][j] = static_cast<double>(W_[j][i]);
        acc_ = W_[j][i];
        acc_ -= Wd_[i][j];
        Wl_[i][j] = static_cast<double>(acc_);
      }
    }
    const double hl_d = static_cast<double>(hl);
    (*warm_)(*matrices_, have_previous_ ? &previous_ : nullptr, hl, warm_d_);
    for (std::size_t i = 0; i < 4; ++i) Zd_[i] = warm_d_[i];
    std::array<double, 4> qa_d;
    for (std::size_t i = 0; i < 4; ++i) qa_d[i] = static_cast<double>(q_[i]) + static_cast<double>(q_lo_[i]);
    if (!sweeps(Zd_, qa_d, hl_d, false)) return false;
    double r_prev_log = std::numeric_limits<double>::infinity();
    if constexpr (std::is_same_v<T, double>) {
      Z_ = Zd_;  // in double the sweeps' solution is the first iterate
    } else {
      r_prev_log = log_of(double_double_residual(hl));
      if (!sweeps(R_, {0.0, 0.0, 0.0, 0.0}, hl_d, true)) return false;
      for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t j = 0; j < n1_; ++j) {
          Z_[i][j] = T(Zd_[i][j]);
          add_double(Z_[i][j], R_[i][j]);
        }
    }
    const std::size_t max_passes = 4 + significand_bits<T>() / 40;
    ++stats_.wide_residuals;
    double r_log = log_of(wide_residual(hl));
    for (std::size_t pass = 1; !converged(r_log, r_prev_log); ++pass) {
      if (pass >= max_passes || r_log > r_prev_log - std::log(2.0)) return false;
      r_prev_log = r_log;
      // The correction must be right to the tolerance, not to its own last digit.
      if (!sweeps(R_, {0.0, 0.0, 0.0, 0.0}, hl_d, true, 0.125 * std::exp(std::max(tol_log_, eps_log_)))) return false;
      // An update where its error, 2^-100 of this residual, lies 2^-20 below the tolerance
      // (quad after its first residual); a new residual in T otherwise (deep MPFR).
      if (!std::is_same_v<T, double> &&
          r_log - 100 * std::log(2.0) <= std::max(tol_log_, eps_log_) - 20 * std::log(2.0)) {
        r_log = log_of(updated_residual(hl));
        continue;
      }
      for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t j = 1; j < n1_; ++j) add_double(Z_[i][j], R_[i][j]);
      ++stats_.wide_residuals;
      r_log = log_of(wide_residual(hl));
    }
    ++stats_.segments;
    return tail_->excess_log(*matrices_, F_, hl, 0.0) <= std::log(8.0);
  }

  // x = c + hl S ((b + x) (x) (0, W/2)) by Picard sweeps in double, c = x's start value when
  // `correction` (then b = 0), else c = 0; true when the change fell to double rounding, or
  // below `enough` (absolute: a correction far below the tolerance needs only its leading digits).
  bool sweeps(narrow& x, const std::array<double, 4>& b, double hl_d, bool correction, double enough = 0) {
    if (correction) c_ = x;
    double prev = std::numeric_limits<double>::infinity(), first = -1;
    const double *w1 = Wd_[0].data(), *w2 = Wd_[1].data(), *w3 = Wd_[2].data();
    for (int sweep = 0; sweep < 400; ++sweep) {
      for (std::size_t j = 0; j < n1_; ++j) {
        const double qw = b[0] + x[0][j], qx = b[1] + x[1][j], qy = b[2] + x[2][j], qz = b[3] + x[3][j];
        G_[0][j] = -(qx * w1[j] + qy * w2[j] + qz * w3[j]);
        G_[1][j] = qw * w1[j] + qy * w3[j] - qz * w2[j];
        G_[2][j] = qw * w2[j] - qx * w3[j] + qz * w1[j];
        G_[3][j] = qw * w3[j] + qx * w2[j] - qy * w1[j];
      }
      matrices_->double_integral(G_, next_);
      double diff = 0, big = 0;
      for (std::size_t i = 0; i < 4; ++i) {
        next_[i][0] = 0;
        const double* ci = c_[i].data();
        for (std::size_t j = 1; j < n1_; ++j) {
          const double v = (correction ? ci[j] : 0.0) + hl_d * next_[i][j];
          diff = std::max(diff, std::abs(v - x[i][j]));
          big = std::max(big, std::abs(v));
          next_[i][j] = v;
        }
      }
      std::swap(x, next_);
      if (!std::isfinite(diff)) return false;
      if (first < 0) first = diff;
      if (diff <= std::max(4e-16 * std::max(big, correction ? 0.0 : 1.0), enough)) return true;
      if (sweep > 4 && diff >= 0.7 * prev) return diff <= 1e-12 * std::max(big, 1.0) || diff <= first;
      prev = diff;
    }
    return false;
  }

  // The residual from the double solve Zd_, in double-double: Q = q_a + Zd_ and W/2 in
  // double-double, F = Q (x) (0, W/2), Y = hl S F (S in double-double); R = Y - Zd_ in double,
  // about 2^-100 of Y from the truth: enough to drive the correction that follows to that level.
  double double_double_residual(const T& hl) {
    std::array<double_double, 4> qa;
    for (std::size_t i = 0; i < 4; ++i) {
      acc_ = q_[i];
      acc_ += q_lo_[i];
      const double hi = static_cast<double>(acc_);
      acc_ -= hi;
      qa[i] = {hi, static_cast<double>(acc_)};
    }
    acc_ = hl;
    const double hl_hi = static_cast<double>(hl);
    acc_ -= hl_hi;
    const double_double hl_dd{hl_hi, static_cast<double>(acc_)};
    for (std::size_t j = 0; j < n1_; ++j) {
      std::array<double_double, 4> q;
      for (std::size_t i = 0; i < 4; ++i) q[i] = add(qa[i], double_double{Zd_[i][j], 0.0});
      const double_double w1{Wd_[0][j], Wl_[0][j]}, w2{Wd_[1][j], Wl_[1][j]}, w3{Wd_[2][j], Wl_[2][j]};
      const std::array<double_double, 4> f = {
          negated(add(add(mul(q[1], w1), mul(q[2], w2)), mul(q[3], w3))),
          add(add(mul(q[0], w1), mul(q[2], w3)), negated(mul(q[3], w2))),
          add(add(mul(q[0], w2), negated(mul(q[1], w3))), mul(q[3], w1)),
          add(add(mul(q[0], w3), mul(q[1], w2)), negated(mul(q[2], w1)))};
      for (std::size_t i = 0; i < 4; ++i) {
        const double_double hf = mul(f[i], hl_dd);
        Fhi_[i][j] = hf.hi;
        Flo_[i][j] = hf.lo;
      }
    }
    double r_max = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      matrices_->S_dd.multiply(Fhi_[i].data(), Flo_[i].data(), Yhi_.data(), Ylo_.data(), 1);
      R_[i][0] = 0;
      for (std::size_t j = 1; j < n1_; ++j) {
        R_[i][j] = (Yhi_[j] - Zd_[i][j]) + Ylo_[j];
        r_max = std::max(r_max, std::abs(R_[i][j]));
      }
    }
    return r_max;
  }

  // After a correction delta (in R_) to Z, the new residual without a new one in T: the Picard
  // map is linear in q, so it moves by exactly U = hl S (delta (x) (0, W/2)), formed in
  // double-double from delta and W/2 (its error, about 2^-100 |U| with |U| ~ |delta| ~ 1e-16 |Z|
  // after the first residual in T, lies thirty orders below quad's rounding). Yn += U, Z += delta,
  // R = Yn - Z in T. Returns max |R|.
  double updated_residual(const T& hl) {
    acc_ = hl;
    const double hl_hi = static_cast<double>(hl);
    acc_ -= hl_hi;
    const double_double hl_dd{hl_hi, static_cast<double>(acc_)};
    for (std::size_t j = 0; j < n1_; ++j) {
      const double d0 = R_[0][j], d1 = R_[1][j], d2 = R_[2][j], d3 = R_[3][j];
      const double_double w1{Wd_[0][j], Wl_[0][j]}, w2{Wd_[1][j], Wl_[1][j]}, w3{Wd_[2][j], Wl_[2][j]};
      const std::array<double_double, 4> u = {
          negated(add(add(mul(w1, d1), mul(w2, d2)), mul(w3, d3))), add(add(mul(w1, d0), mul(w3, d2)), negated(mul(w2, d3))),
          add(add(mul(w2, d0), negated(mul(w3, d1))), mul(w1, d3)), add(add(mul(w3, d0), mul(w2, d1)), negated(mul(w1, d2)))};
      for (std::size_t i = 0; i < 4; ++i) {
        const double_double hu = mul(u[i], hl_dd);
        Fhi_[i][j] = hu.hi;
        Flo_[i][j] = hu.lo;
      }
    }
    // The tail test reads F at the converged iterate: in quad the correction lies below the tail's
    // rounding floor (4 (N+1) eps), in MPFR far above it, so there F moves with Z.
    if constexpr (std::is_same_v<T, mpfr_real>)
      for (std::size_t j = 0; j < n1_; ++j) {
        const quaternion<T> d{T(R_[0][j]), T(R_[1][j]), T(R_[2][j]), T(R_[3][j])};
        const quaternion<T> g = d * quaternion<T>{T(0), W_[j][0], W_[j][1], W_[j][2]};
        F_[0][j] += g.w;
        F_[1][j] += g.x;
        F_[2][j] += g.y;
        F_[3][j] += g.z;
      }
    double r_max = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      matrices_->S_dd.multiply(Fhi_[i].data(), Flo_[i].data(), Yhi_.data(), Ylo_.data(), 1);
      for (std::size_t j = 1; j < n1_; ++j) {
        add_double(Yn_[i][j], Yhi_[j]);
        add_double(Yn_[i][j], Ylo_[j]);
        add_double(Z_[i][j], R_[i][j]);
        acc_ = Yn_[i][j];
        acc_ -= Z_[i][j];
        R_[i][j] = static_cast<double>(acc_);
        r_max = std::max(r_max, std::abs(R_[i][j]));
      }
    }
    return r_max;
  }

  // F = Q (x) (0, W/2) at the nodes and Yn = hl S F in T; R = Yn - Z in double. Returns max |R|.
  double wide_residual(const T& hl) {
    for (std::size_t j = 0; j < n1_; ++j) {
      for (std::size_t i = 0; i < 4; ++i) {
        q_node_[i] = q_lo_[i];
        q_node_[i] += Z_[i][j];
        q_node_[i] += q_[i];
      }
      const vec3<T>& w = W_[j];
      F_[0][j] = -(q_node_[1] * w[0] + q_node_[2] * w[1] + q_node_[3] * w[2]);
      F_[1][j] = q_node_[0] * w[0] + q_node_[2] * w[2] - q_node_[3] * w[1];
      F_[2][j] = q_node_[0] * w[1] - q_node_[1] * w[2] + q_node_[3] * w[0];
      F_[3][j] = q_node_[0] * w[2] + q_node_[1] * w[1] - q_node_[2] * w[0];
    }
    double r_max = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      Yn_[i][0] = 0;
      if constexpr (!std::is_same_v<T, double>) {
        matrices_->S_fx.multiply(F_[i].data(), Yn_[i].data(), 1);
        for (std::size_t j = 1; j < n1_; ++j) Yn_[i][j] *= hl;
      } else {
        for (std::size_t j = 1; j < n1_; ++j) {
          const T* row = &matrices_->basis.integral[j * n1_];
          acc_ = 0;
          for (std::size_t k = 0; k < n1_; ++k) acc_ += row[k] * F_[i][k];
          Yn_[i][j] = acc_ * hl;
        }
      }
      R_[i][0] = 0;
      for (std::size_t j = 1; j < n1_; ++j) {
        acc_ = Yn_[i][j];
        acc_ -= Z_[i][j];
        R_[i][j] = static_cast<double>(acc_);
        r_max = std::max(r_max, std::abs(R_[i][j]));
      }
    }
    return r_max;
  }

  // As the rates' test: within the tolerance or at the rounding level of one residual (|q| = 1),
  // or stagnant near that floor.
  bool converged(double r_log, double r_prev_log) const {
    const double rounding_log = eps_log_ + std::log(4.0 * std::sqrt(double(n1_)));
    const double floor_log = eps_log_ + std::log(64.0 * n1_);
    return r_log <= std::max(tol_log_, rounding_log) || (r_log <= floor_log && r_log > r_prev_log - std::log(16.0));
  }

  // q_ moves to the segment's end (its last increment), with TwoSum compensation; the segment
  // becomes the next warm start.
  void advance() {
    previous_.values.resize(n1_);
    for (std::size_t j = 0; j < n1_; ++j)
      for (std::size_t i = 0; i < 4; ++i) previous_.values[j][i] = Yn_[i][j];
    previous_.base = q_;
    previous_.base_lo = q_lo_;
    have_previous_ = true;
    for (std::size_t i = 0; i < 4; ++i) {
      const T y = Yn_[i][N_] + q_lo_[i];
      T s, e, bb;
      two_sum(q_[i], y, s, e, bb);
      q_[i] = s;
      q_lo_[i] = e;
    }
  }

  static void add_double(T& x, double d) {
    if constexpr (std::is_same_v<T, mpfr_real>)
      mpfr_add_d(x.backend().data(), x.backend().data(), d, MPFR_RNDN);
    else
      x += d;
  }
  static double log_of(double r) { return r > 0 ? std::log(r) : -std::numeric_limits<double>::infinity(); }

  body_rates<T> rates_;
  picard_settings settings_;
  bool ready_ = false;
  std::size_t N_ = 0, n1_ = 0;
  std::optional<detail::picard_matrices<T>> matrices_;
  std::optional<detail::tail_estimator<T>> tail_;
  std::optional<detail::warm_start<T, 4>> warm_;
  double eps_log_ = 0, tol_log_ = 0;
  quat4 q_, q_lo_;                      // q at the current start, and its compensation
  std::vector<vec3<T>> W_;              // half of omega per unit time at the nodes, in T
  narrow Wd_{}, Wl_{};                  // the same in double-double (components 0..2 used)
  narrow Zd_, G_, R_, next_, warm_d_, c_, Fhi_, Flo_;
  std::vector<double> Yhi_, Ylo_;
  quat4 q_node_;
  wide Z_, F_, Yn_;
  std::vector<vec3<T>> y_;              // the rates at the nodes, in T
  chebyshev_segment<T, 4> previous_;    // q on the last accepted segment: the warm start
  bool have_previous_ = false;
  bool pending_ = false;                // try_segment succeeded, commit not yet called
  combined_segment combined_;
  attitude_stats stats_;
  T acc_;
};

// Out of the class, so that a unit that declares the cascade extern (reference/integrate.hpp)
// compiles none of its solver, which the compiled kernels hold once per scalar.
template <scalar T>
bool attitude_cascade<T>::try_segment(const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
  if (!ready_) init(nodes);
  std::vector<vec3<T>>& y = y_;
  for (std::size_t j = 0; j < n1_; ++j)
    for (std::size_t i = 0; i < 3; ++i) y[j][i] = seg.base[i] + (seg.base_lo[i] + seg.values[j][i]);
  pending_ = solve_piece(y, seg.half_length);
  if (!pending_) ++stats_.refused;
  return pending_;
}

template <scalar T>
auto attitude_cascade<T>::commit(const chebyshev_segment<T>& seg) -> const combined_segment& {
  if (!pending_) throw std::logic_error("attitude_cascade: commit without a successful try_segment");
  pending_ = false;
  combined_.tau_begin = seg.tau_begin;
  combined_.tau_end = seg.tau_end;
  combined_.half_length = seg.half_length;
  for (std::size_t i = 0; i < 3; ++i) {
    combined_.base[i] = seg.base[i];
    combined_.base_lo[i] = seg.base_lo[i];
  }
  for (std::size_t i = 0; i < 4; ++i) {
    combined_.base[3 + i] = q_[i];
    combined_.base_lo[3 + i] = q_lo_[i];
  }
  combined_.values.resize(n1_);
  for (std::size_t j = 0; j < n1_; ++j) {
    for (std::size_t i = 0; i < 3; ++i) combined_.values[j][i] = seg.values[j][i];
    for (std::size_t i = 0; i < 4; ++i) combined_.values[j][3 + i] = Yn_[i][j];
  }
  advance();
  return combined_;
}

}  // namespace eulervop

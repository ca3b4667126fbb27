// The truncation estimate of one segment: how far the Chebyshev series of the segment's
// increment is from having decayed below the tolerance. It drives the segment length
// (length_control.hpp).
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/detail/length_control.hpp>
#include <eulervop/reference/detail/picard_matrices.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>
#include <vector>

namespace eulervop::detail {

template <scalar T>
class tail_estimator {
 public:
  // `eps_log`: log epsilon of T; `target_log`: log of the relative truncation allowed per segment.
  tail_estimator(std::size_t degree, double eps_log, double target_log)
      : N_(degree), n1_(degree + 1), eps_log_(eps_log), target_log_(target_log) {
    coeff_log_.resize(N_ + 2);
    noise_log_.resize(N_ + 2);
    Fd_.resize(n1_);
    head_abs_.resize(N_ + 2);
    if constexpr (!std::is_same_v<T, double>) tail_.resize(N_ + 2);
    acc_ = T(0);
  }

  // The log of the estimated truncation over tol * scale (<= 0: within the tolerance), from the
  // decay of the Chebyshev coefficients b_k of the increment b = hl Q F (F the derivative at the
  // nodes, per component): a least-squares line through log max_i |b_k| over the coefficients
  // above their rounding floor, evaluated at k = N+1, and the last coefficients themselves.
  // `dF`, if set, is a small change of F in double (the increment of a correction that settled
  // the segment, chebyshev_picard.hpp): the coefficients are those of F + dF, with dF's share
  // formed in double.
  template <std::size_t D>
  double excess_log(picard_matrices<T>& m, const std::array<std::vector<T>, D>& F, const T& hl,
                    double scale_log, const std::array<std::vector<double>, D>* dF = nullptr) {
    const std::size_t nb = N_ + 2, tail_from = N_ - 2;
    const double head_max = coefficient_logs(m, F, dF, hl, tail_from);
    const double head_noise = std::log(std::max(head_max, 1e-300) * 8.0 * n1_ * 2.2e-16);
    const double tail_noise = eps_log_ + scale_log + std::log(4.0 * n1_);
    for (std::size_t k = 0; k < nb; ++k) noise_log_[k] = k < tail_from ? std::max(head_noise, tail_noise) : tail_noise;
    // Envelope over neighbours: odd/even parts of the series vanish alternately.
    for (std::size_t k = 1; k + 1 < nb; ++k) coeff_log_[k] = std::max(coeff_log_[k], coeff_log_[k + 1]);
    return excess_of_fit(tail_noise, target_log_ + scale_log);
  }

 private:
  // The coefficient at k = N + 1 predicted by the fitted decay, and never below the last resolved
  // coefficient, over the target (logs).
  double excess_of_fit(double tail_noise, double target) const {
    const std::size_t nb = N_ + 2;
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
    const double last = coeff_log_[nb - 1];
    const bool last_resolved = last > tail_noise + margin;
    if (n >= 3) {
      const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
      const double icpt = (sy - slope * sx) / n;
      double pred = icpt + slope * static_cast<double>(nb - 1);
      if (slope >= 0) pred = last;  // no decay seen: trust only the actual tail
      return std::max(pred, last_resolved ? last : pred) - target;
    }
    // Everything but the first coefficients is at the rounding floor: the series converges much
    // faster than needed, so let the segment grow (the caller caps growth at 2x).
    return last_resolved ? last - target : -std::log(4.0) * double(N_ + 1);
  }

  // coeff_log_[k] = log max_i |b_k| for k >= 1. The head b_1..b_{tail_from - 1} is formed in
  // double (it only has to show the decay rate); the tail in T, since it must be resolved down
  // to the tolerance. Returns the largest head coefficient.
  template <std::size_t D>
  double coefficient_logs(picard_matrices<T>& m, const std::array<std::vector<T>, D>& F,
                          const std::array<std::vector<double>, D>* dF, const T& hl, std::size_t tail_from) {
    const double hl_d = static_cast<double>(hl);
    std::fill(coeff_log_.begin(), coeff_log_.end(), -std::numeric_limits<double>::infinity());
    // The head's largest |b_k| over the components first, then one log per k, a third of the logs:
    // mathematically the largest log. A log not correctly rounded could differ from the largest
    // of the separate logs in its last bit; these logs only fit the decay's slope and set the
    // segment's length, and every shipped scene's output is byte-identical to the one-log-per-
    // component way (tools/golden_outputs.sh).
    std::fill(head_abs_.begin(), head_abs_.end(), 0.0);
    for (std::size_t i = 0; i < D; ++i) {
      for (std::size_t j = 0; j < n1_; ++j) Fd_[j] = static_cast<double>(F[i][j]) + (dF ? (*dF)[i][j] : 0.0);
      for (std::size_t k = 1; k < tail_from; ++k) {
        const double* row = &m.Q_d[k * n1_];
        double a = 0;
        for (std::size_t j = 0; j < n1_; ++j) a += row[j] * Fd_[j];
        head_abs_[k] = std::max(head_abs_[k], std::abs(a * hl_d));
      }
      tail_logs(m, F[i], dF ? &(*dF)[i] : nullptr, hl, tail_from);
    }
    double head_max = 0;
    for (std::size_t k = 1; k < tail_from; ++k) {
      const double a = head_abs_[k];
      head_max = std::max(head_max, a);
      coeff_log_[k] = a > 0 ? std::log(a) : -std::numeric_limits<double>::infinity();
    }
    return head_max;
  }

  // The tail coefficients b_tail_from .. b_{N+1} of one component, in T (dF's share in double).
  void tail_logs(picard_matrices<T>& m, const std::vector<T>& F, const std::vector<double>* dF, const T& hl,
                 std::size_t tail_from) {
    const std::size_t nb = N_ + 2;
    if constexpr (!std::is_same_v<T, double>) {
      m.Q_fx.multiply(F.data(), tail_.data(), tail_from);
      for (std::size_t k = tail_from; k < nb; ++k) {
        if (dF) {
          const double* row = &m.Q_d[k * n1_];
          double d = 0;
          for (std::size_t j = 0; j < n1_; ++j) d += row[j] * (*dF)[j];
          tail_[k] += d;
        }
        coeff_log_[k] = std::max(coeff_log_[k], log_abs(T(tail_[k] * hl)));
      }
    } else {
      for (std::size_t k = tail_from; k < nb; ++k) {
        const T* row = &m.basis.to_coeffs[k * n1_];
        acc_ = 0;
        for (std::size_t j = 0; j < n1_; ++j) acc_ += row[j] * (dF ? F[j] + (*dF)[j] : F[j]);
        acc_ *= hl;
        coeff_log_[k] = std::max(coeff_log_[k], log_abs(acc_));
      }
    }
  }

  std::size_t N_, n1_;
  double eps_log_, target_log_;
  std::vector<double> coeff_log_, noise_log_;  // log |b_k| and its rounding floor
  std::vector<double> Fd_;                     // one component of F in double
  std::vector<double> head_abs_;               // max over the components of |b_k|, k in the head
  std::vector<T> tail_;                        // the tail coefficients of one component (wide T)
  T acc_;
};

}  // namespace eulervop::detail

// The bounds of a segment's Jacobian J (D x D Chebyshev models over the segment) that the general
// path's a-priori bound and Lohner box take (ball_certifier.hpp, step 3), in the weighted norm
// |W v|_2, W = diag(weight): there W J W^-1 has the entries J_ik w_i / w_k, and
//   jmax >= its 2-norm (the Frobenius norm, from the ranges of the entries);
//   mu+ >= max(0, the largest eigenvalue of its symmetric part) (Gershgorin's theorem on the ranges
//   of the symmetric part's entries: where w_i = w_k, of the range of J_ik + J_ki itself, so that a
//   skew block such as q's adds nothing).
// q's weight is the power of two, from 1 down to 2^-12, with the smallest mu: the rates' error
// drives q's through a coupling that carries the units of the map from the rates to the body's
// (body_rates.hpp), and with the plain norm that coupling alone would set mu.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>

#include <arb.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace eulervop::detail {

// Keeps its scratch between segments (one per segment check).
class weighted_jacobian_bounds {
 public:
  // Sets `weight` (D entries), `jmax` and `mu_plus`; false where a bound is not finite.
  bool compute(const std::vector<chebyshev_model>& J, std::size_t D, slong prec, std::vector<double>& weight,
               mag_t jmax, mag_t mu_plus);

 private:
  static int group(std::size_t i) { return i < 3 ? 0 : 1; }
  void entry_ranges(const std::vector<chebyshev_model>& J);
  void gershgorin_mu(int e, arf_t out, slong prec);

  std::size_t D_ = 0;
  // |J_ik| over the segment; where i and k share a weight, |J_ik + J_ki| / 2; the range of J_ii.
  std::vector<mag_value> range_, sym_;
  std::vector<ball> diag_;
  chebyshev_model sum_;
  ball x_, row_;
  arf_t up_;
  mag_value m_, other_;

 public:
  weighted_jacobian_bounds() { arf_init(up_); }
  ~weighted_jacobian_bounds() { arf_clear(up_); }
  weighted_jacobian_bounds(const weighted_jacobian_bounds&) = delete;
  weighted_jacobian_bounds& operator=(const weighted_jacobian_bounds&) = delete;
};

inline void weighted_jacobian_bounds::entry_ranges(const std::vector<chebyshev_model>& J) {
  const std::size_t D = D_;
  range_.resize(D * D);
  sym_.resize(D * D);
  diag_.resize(D);
  for (std::size_t q = 0; q < D * D; ++q) {
    range_of(x_, J[q]);
    arb_get_mag(range_[q].m, x_.get());
    if (q % (D + 1) == 0) diag_[q / D] = x_;
  }
  // J_ik + J_ki coefficient by coefficient at 64 bits: only its range's magnitude is taken, and
  // a skew pair still sums to exactly zero.
  for (std::size_t i = 0; i < D; ++i)
    for (std::size_t k = i + 1; k < D; ++k) {
      if (group(i) != group(k)) continue;
      const chebyshev_model &a = J[i * D + k], &b = J[k * D + i];
      sum_.reserve_length(std::max(a.length(), b.length()));
      for (slong c = 0; c < sum_.length(); ++c) {
        if (c < a.length() && c < b.length())
          arb_add(sum_.coeff(c), a.coeff(c), b.coeff(c), 64);
        else
          arb_set_round(sum_.coeff(c), (c < a.length() ? a : b).coeff(c), 64);
      }
      mag_add(sum_.remainder(), a.remainder(), b.remainder());
      range_of(x_, sum_);
      arb_get_mag(sym_[i * D + k].m, x_.get());
      mag_mul_2exp_si(sym_[i * D + k].m, sym_[i * D + k].m, -1);
      mag_set(sym_[k * D + i].m, sym_[i * D + k].m);
    }
}

// mu+ for q's weight 2^-e: Gershgorin's bound, each row's radius summed in mags (upward).
inline void weighted_jacobian_bounds::gershgorin_mu(int e, arf_t out, slong prec) {
  const std::size_t D = D_;
  const auto scaled = [&](std::size_t i, std::size_t k, mag_t o) {  // |J_ik| w_i / w_k
    mag_mul_2exp_si(o, range_[i * D + k].m, (group(k) - group(i)) * e);
  };
  arf_zero(out);
  for (std::size_t i = 0; i < D; ++i) {
    arb_set(row_.get(), diag_[i].get());
    for (std::size_t k = 0; k < D; ++k) {
      if (k == i) continue;
      if (group(i) == group(k)) {
        mag_set(m_.m, sym_[i * D + k].m);
      } else {
        scaled(i, k, m_.m);
        scaled(k, i, other_.m);
        mag_add(m_.m, m_.m, other_.m);
        mag_mul_2exp_si(m_.m, m_.m, -1);
      }
      arb_add_error_mag(row_.get(), m_.m);
    }
    arb_get_ubound_arf(up_, row_.get(), prec);
    arf_max(out, out, up_);  // mu+ = max(mu, 0): exp(mu+ dt) bounds |Phi| for growth and decay alike
  }
}

inline bool weighted_jacobian_bounds::compute(const std::vector<chebyshev_model>& J, std::size_t D, slong prec,
                                              std::vector<double>& weight, mag_t jmax, mag_t mu_plus) {
  D_ = D;
  entry_ranges(J);
  int best_e = 0;
  arf_t mu_e, best;
  arf_init(mu_e);
  arf_init(best);
  gershgorin_mu(0, mu_e, prec);
  arf_set(best, mu_e);
  if (D == 7)
    for (int e = 1; e <= 12; ++e) {
      gershgorin_mu(e, mu_e, prec);
      if (arf_cmp(mu_e, best) < 0) {
        arf_set(best, mu_e);
        best_e = e;
      }
    }
  arf_get_mag(mu_plus, best);
  arf_clear(mu_e);
  arf_clear(best);
  for (std::size_t i = 0; i < D; ++i) weight[i] = std::ldexp(1.0, -best_e * group(i));
  mag_zero(jmax);
  for (std::size_t i = 0; i < D; ++i)
    for (std::size_t k = 0; k < D; ++k) {
      mag_mul_2exp_si(m_.m, range_[i * D + k].m, (group(k) - group(i)) * best_e);
      mag_addmul(jmax, m_.m, m_.m);
    }
  mag_sqrt(jmax, jmax);
  return mag_is_finite(jmax) && mag_is_finite(mu_plus);
}

}  // namespace eulervop::detail

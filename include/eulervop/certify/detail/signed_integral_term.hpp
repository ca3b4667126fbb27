// The signed integral term of a segment (docs/certified.md, "How", step 3):
//   u(b) = int_a^b Phi(b, s) J(s) r(s) ds,
// which solves u = hl int J (u + r) (s from -1). It is computed in double by Picard iteration on
// Chebyshev coefficients (degree 2N + 1, like r), then bounded: with
// R_u = hl int J (u_num + r) - u_num, E = u - u_num solves E = R_u + hl int J E, so
// |E(1)| <= sup|R_u| (1 + h exp(mu h) |J|). u_num(1) joins r(1) as a signed vector; only |E(1)|
// is a ball. It is about ten times r(1) where a segment spans a good part of a rotation, so
// bounding it by norms would dominate the whole bound.
#pragma once

#include <eulervop/certify/detail/bounded_chebyshev.hpp>
#include <eulervop/certify/detail/linearized_flow.hpp>
#include <eulervop/certify/detail/picard_residual.hpp>
#include <eulervop/certify/detail/real.hpp>
#include <eulervop/certify/detail/segment_polynomial.hpp>
#include <eulervop/certify/interval.hpp>

#include <mpfi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace eulervop::detail {

class signed_integral_term {
 public:
  signed_integral_term(mpfr_prec_t bits, std::size_t degree)
      : u1(3, interval::zero(bits)), eps(interval::zero(bits)), nr_(2 * degree + 2), ud_(3 * nr_), next_(3 * nr_),
        w_(3 * nr_), scratch_(interval::zero(bits)) {}

  void compute(const segment_polynomial& P, const picard_residual& r, const jacobian_rows& rows,
               const linear_growth& g, integrated_products& sums);

  std::vector<interval> u1;  // u_num(1), signed
  interval eps;              // |u(b) - u_num(1)|_2 <= eps

 private:
  void shorten(const segment_polynomial& P);
  void J_times(const segment_polynomial& P, const jacobian_rows& rows, int i, const double* w,
               const std::array<double, 3>& wrad, bool full, double hl, integrated_products& sums) const;
  void iterate(const segment_polynomial& P, const picard_residual& r, const jacobian_rows& rows, double hl,
               integrated_products& sums);
  double residual_sup(const segment_polynomial& P, const picard_residual& r, const jacobian_rows& rows, double hl,
                      integrated_products& sums);

  std::size_t nr_;
  std::array<std::size_t, 3> short_length_{};
  std::vector<double> ud_, next_, w_;  // u_num (3 x nr), the next iterate, u_num + r
  interval scratch_;
};

inline void signed_integral_term::compute(const segment_polynomial& P, const picard_residual& r,
                                          const jacobian_rows& rows, const linear_growth& g,
                                          integrated_products& sums) {
  shorten(P);
  iterate(P, r, rows, g.hl, sums);
  sums.hl_error = g.hl_error;
  g.error_at_end(eps, residual_sup(P, r, rows, g.hl, sums), P);
  for (int i = 0; i < 3; ++i) {
    enclose_double_sum(u1[i], &ud_[i * nr_], nr_, scratch_);  // u_num(1) = sum_k u_k
    mpfi_mul_2si(u1[i].get(), u1[i].get(), -r.r_scale);  // back from r's scaling
  }
  mpfi_mul_2si(eps.get(), eps.get(), -r.r_scale);
}

// The iteration needs u to a few digits only, so it drops P's coefficients below 1e-9 of the
// largest (the final residual uses them all).
inline void signed_integral_term::shorten(const segment_polynomial& P) {
  for (int c = 0; c < 3; ++c) {
    double big = 0;
    for (std::size_t k = 0; k < P.n1; ++k) big = std::max(big, std::abs(P.cd[c * P.n1 + k]));
    std::size_t n = P.n1;
    while (n > 1 && std::abs(P.cd[c * P.n1 + n - 1]) < 1e-9 * big) --n;
    short_length_[c] = n;
  }
}

// sums = hl int (J w)_i, w three series of nr_ coefficients within wrad of the exact ones.
inline void signed_integral_term::J_times(const segment_polynomial& P, const jacobian_rows& rows, int i,
                                          const double* w, const std::array<double, 3>& wrad, bool full, double hl,
                                          integrated_products& sums) const {
  std::array<product_term, 2> terms;
  for (int t = 0; t < 2; ++t) {
    const jacobian_entry& e = rows[i][t];
    terms[t] = {e.coefficient, {&P.cd[e.c * P.n1], full ? P.n1 : short_length_[e.c], P.prad[e.c]},
                {&w[e.k * nr_], nr_, wrad[e.k]}};
  }
  sums.compute(hl, terms);
}

inline void signed_integral_term::iterate(const segment_polynomial& P, const picard_residual& r,
                                          const jacobian_rows& rows, double hl, integrated_products& sums) {
  std::fill(ud_.begin(), ud_.end(), 0.0);
  for (int it = 0; it < 60; ++it) {
    for (std::size_t q = 0; q < 3 * nr_; ++q) w_[q] = ud_[q] + r.rd[q];
    double change = 0, size = 0;
    for (int i = 0; i < 3; ++i) {
      J_times(P, rows, i, w_.data(), {0, 0, 0}, false, hl, sums);
      for (std::size_t k = 0; k < nr_; ++k) {  // truncated to r's length
        const std::size_t q = i * nr_ + k;
        change = std::max(change, std::abs(sums.coeffs[k] - ud_[q]));
        size = std::max(size, std::abs(sums.coeffs[k]));
        next_[q] = sums.coeffs[k];
      }
    }
    ud_.swap(next_);
    if (!std::isfinite(change)) P.fail(outcome_kind::certify_non_finite);
    if (change <= 1e-5 * size) break;  // enough: the residual bound covers the rest
  }
}

// The residual of the exact polynomials: u_num exact, r = rd + (its radius); u_num + r as a view,
// the sum rounded, its error in the radius.
inline double signed_integral_term::residual_sup(const segment_polynomial& P, const picard_residual& r,
                                                 const jacobian_rows& rows, double hl, integrated_products& sums) {
  for (std::size_t q = 0; q < 3 * nr_; ++q) w_[q] = ud_[q] + r.rd[q];
  double sup2 = 0;
  for (int i = 0; i < 3; ++i) {
    std::array<double, 3> rad;
    for (int k = 0; k < 3; ++k)
      rad[k] = r.rrad[k] + gamma_of(2) * (abs_sum(&ud_[k * nr_], nr_) + abs_sum(&r.rd[k * nr_], nr_));
    J_times(P, rows, i, w_.data(), rad, true, hl, sums);
    const double b = residual_bound(0.0, sums, {&ud_[i * nr_], nr_, 0.0});
    sup2 += b * b;
  }
  return std::sqrt(sup2) * (1 + 1e-12);
}

}  // namespace eulervop::detail

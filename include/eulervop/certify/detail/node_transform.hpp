// The Chebyshev coefficients of a segment's polynomial from its node values, enclosed
// (docs/certified.md, "How", step 1): the degree-N interpolant of the values at the Lobatto nodes
// s_j = -cos(j pi / N) has the coefficients
//   c_k = (2/N) sum_j'' v_j T_k(s_j),  T_k(s_j) = (-1)^k cos(k j pi / N),
// the sum's end terms halved, and c_0, c_N halved too. The matrix M of this map is enclosed once;
// each segment's sums run on midpoints in plain MPFR, widened by a bound of their roundings.
#pragma once

#include <eulervop/certify/detail/real.hpp>
#include <eulervop/certify/interval.hpp>

#include <mpfi.h>
#include <mpfr.h>

#include <cmath>
#include <cstddef>
#include <vector>

namespace eulervop::detail {

class node_transform {
 public:
  node_transform(mpfr_prec_t bits, std::size_t degree);

  // c (three components of N + 1 coefficients) from the node values `v` (the same layout,
  // exact points at the working precision).
  void apply(const std::vector<real>& v, std::vector<interval>& c);

 private:
  std::vector<interval> enclosed_matrix() const;

  mpfr_prec_t bits_;
  std::size_t N_, n1_;
  // M's midpoints; (1 + 2^-40) (dM + Mmax (n + 2) 2^-p (1 + 2^-20)) with dM >= max |M - M^|
  // (the widths) and Mmax >= max |M^|.
  std::vector<real> Mmid_;
  real error_scale_{64};
  // Scratch: the folded values, a coefficient's sum and product, sum |f^_j|.
  std::vector<real> fold_plus_, fold_minus_;
  real sum_, product_, F_{64};
};

inline node_transform::node_transform(mpfr_prec_t bits, std::size_t degree)
    : bits_(bits), N_(degree), n1_(degree + 1), Mmid_(n1_ * n1_, real(bits)), fold_plus_(n1_ / 2, real(bits)),
      fold_minus_(n1_ / 2, real(bits)), sum_(bits), product_(bits) {
  const std::vector<interval> M = enclosed_matrix();
  real dM(64), Mmax(64), lo(bits), scratch(bits);
  for (std::size_t q = 0; q < n1_ * n1_; ++q) {
    mpfi_mid(Mmid_[q].get(), M[q].get());
    width_up(scratch, M[q], lo);
    mpfr_max(dM.get(), dM.get(), scratch.get(), MPFR_RNDU);
    mpfr_abs(scratch.get(), Mmid_[q].get(), MPFR_RNDU);
    mpfr_max(Mmax.get(), Mmax.get(), scratch.get(), MPFR_RNDU);
  }
  // n = half + 1 terms per sum.
  mpfr_ptr e = error_scale_.get();
  mpfr_set_ui(e, static_cast<unsigned long>(n1_ / 2 + 3), MPFR_RNDU);
  mpfr_mul_2si(e, e, -static_cast<long>(bits), MPFR_RNDU);
  mpfr_mul_d(e, e, 1 + std::ldexp(1.0, -20), MPFR_RNDU);
  mpfr_mul(e, e, Mmax.get(), MPFR_RNDU);
  mpfr_add(e, e, dM.get(), MPFR_RNDU);
  mpfr_mul_d(e, e, 1 + std::ldexp(1.0, -40), MPFR_RNDU);
}

// M_kj = (2/N) (-1)^k cos(k j pi / N), halved for j in {0, N} and for k in {0, N}; the angle
// reduced modulo 2N (exact integers).
inline std::vector<interval> node_transform::enclosed_matrix() const {
  const std::size_t N = N_;
  std::vector<interval> cosines(2 * N, interval::zero(bits_));
  interval pi = interval::zero(bits_);
  mpfi_const_pi(pi.get());
  for (std::size_t m = 0; m < 2 * N; ++m) {
    mpfi_mul_ui(cosines[m].get(), pi.get(), static_cast<unsigned long>(m));
    mpfi_div_ui(cosines[m].get(), cosines[m].get(), static_cast<unsigned long>(N));
    mpfi_cos(cosines[m].get(), cosines[m].get());
  }
  std::vector<interval> M(n1_ * n1_, interval::zero(bits_));
  for (std::size_t k = 0; k < n1_; ++k)
    for (std::size_t j = 0; j < n1_; ++j) {
      interval& w = M[k * n1_ + j];
      mpfi_set(w.get(), cosines[(k * j) % (2 * N)].get());
      if (k % 2) mpfi_neg(w.get(), w.get());
      mpfi_mul_ui(w.get(), w.get(), 2);
      mpfi_div_ui(w.get(), w.get(), static_cast<unsigned long>(N));
      if (j == 0 || j == N) mpfi_mul_2si(w.get(), w.get(), -1);
      if (k == 0 || k == N) mpfi_mul_2si(w.get(), w.get(), -1);
    }
  return M;
}

// The columns j and N - j differ by the factor (-1)^k (T_k(-s) = (-1)^k T_k(s) and the nodes are
// symmetric), so the sums and differences of mirrored values halve the products. The sums are
// done on midpoints, rounded to nearest at the working precision p, and then widened by one
// bound E per component:
//   |c_k - c^_k| <= sum_j |M_kj - M^_kj| |f_j| + |M^_kj| |f_j - f^_j| + gamma_n sum |M^_kj| |f^_j|
//               <= F^ (1 + 2^-p) (dM + Mmax ((n + 2) 2^-p (1 + 2^-20))),
// F^ = sum |f^_j| (Higham 2002, section 3.1, for the dot products); plain MPFR operations cost
// less than half of interval ones.
inline void node_transform::apply(const std::vector<real>& values, std::vector<interval>& c) {
  const std::size_t half = n1_ / 2;  // pairs j < half with N - j; N even leaves j = N/2 alone
  mpfr_ptr tmp = product_.get();
  interval widen = interval::zero(bits_);
  for (int i = 0; i < 3; ++i) {
    const real* v = &values[i * n1_];
    mpfr_set_ui(F_.get(), 0, MPFR_RNDU);
    for (std::size_t j = 0; j < half; ++j) {
      mpfr_add(fold_plus_[j].get(), v[j].get(), v[N_ - j].get(), MPFR_RNDN);
      mpfr_sub(fold_minus_[j].get(), v[j].get(), v[N_ - j].get(), MPFR_RNDN);
      add_abs_up(F_, fold_plus_[j].get());
      add_abs_up(F_, fold_minus_[j].get());
    }
    if (n1_ % 2) add_abs_up(F_, v[half].get());
    for (std::size_t k = 0; k < n1_; ++k) {
      const std::vector<real>& folded = (k % 2) ? fold_minus_ : fold_plus_;
      mpfr_ptr ck = sum_.get();
      mpfr_set_ui(ck, 0, MPFR_RNDN);
      for (std::size_t j = 0; j < half; ++j) {
        mpfr_mul(tmp, Mmid_[k * n1_ + j].get(), folded[j].get(), MPFR_RNDN);
        mpfr_add(ck, ck, tmp, MPFR_RNDN);
      }
      if (n1_ % 2) {
        mpfr_mul(tmp, Mmid_[k * n1_ + half].get(), v[half].get(), MPFR_RNDN);
        mpfr_add(ck, ck, tmp, MPFR_RNDN);
      }
      mpfi_set_fr(c[i * n1_ + k].get(), ck);
    }
    mpfr_mul(F_.get(), F_.get(), error_scale_.get(), MPFR_RNDU);
    mpfi_interv_fr(widen.get(), F_.get(), F_.get());
    mpfi_neg(widen.get(), widen.get());
    mpfi_put_fr(widen.get(), F_.get());  // [-E, E]
    for (std::size_t k = 0; k < n1_; ++k) mpfi_add(c[i * n1_ + k].get(), c[i * n1_ + k].get(), widen.get());
  }
}

}  // namespace eulervop::detail

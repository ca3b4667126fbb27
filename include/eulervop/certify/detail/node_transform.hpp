// The Chebyshev coefficients of a segment's polynomial from its node values, enclosed
// (docs/certified.md, "How", step 1): the degree-N interpolant of the values at the Lobatto nodes
// s_j = -cos(j pi / N) has the coefficients
//   c_k = (2/N) sum_j'' v_j T_k(s_j),  T_k(s_j) = (-1)^k cos(k j pi / N),
// the sum's end terms halved, and c_0, c_N halved too. The matrix M of this map is enclosed once
// and put on a grid of step 2^-p (p the working bits); each segment's values go on a grid too,
// the sums are exact integers (grid_integer.hpp), and the result is widened by a bound of the
// two grids' steps and of one final rounding.
#pragma once

#include <eulervop/certify/detail/grid_integer.hpp>
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
  void widen(const grid_integer& abs_sum, long shift, std::vector<interval>& c, int i);
  bool load_folds();
  template <std::size_t L>
  void sums_on_limbs(long shift, std::vector<interval>& c, int i);

  mpfr_prec_t bits_;
  std::size_t N_, n1_, half_;
  // M on the grid 2^-p: Mq_ 2^-p within dM_ of the exact M (its enclosure's width plus a step),
  // |Mq_| 2^-p <= Mmax_ (both at 64 bits, rounded up).
  std::vector<grid_integer> Mq_;
  real dM_{64}, Mmax_{64};
  // Scratch: the values on their grid, folded (sums, differences), a sum, sum |f_j| on the grid.
  std::vector<grid_integer> vq_, fold_plus_, fold_minus_;
  grid_integer acc_, abs_sum_;
  real ck_, bound_{64}, term_{64}, scratch_;
  // M and the folded values on `limbs_` limbs (0: GMP's integers; grid_integer.hpp, limbs), the
  // folded values in the order plus, minus, middle.
  std::size_t limbs_ = 0;
  std::vector<mp_limb_t> Ml_, Mneg_, fl_, fneg_, lacc_;
};

inline node_transform::node_transform(mpfr_prec_t bits, std::size_t degree)
    : bits_(bits), N_(degree), n1_(degree + 1), half_(n1_ / 2), Mq_(n1_ * n1_, grid_integer(bits + 64)),
      vq_(n1_, grid_integer(bits + 64)), fold_plus_(half_, grid_integer(bits + 64)),
      fold_minus_(half_, grid_integer(bits + 64)), acc_(2 * bits + 128), abs_sum_(bits + 128), ck_(bits),
      scratch_(bits + 64) {
  const std::vector<interval> M = enclosed_matrix();
  real mid(bits + 64), lo(bits + 64), width(bits + 64);
  for (std::size_t q = 0; q < n1_ * n1_; ++q) {
    mpfi_mid(mid.get(), M[q].get());
    to_grid(Mq_[q], mid.get(), bits);
    // |M - Mq 2^-p| <= width + |mid - Mq 2^-p| < width + 2^-p
    width_up(width, M[q], lo);
    mpfr_max(dM_.get(), dM_.get(), width.get(), MPFR_RNDU);
    mpfr_abs(mid.get(), mid.get(), MPFR_RNDU);
    mpfr_max(Mmax_.get(), Mmax_.get(), mid.get(), MPFR_RNDU);
  }
  mpfr_set_ui_2exp(width.get(), 1, -bits, MPFR_RNDU);
  mpfr_add(dM_.get(), dM_.get(), width.get(), MPFR_RNDU);
  mpfr_add(Mmax_.get(), Mmax_.get(), width.get(), MPFR_RNDU);  // floor moves a value by < a step
  // Folded values have at most bits + 2 bits (two values of at most bits + 1 bits, summed).
  const std::size_t limbs = (static_cast<std::size_t>(bits) + 2 + 63) / 64;
  if (limbs > 8) return;
  Ml_.resize(n1_ * n1_ * limbs);
  Mneg_.resize(n1_ * n1_);
  for (std::size_t q = 0; q < n1_ * n1_; ++q)
    if (!limbs::load(Mq_[q].get(), limbs, &Ml_[q * limbs], Mneg_[q])) return;
  limbs_ = limbs;
  fl_.resize((2 * half_ + 1) * limbs);
  fneg_.resize(2 * half_ + 1);
  lacc_.resize(2 * limbs + 1);
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
// symmetric), so the sums and differences of mirrored values halve the products. The values go on
// a grid of step 2^-shift under their largest (their bits below the grid rounded down), and the
// sums are exact integers; one rounding to nearest at p bits brings each c_k back to MPFR.
inline void node_transform::apply(const std::vector<real>& values, std::vector<interval>& c) {
  const long shift = grid_shift(values, [](const real& x) { return x.get(); }, bits_);
  for (int i = 0; i < 3; ++i) {
    const real* v = &values[i * n1_];
    for (std::size_t j = 0; j < n1_; ++j) to_grid(vq_[j], v[j].get(), shift);
    mpz_set_ui(abs_sum_.get(), 0);
    for (std::size_t j = 0; j < half_; ++j) {
      mpz_add(fold_plus_[j].get(), vq_[j].get(), vq_[N_ - j].get());
      mpz_sub(fold_minus_[j].get(), vq_[j].get(), vq_[N_ - j].get());
      add_abs(abs_sum_, fold_plus_[j].get());
      add_abs(abs_sum_, fold_minus_[j].get());
    }
    if (n1_ % 2) add_abs(abs_sum_, vq_[half_].get());
    if (limbs_ > 0 && load_folds() &&
        limbs::with_limb_count(limbs_, [&](auto L) { sums_on_limbs<decltype(L)::value>(shift, c, i); })) {
      widen(abs_sum_, shift, c, i);
      continue;
    }
    for (std::size_t k = 0; k < n1_; ++k) {
      const std::vector<grid_integer>& folded = (k % 2) ? fold_minus_ : fold_plus_;
      const grid_integer* Mk = &Mq_[k * n1_];
      mpz_set_ui(acc_.get(), 0);
      for (std::size_t j = 0; j < half_; ++j) mpz_addmul(acc_.get(), Mk[j].get(), folded[j].get());
      if (n1_ % 2) mpz_addmul(acc_.get(), Mk[half_].get(), vq_[half_].get());
      mpfr_set_z_2exp(ck_.get(), acc_.get(), -(static_cast<long>(bits_) + shift), MPFR_RNDN);
      mpfi_set_fr(c[i * n1_ + k].get(), ck_.get());
    }
    widen(abs_sum_, shift, c, i);
  }
}

// The folded values into fl_ (false if one needs more than limbs_ limbs).
inline bool node_transform::load_folds() {
  for (std::size_t j = 0; j < half_; ++j)
    if (!limbs::load(fold_plus_[j].get(), limbs_, &fl_[j * limbs_], fneg_[j]) ||
        !limbs::load(fold_minus_[j].get(), limbs_, &fl_[(half_ + j) * limbs_], fneg_[half_ + j]))
      return false;
  return n1_ % 2 == 0 || limbs::load(vq_[half_].get(), limbs_, &fl_[2 * half_ * limbs_], fneg_[2 * half_]);
}

// c_k for component i from the folded values on L limbs: the same exact sums as with GMP.
template <std::size_t L>
void node_transform::sums_on_limbs(long shift, std::vector<interval>& c, int i) {
  constexpr std::size_t W = 2 * L + 1;
  mp_limb_t* acc = lacc_.data();
  const auto add = [&](limbs::column_sum<L>& sum, std::size_t q, std::size_t f) {
    limbs::product_columns<L> p;
    limbs::columns_of<L>(&Ml_[q * L], &fl_[f * L], p);
    sum.add(p, (Mneg_[q] ^ fneg_[f]) & 1);
  };
  for (std::size_t k = 0; k < n1_; ++k) {
    const std::size_t folded = (k % 2) ? half_ : 0;  // minus or plus
    limbs::column_sum<L> sum;
    for (std::size_t j = 0; j < half_; ++j) add(sum, k * n1_ + j, folded + j);
    if (n1_ % 2) add(sum, k * n1_ + half_, 2 * half_);
    sum.to_limbs(acc, W);
    limbs::round_to(acc, W, ck_.get(), static_cast<long>(bits_) + shift);
    mpfi_set_fr(c[i * n1_ + k].get(), ck_.get());
  }
}

// The bound E of |c_k - c^_k| for component i, added to every c_k as [-E, E]. With f_j the exact
// folded values, f^_j those on the grid (|f_j - f^_j| < 2 steps: two values rounded down; the
// middle value alone, one), F^ = sum |f^_j| and n_f the number of folded values:
//   |c_k - c^_k| <= sum_j |M_kj - M^_kj| |f_j| + |M^_kj| |f_j - f^_j| + 2^-p |c^_k|
//               <= dM (F^ + 2 n_f 2^-shift) + Mmax 2 n_f 2^-shift + 2^-p Mmax F^,
// the last term the final rounding to nearest (|c^_k| <= Mmax F^ before it).
inline void node_transform::widen(const grid_integer& abs_sum, long shift, std::vector<interval>& c, int i) {
  mpfr_ptr E = bound_.get(), t = term_.get();
  const std::size_t n_f = half_ + n1_ % 2;
  mpfr_set_ui(E, 0, MPFR_RNDU);
  add_abs_on_grid(E, abs_sum.get(), shift, scratch_.get());  // F^
  mpfr_set_ui_2exp(t, static_cast<unsigned long>(2 * n_f), -shift, MPFR_RNDU);  // 2 n_f steps
  mpfr_mul(scratch_.get(), E, Mmax_.get(), MPFR_RNDU);
  mpfr_mul_2si(scratch_.get(), scratch_.get(), -static_cast<long>(bits_), MPFR_RNDU);  // 2^-p Mmax F^
  mpfr_add(E, E, t, MPFR_RNDU);
  mpfr_mul(E, E, dM_.get(), MPFR_RNDU);
  mpfr_add(E, E, scratch_.get(), MPFR_RNDU);
  mpfr_mul(t, t, Mmax_.get(), MPFR_RNDU);
  mpfr_add(E, E, t, MPFR_RNDU);
  interval widen = interval::zero(bits_);
  mpfi_interv_fr(widen.get(), E, E);
  mpfi_neg(widen.get(), widen.get());
  mpfi_put_fr(widen.get(), E);  // [-E, E]
  for (std::size_t k = 0; k < n1_; ++k) mpfi_add(c[i * n1_ + k].get(), c[i * n1_ + k].get(), widen.get());
}

}  // namespace eulervop::detail

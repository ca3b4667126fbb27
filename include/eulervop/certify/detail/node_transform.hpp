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
#include <memory>
#include <vector>

namespace eulervop::detail {

class node_transform {
 public:
  node_transform(mpfr_prec_t bits, std::size_t degree);

  // c (three components of N + 1 coefficients) from the node values `v` (the same layout,
  // exact points at the working precision), and `widths` >= the sum of c's widths per component
  // (three numbers, rounded up).
  void apply(const std::vector<real>& v, std::vector<interval>& c, std::vector<real>& widths);

 private:
  std::vector<interval> enclosed_matrix() const;
  void bound(long shift, real& width);
  void set_widened(interval& c);
  bool load_folds(const real* v, long shift);
  template <std::size_t L>
  void sums_on_limbs(long shift, std::vector<interval>& c, int i);

  mpfr_prec_t bits_;
  std::size_t N_, n1_, half_;
  // M on the grid 2^-p: q 2^-p within dM of the exact M (its enclosure's width plus a step),
  // |q| 2^-p <= Mmax (both at 64 bits, rounded up); q on `limbs` limbs (0: GMP's integers only).
  // Constant, so the copies (one per check) share it.
  struct grid_matrix {
    std::vector<grid_integer> q;
    real dM{64}, Mmax{64};
    std::size_t limbs = 0;
    std::vector<mp_limb_t> l, neg;
  };
  std::shared_ptr<const grid_matrix> M_;
  // Scratch: the values on their grid, folded (sums, differences), a sum, sum |f_j| on the grid.
  std::vector<grid_integer> vq_, fold_plus_, fold_minus_;
  grid_integer acc_, abs_sum_;
  real ck_, bound_{64}, term_{64}, scratch_, folded_abs_{64};
  // The folded values on `limbs_` limbs (M's; grid_integer.hpp, limbs), in the order plus, minus,
  // middle.
  std::size_t limbs_ = 0;
  std::vector<mp_limb_t> fl_, fneg_, lacc_;
};

inline node_transform::node_transform(mpfr_prec_t bits, std::size_t degree)
    : bits_(bits), N_(degree), n1_(degree + 1), half_(n1_ / 2), vq_(n1_, grid_integer(bits + 64)),
      fold_plus_(half_, grid_integer(bits + 64)), fold_minus_(half_, grid_integer(bits + 64)), acc_(2 * bits + 128),
      abs_sum_(bits + 128), ck_(bits), scratch_(bits + 64) {
  auto m = std::make_shared<grid_matrix>();
  m->q.assign(n1_ * n1_, grid_integer(bits + 64));
  const std::vector<interval> M = enclosed_matrix();
  real mid(bits + 64), width(bits + 64);
  for (std::size_t q = 0; q < n1_ * n1_; ++q) {
    mpfi_mid(mid.get(), M[q].get());
    to_grid(m->q[q], mid.get(), bits);
    // |M - q 2^-p| <= width + |mid - q 2^-p| < width + 2^-p
    width_up(width, M[q]);
    mpfr_max(m->dM.get(), m->dM.get(), width.get(), MPFR_RNDU);
    mpfr_abs(mid.get(), mid.get(), MPFR_RNDU);
    mpfr_max(m->Mmax.get(), m->Mmax.get(), mid.get(), MPFR_RNDU);
  }
  mpfr_set_ui_2exp(width.get(), 1, -bits, MPFR_RNDU);
  mpfr_add(m->dM.get(), m->dM.get(), width.get(), MPFR_RNDU);
  mpfr_add(m->Mmax.get(), m->Mmax.get(), width.get(), MPFR_RNDU);  // floor moves a value by < a step
  // Folded values have at most bits + 2 bits (two values of at most bits + 1 bits, summed).
  const std::size_t limbs = (static_cast<std::size_t>(bits) + 2 + 63) / 64;
  bool fits = limbs <= 8;
  if (fits) {
    m->l.resize(n1_ * n1_ * limbs);
    m->neg.resize(n1_ * n1_);
    for (std::size_t q = 0; fits && q < n1_ * n1_; ++q) fits = limbs::load(m->q[q].get(), limbs, &m->l[q * limbs], m->neg[q]);
  }
  if (fits) {
    m->limbs = limbs_ = limbs;
    fl_.resize((2 * half_ + 1) * limbs);
    fneg_.resize(2 * half_ + 1);
    lacc_.resize(2 * limbs + 1);  // also two values, or a sum of magnitudes on limbs + 1
  }
  M_ = std::move(m);
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
// a grid of step 2^-shift under their largest (their bits below the grid dropped, toward zero or
// down: less than a step either way), and the sums are exact integers; one rounding to nearest at
// p bits brings each c_k back to MPFR.
inline void node_transform::apply(const std::vector<real>& values, std::vector<interval>& c,
                                  std::vector<real>& widths) {
  const long shift = grid_shift(values, [](const real& x) { return x.get(); }, bits_);
  for (int i = 0; i < 3; ++i) {
    const real* v = &values[i * n1_];
    if (limbs_ > 0 && load_folds(v, shift)) {
      bound(shift, widths[i]);
      if (limbs::with_limb_count(limbs_, [&](auto L) { sums_on_limbs<decltype(L)::value>(shift, c, i); })) continue;
    }
    for (std::size_t j = 0; j < n1_; ++j) to_grid(vq_[j], v[j].get(), shift);
    mpz_set_ui(abs_sum_.get(), 0);
    for (std::size_t j = 0; j < half_; ++j) {
      mpz_add(fold_plus_[j].get(), vq_[j].get(), vq_[N_ - j].get());
      mpz_sub(fold_minus_[j].get(), vq_[j].get(), vq_[N_ - j].get());
      add_abs(abs_sum_, fold_plus_[j].get());
      add_abs(abs_sum_, fold_minus_[j].get());
    }
    if (n1_ % 2) add_abs(abs_sum_, vq_[half_].get());
    mpfr_set_ui(folded_abs_.get(), 0, MPFR_RNDU);
    add_abs_on_grid(folded_abs_.get(), abs_sum_.get(), shift, scratch_.get());
    bound(shift, widths[i]);
    for (std::size_t k = 0; k < n1_; ++k) {
      const std::vector<grid_integer>& folded = (k % 2) ? fold_minus_ : fold_plus_;
      const grid_integer* Mk = &M_->q[k * n1_];
      mpz_set_ui(acc_.get(), 0);
      for (std::size_t j = 0; j < half_; ++j) mpz_addmul(acc_.get(), Mk[j].get(), folded[j].get());
      if (n1_ % 2) mpz_addmul(acc_.get(), Mk[half_].get(), vq_[half_].get());
      mpfr_set_z_2exp(ck_.get(), acc_.get(), -(static_cast<long>(bits_) + shift), MPFR_RNDN);
      set_widened(c[i * n1_ + k]);
    }
  }
}

// One component's values v on the grid and folded into fl_ (plus, minus, middle), their
// magnitudes' sum into folded_abs_ (rounded up); false if a value needs more than limbs_ limbs.
inline bool node_transform::load_folds(const real* v, long shift) {
  const std::size_t L = limbs_;
  mp_limb_t* a = &lacc_[0];
  mp_limb_t* b = &lacc_[L];
  mp_limb_t a_neg = 0, b_neg = 0;
  for (std::size_t j = 0; j < half_; ++j) {
    if (!limbs::load_truncated(v[j].get(), shift, L, a, a_neg) ||
        !limbs::load_truncated(v[N_ - j].get(), shift, L, b, b_neg))
      return false;
    limbs::signed_sum(a, a_neg, b, b_neg, false, L, &fl_[j * L], fneg_[j]);
    limbs::signed_sum(a, a_neg, b, b_neg, true, L, &fl_[(half_ + j) * L], fneg_[half_ + j]);
  }
  if (n1_ % 2 && !limbs::load_truncated(v[half_].get(), shift, L, &fl_[2 * half_ * L], fneg_[2 * half_]))
    return false;
  // sum |f_j| exactly on L + 1 limbs (fewer than 2^64 values below 2^(64 L)), then rounded up.
  mp_limb_t* sum = &lacc_[0];
  for (std::size_t t = 0; t <= L; ++t) sum[t] = 0;
  const std::size_t count = 2 * half_ + n1_ % 2;
  for (std::size_t f = 0; f < count; ++f)
    sum[L] += mpn_add_n(sum, sum, &fl_[f * L], static_cast<mp_size_t>(L));
  mp_size_t size = static_cast<mp_size_t>(L + 1);
  while (size > 0 && sum[size - 1] == 0) --size;
  mpz_t view;
  mpfr_set_z_2exp(folded_abs_.get(), mpz_roinit_n(view, sum, size), -shift, MPFR_RNDU);
  return true;
}

// c_k for component i from the folded values on L limbs: the same exact sums as with GMP.
template <std::size_t L>
void node_transform::sums_on_limbs(long shift, std::vector<interval>& c, int i) {
  constexpr std::size_t W = 2 * L + 1;
  mp_limb_t* acc = lacc_.data();
  const auto add = [&](limbs::column_sum<L>& sum, std::size_t q, std::size_t f) {
    limbs::product_columns<L> p;
    limbs::columns_of<L>(&M_->l[q * L], &fl_[f * L], p);
    sum.add(p, (M_->neg[q] ^ fneg_[f]) & 1);
  };
  for (std::size_t k = 0; k < n1_; ++k) {
    const std::size_t folded = (k % 2) ? half_ : 0;  // minus or plus
    limbs::column_sum<L> sum;
    for (std::size_t j = 0; j < half_; ++j) add(sum, k * n1_ + j, folded + j);
    if (n1_ % 2) add(sum, k * n1_ + half_, 2 * half_);
    sum.to_limbs(acc, W);
    limbs::round_to(acc, W, ck_.get(), static_cast<long>(bits_) + shift);
    set_widened(c[i * n1_ + k]);
  }
}

// The bound E of |c_k - c^_k| for component i (bound_), each c_k then being c^_k + [-E, E]. With
// f_j the exact folded values, f^_j those on the grid (|f_j - f^_j| < 2 steps: two values on the
// grid; the middle value alone, one), F^ = sum |f^_j| (folded_abs_) and n_f the number of folded
// values:
//   |c_k - c^_k| <= sum_j |M_kj - M^_kj| |f_j| + |M^_kj| |f_j - f^_j| + 2^-p |c^_k|
//               <= dM (F^ + 2 n_f 2^-shift) + Mmax 2 n_f 2^-shift + 2^-p Mmax F^,
// the last term the final rounding to nearest (|c^_k| <= Mmax F^ before it). Each interval's ends
// are rounded outward at p bits, by at most 2^(1-p) of their magnitudes, so its width is at most
// 2 E + 2^(2-p) (|c^_k| + E) <= 2 E + 2^(3-p) (Mmax F^ + E): `width` is n1 times that.
inline void node_transform::bound(long shift, real& width) {
  mpfr_ptr E = bound_.get(), t = term_.get();
  const std::size_t n_f = half_ + n1_ % 2;
  mpfr_set(E, folded_abs_.get(), MPFR_RNDU);  // F^
  mpfr_set_ui_2exp(t, static_cast<unsigned long>(2 * n_f), -shift, MPFR_RNDU);  // 2 n_f steps
  mpfr_mul(scratch_.get(), E, M_->Mmax.get(), MPFR_RNDU);
  mpfr_mul_2si(scratch_.get(), scratch_.get(), -static_cast<long>(bits_), MPFR_RNDU);  // 2^-p Mmax F^
  mpfr_add(E, E, t, MPFR_RNDU);
  mpfr_mul(E, E, M_->dM.get(), MPFR_RNDU);
  mpfr_add(E, E, scratch_.get(), MPFR_RNDU);
  mpfr_mul(t, t, M_->Mmax.get(), MPFR_RNDU);
  mpfr_add(E, E, t, MPFR_RNDU);
  mpfr_ptr w = width.get();
  mpfr_mul(w, folded_abs_.get(), M_->Mmax.get(), MPFR_RNDU);
  mpfr_add(w, w, E, MPFR_RNDU);
  mpfr_mul_2si(w, w, 3 - static_cast<long>(bits_), MPFR_RNDU);
  mpfr_add(w, w, E, MPFR_RNDU);
  mpfr_add(w, w, E, MPFR_RNDU);
  mpfr_mul_ui(w, w, static_cast<unsigned long>(n1_), MPFR_RNDU);
}

// c = ck_ + [-E, E], its ends rounded outward.
inline void node_transform::set_widened(interval& c) {
  mpfr_sub(&c.get()->left, ck_.get(), bound_.get(), MPFR_RNDD);
  mpfr_add(&c.get()->right, ck_.get(), bound_.get(), MPFR_RNDU);
}

}  // namespace eulervop::detail

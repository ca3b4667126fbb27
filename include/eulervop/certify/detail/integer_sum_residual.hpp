// The sup bound of a residual of the linear flow (ball_linear_flow.hpp), rho = hl int S - Q (+ I),
// where the integrand S = sum_k J_ik Y_k is a sum of products of integer polynomials on binary
// grids, exact in integers, and Q (an entry of Phi_num or a component of u_num) is an integer
// polynomial on a binary grid too. The integral of a Chebyshev series is Clenshaw and Curtis's
// (1960) recurrence, as picard_residual_model() in residual_model.hpp: its coefficient k >= 1 is
// b_k = hl 2^e d_k / (2k) with d_k = S_{k-1} - S_{k+1} an exact integer, its constant term the
// alternating sum of the others. With hl = M 2^m + eps (M the top 128 bits of the half-length:
// all of a binary128's, so that eps = 0 in quad), the residual's coefficient times 2k,
//   2k (b_k - Q_k) = M d_k 2^(m+e) - 2k q_k 2^f + eps d_k 2^e,
// is a difference of integers on binary grids, computed exactly (exact_difference.hpp) and
// rounded down onto a grid 48 bits below Q's; the division by 2k is a product with the integer
// neighbours of 2^64 / (2k), and the sums over k (the magnitudes', and the alternating one with
// the sum of its roundings beside it) stay exact integers until one magnitude, rounded up, ends
// each. Why: the two terms cancel to the residual's few bits, so that in 64-bit balls (Arb;
// Johansson 2017, IEEE Trans. Computers 66) each coefficient was rounded by 2^-64 of the
// integral rather than of the residual, and cost four calls (8% of a certified run's
// instructions in the coefficient form; docs/certified.md, "Where rounding goes", has the
// figures). A term whose integers do not fit (FLINT's sums beyond 128 bits, a coefficient of Q
// beyond 62 bits, or a Q far from the integral) takes the path in balls, as before.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/exact_difference.hpp>
#include <eulervop/certify/detail/short_integer_series.hpp>

#include <arb.h>
#include <flint/fmpz.h>
#include <flint/fmpz_poly.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace eulervop::detail {

// The sums of products behind a residual, as the integral needs them: their length and the
// differences S_{k-1} - S_{k+1} (2 S_0 - S_2 for k = 1), exactly. Either FLINT's integers or the
// 128-bit sums of short_integer_series.hpp, which exact() also gives as one integer (false:
// FLINT's, which take the path in balls).
struct flint_sums {
  const fmpz_poly_struct* p;
  slong length() const { return p->length; }
  bool exact(wide_int&, slong) const { return false; }
  void difference(arf_t out, slong k) const {
    fmpz_t d;
    fmpz_init(d);
    const auto S = [&](slong i) -> const fmpz* { return i < p->length ? p->coeffs + i : nullptr; };
    if (k == 1) {
      fmpz_mul_2exp(d, S(0), 1);
      if (S(2)) fmpz_sub(d, d, S(2));
    } else {
      fmpz_set(d, S(k - 1));
      if (S(k + 1)) fmpz_sub(d, d, S(k + 1));
    }
    arf_set_fmpz(out, d);
    fmpz_clear(d);
  }
};
struct wide_sums {
  const std::vector<wide_int>* s;
  slong length() const {
    slong n = static_cast<slong>(s->size());
    while (n > 0 && (*s)[static_cast<std::size_t>(n - 1)] == 0) --n;
    return n;
  }
  bool exact(wide_int& out, slong k) const {
    const auto S = [&](slong i) -> wide_int { return i < static_cast<slong>(s->size()) ? (*s)[static_cast<std::size_t>(i)] : 0; };
    out = k == 1 ? 2 * S(0) - S(2) : S(k - 1) - S(k + 1);
    return true;
  }
  void difference(arf_t out, slong k) const {
    wide_int d;
    exact(d, k);
    set_wide(out, d);
  }
};

// Arb numbers in one array.
class arb_vector {
 public:
  arb_vector() = default;
  arb_vector(const arb_vector&) = delete;
  arb_vector& operator=(const arb_vector&) = delete;
  ~arb_vector() {
    if (v_) _arb_vec_clear(v_, n_);
  }
  void reserve(slong n) {
    if (n <= n_) return;
    if (v_) _arb_vec_clear(v_, n_);
    v_ = _arb_vec_init(n);
    n_ = n;
  }
  arb_ptr operator[](slong k) { return v_ + k; }

 private:
  arb_ptr v_ = nullptr;
  slong n_ = 0;
};

// The bound of one segment's residuals. The integral's factors hl 2^e / (2k), k = 1 .. n, as
// hl = +-(M 2^m + eps), M the top 128 bits of |hl|, and 2^64 / (2k) between two integers; as
// balls for the path in balls (FLINT's sums, or a term whose integers do not fit), computed when
// that path first needs them.
class integral_residual {
 public:
  void set_factors(slong n, const ball& hl, slong e, slong prec);
  // out >= sup |2^e hl int S - Q + delta| over [-1, 1] (|T_k| <= 1: the sum of the coefficients'
  // magnitudes), for S = sum n_k T_k on the grid 2^e with the remainder `rem` (n_k: `sum`, at most
  // n of set_factors() long), Q = q 2^f exactly and delta the identity (1) or 0.
  template <class Sums>
  void sup(mag_t out, const Sums& sum, const mag_t rem, const fmpz_poly_t q, slong f, int identity);

 private:
  // The exact terms' sums on the grid 2^(g - 64), g = f - 48: 2k (b_k - Q_k) less eps's part is
  // 2^g (W_k + r_k), W_k an integer, |r_k| < 1, and 2^64 / (2k) lies in [lo_k, hi_k], hi_k - lo_k
  // <= 1. So sum |b_k - Q_k| <= sum (|W_k| + 1) hi_k <= sum |W_k| lo_k + sum |W_k| + sum hi_k,
  // and the alternating sum of b_k - Q_k is that of W_k lo_k (its positive and negative terms)
  // within sum |W_k| + sum (lo_k + 1). sum |d_k| hi_k for eps.
  struct sums {
    limbs256 positive, negative, W, eps;
    wide_uint hi = 0, lo = 0;  // sum hi_k, sum (lo_k + 1)
  };
  template <class Sums>
  bool exact_term(sums& a, const Sums& sum, slong k, const fmpz* q, slong t);
  template <class Sums>
  void ball_term(mag_t out, const Sums& sum, slong k, const fmpz* q, slong f);
  void constant_term(mag_t out, const sums& a, const fmpz_poly_t q, slong n, slong f, slong g, int identity);
  void ball_factors();

  slong prec_ = 0, n_ = 0, e_ = 0;
  ball hl_;
  bool factors_ = false;  // factor_ set for hl_
  arb_vector factor_;     // hl 2^e / (2k) at k
  std::vector<std::uint64_t> lo_, hi_;  // floor and ceil of 2^64 / (2k) at k
  wide_uint M_ = 0;
  slong A_ = 0;  // m + e
  bool negative_ = false;
  mag_value eps_, hl_mag_;  // >= |eps| 2^e, >= |hl|
  ball b_, q_, c0_;  // c0_: the path in balls' part of the constant term
};

inline void integral_residual::set_factors(slong n, const ball& hl, slong e, slong prec) {
  prec_ = prec;
  n_ = n;
  e_ = e;
  arb_set(hl_.get(), hl.get());
  factors_ = false;
  if (static_cast<slong>(lo_.size()) < n + 1) {
    lo_.resize(static_cast<std::size_t>(n + 1));
    hi_.resize(static_cast<std::size_t>(n + 1));
    for (slong k = 1; k <= n; ++k) {
      const std::uint64_t half = std::uint64_t{1} << 63, K = static_cast<std::uint64_t>(k);  // 2^64 / (2k) = 2^63 / k
      lo_[static_cast<std::size_t>(k)] = half / K;
      hi_[static_cast<std::size_t>(k)] = half / K + (half % K != 0);
    }
  }
  arb_get_mag(hl_mag_.m, hl.get());
  // |hl| = M 2^m + eps: the mantissa's top 128 bits, the rest (below 2^m) and the radius in eps.
  fmpz_t man, ex;
  fmpz_init(man);
  fmpz_init(ex);
  arf_get_fmpz_2exp(man, ex, arb_midref(hl.get()));
  negative_ = fmpz_sgn(man) < 0;
  fmpz_abs(man, man);
  slong m = fmpz_get_si(ex);
  mag_set(eps_.m, arb_radref(hl.get()));
  if (fmpz_bits(man) > 128) {
    const slong drop = static_cast<slong>(fmpz_bits(man)) - 128;
    fmpz_tdiv_q_2exp(man, man, static_cast<ulong>(drop));
    m += drop;
    mag_add_ui_2exp_si(eps_.m, eps_.m, 1, m);
  }
  mp_limb_t high = 0, low = 0;
  fmpz_get_uiui(&high, &low, man);
  M_ = (static_cast<wide_uint>(high) << 64) | low;
  A_ = m + e;
  mag_mul_2exp_si(eps_.m, eps_.m, e);
  fmpz_clear(man);
  fmpz_clear(ex);
}

inline void integral_residual::ball_factors() {
  factor_.reserve(n_ + 1);
  for (slong k = 1; k <= n_; ++k) {
    arb_mul_2exp_si(factor_[k], hl_.get(), e_ - 1);
    arb_div_ui(factor_[k], factor_[k], static_cast<ulong>(k), prec_);
  }
  factors_ = true;
}

// Term k into the sums, exactly: false (and nothing added) where its integers do not fit. With
// X = M |d_k| and y = 2k |q_k|, 2k (b_k - Q_k) less eps's part is 2^g (+-X 2^-t -+ y 2^48),
// t = g - m - e: W_k = +-floor(X 2^-t) -+ y 2^48 when both terms are below 2^126.
template <class Sums>
bool integral_residual::exact_term(sums& a, const Sums& sum, slong k, const fmpz* q, slong t) {
  wide_int w = 0;
  if (!sum.exact(w, k) || (q != nullptr && COEFF_IS_MPZ(*q))) return false;
  const auto dk = static_cast<wide_uint>(w < 0 ? -w : w);
  const slong qk = q ? *q : 0;
  const auto y = static_cast<wide_uint>(qk < 0 ? -qk : qk) * static_cast<wide_uint>(2 * k);
  wide_uint xt = 0;
  if (y >> 78 != 0 || !scaled_floor(xt, multiply(M_, dk), t, 126)) return false;
  const auto x = static_cast<wide_int>(xt), y48 = static_cast<wide_int>(y << 48);
  const wide_int W = ((w < 0) != negative_ ? -x : x) - (qk < 0 ? -y48 : y48);
  const auto Wabs = static_cast<wide_uint>(W < 0 ? -W : W);
  const std::uint64_t lo = lo_[static_cast<std::size_t>(k)], hi = hi_[static_cast<std::size_t>(k)];
  add_product((W < 0) != (k % 2 == 0) ? a.negative : a.positive, Wabs, lo);  // (-1)^(k+1) W_k's sign
  add(a.W, Wabs);
  a.hi += hi;
  a.lo += lo + 1;
  if (!mag_is_zero(eps_.m)) add_product(a.eps, dk, hi);
  return true;
}

// Term k in balls (hl's eps within its factor): out = |b_k - Q_k| rounded up, c0_ += its
// alternating part.
template <class Sums>
void integral_residual::ball_term(mag_t out, const Sums& sum, slong k, const fmpz* q, slong f) {
  if (!factors_) ball_factors();
  sum.difference(arb_midref(b_.get()), k);
  mag_zero(arb_radref(b_.get()));
  arb_mul(b_.get(), b_.get(), factor_[k], prec_);
  if (q) {
    set_fmpz_2exp(arb_midref(q_.get()), q, f);
    mag_zero(arb_radref(q_.get()));
    arb_sub(b_.get(), b_.get(), q_.get(), prec_);
  }
  arb_get_mag(out, b_.get());
  (k % 2 ? arb_add : arb_sub)(c0_.get(), c0_.get(), b_.get(), prec_);
}

template <class Sums>
void integral_residual::sup(mag_t out, const Sums& sum, const mag_t rem, const fmpz_poly_t q, slong f, int identity) {
  const slong n = sum.length(), nq = q->length;
  // The grid 2^g, 48 bits below Q's: a term of the residual's size (a few units of Q's grid)
  // fits 128 bits there, and its rounding down costs 2^-48 of a unit.
  const slong g = f - 48;
  sums a;
  mag_value m;
  mag_zero(out);
  arb_zero(c0_.get());
  for (slong k = 1; k <= n; ++k) {
    const fmpz* qk = k < nq ? q->coeffs + k : nullptr;
    if (exact_term(a, sum, k, qk, g - A_)) continue;
    ball_term(m.m, sum, k, qk, f);
    mag_add(out, out, m.m);
  }
  limbs256 magnitude = a.positive;
  add(magnitude, a.negative);
  add(magnitude, a.W);
  add(magnitude, a.hi);
  mag_set_limbs_2exp(m.m, magnitude, g - 64);
  mag_add(out, out, m.m);
  constant_term(m.m, a, q, n, f, g, identity);
  mag_add(out, out, m.m);
  // eps's part of the exact terms, in their magnitudes and in the constant term: 2 |eps| 2^e
  // sum |d_k| / (2k).
  mag_set_limbs_2exp(m.m, a.eps, -63);
  mag_addmul(out, m.m, eps_.m);
  for (slong k = n + 1; k < nq; ++k) {
    mag_set_fmpz(m.m, q->coeffs + k);
    mag_mul_2exp_si(m.m, m.m, f);
    mag_add(out, out, m.m);
  }
  // The product's remainder integrates to at most 2 |hl| rem.
  mag_mul(m.m, hl_mag_.m, rem);
  mag_mul_2exp_si(m.m, m.m, 1);
  mag_add(out, out, m.m);
}

// out >= |b_0 + delta - Q_0|, b_0 = sum_{k>=1} (-1)^(k+1) b_k: the exact terms' signed sum (with
// its error), plus sum_{k>=1} (-1)^(k+1) Q_k + delta - Q_0 exactly, plus the path in balls' part.
// The constant term cancels like the others, so it is summed before it is rounded.
inline void integral_residual::constant_term(mag_t out, const sums& a, const fmpz_poly_t q, slong n, slong f, slong g,
                                             int identity) {
  const bool negative = less(a.positive, a.negative);
  const limbs256 v = negative ? subtract(a.negative, a.positive) : subtract(a.positive, a.negative);
  mp_limb_t limbs[4];
  slong len = 0;
  for (int i = 0; i < 4; ++i) {
    limbs[i] = v.w[i];
    if (v.w[i] != 0) len = i + 1;
  }
  arb_zero(b_.get());
  if (len > 0) arf_set_mpn(arb_midref(b_.get()), limbs, len, negative);
  arb_mul_2exp_si(b_.get(), b_.get(), g - 64);
  // sum_{k>=1} (-1)^(k+1) q_k - q_0, in 128 bits where the q_k are FLINT's small integers (below
  // 2^62), in FLINT's otherwise.
  fmpz_t t;
  fmpz_init(t);
  wide_int small = 0;
  for (slong k = 0; k <= std::min(n, q->length - 1); ++k) {
    const bool plus = k % 2 == 1;
    if (COEFF_IS_MPZ(q->coeffs[k]))
      (plus ? fmpz_add : fmpz_sub)(t, t, q->coeffs + k);
    else
      small += plus ? q->coeffs[k] : -q->coeffs[k];
  }
  const auto u = static_cast<unsigned __int128>(small);
  fmpz_t w;
  fmpz_init(w);
  fmpz_set_signed_uiui(w, static_cast<ulong>(u >> 64), static_cast<ulong>(u));
  fmpz_add(t, t, w);
  fmpz_clear(w);
  arb_set_fmpz(q_.get(), t);
  arb_mul_2exp_si(q_.get(), q_.get(), f);
  arb_add_si(q_.get(), q_.get(), identity, ARF_PREC_EXACT);
  arb_add(b_.get(), b_.get(), q_.get(), ARF_PREC_EXACT);
  arb_add(b_.get(), b_.get(), c0_.get(), prec_);
  mag_value error;
  limbs256 e = a.W;
  add(e, a.lo);
  mag_set_limbs_2exp(error.m, e, g - 64);
  arb_add_error_mag(b_.get(), error.m);
  arb_get_mag(out, b_.get());
  fmpz_clear(t);
}

}  // namespace eulervop::detail

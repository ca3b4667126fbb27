// The sup bound of a residual of the linear flow (ball_linear_flow.hpp), rho = hl int S - Q (+ I),
// where the integrand S = sum_k J_ik Y_k is a sum of products of integer polynomials on binary
// grids, exact in integers: only the integral's factors hl / (2k) and the subtraction of Q are
// done in balls (Arb), at a precision a bound needs (Johansson 2017, IEEE Trans. Computers 66).
// The integral of a Chebyshev series is Clenshaw and Curtis's (1960) recurrence, as integrate() in
// chebyshev_model.hpp.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/short_integer_series.hpp>

#include <arb.h>
#include <flint/fmpz_poly.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace eulervop::detail {

// The sums of products behind a residual, as the integral needs them: their length and the
// differences S_{k-1} - S_{k+1} (2 S_0 - S_2 for k = 1), exactly. Either FLINT's integers or the
// 128-bit sums of short_integer_series.hpp.
struct flint_sums {
  const fmpz_poly_struct* p;
  slong length() const { return p->length; }
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
  void difference(arf_t out, slong k) const {
    const auto S = [&](slong i) -> wide_int { return i < static_cast<slong>(s->size()) ? (*s)[static_cast<std::size_t>(i)] : 0; };
    set_wide(out, k == 1 ? 2 * S(0) - S(2) : S(k - 1) - S(k + 1));
  }
};

// hl 2^e / (2k) for k = 1 .. n, the integral's factors (in balls at `prec`).
inline void integral_factors(std::vector<ball>& out, slong n, const ball& hl, slong e, slong prec) {
  out.resize(static_cast<std::size_t>(std::max<slong>(n, 0)) + 1);
  for (slong k = 1; k <= n; ++k) {
    arb_mul_2exp_si(out[static_cast<std::size_t>(k)].get(), hl.get(), e - 1);
    arb_div_ui(out[static_cast<std::size_t>(k)].get(), out[static_cast<std::size_t>(k)].get(), static_cast<ulong>(k), prec);
  }
}

// The integral and the difference in one pass over the sums' integer coefficients S_k (in units
// of 2^e): int_{-1}^s sum S_k T_k has the coefficients b_1 = S_0 - S_2 / 2, b_k = (S_{k-1} -
// S_{k+1}) / (2k) for k >= 2, and b_0 = sum_{k>=1} (-1)^(k+1) b_k, so that it vanishes at -1
// (integrate() in chebyshev_model.hpp); each difference is exact in integers, then multiplied by
// its factor hl 2^e / (2k) (`factors`, integral_factors(), at least the sums' length of them).
//
// out >= sup |2^e hl int S - Q + delta| over [-1, 1] (|T_k| <= 1: the sum of the coefficients'
// magnitudes), for S = sum n_k T_k on the grid 2^e with the remainder `rem`, Q = `subtract` (exact
// or with its own remainder) and delta the identity (1) or 0.
template <class Sums>
void integral_residual_sup(mag_t out, const Sums& sum, const std::vector<ball>& factors, const mag_t rem,
                           const ball& hl, const chebyshev_model& subtract, int identity, slong prec) {
  const slong n = sum.length();
  ball b, c0;
  mag_t m;
  mag_init(m);
  mag_zero(out);
  for (slong k = 1; k <= n; ++k) {
    sum.difference(arb_midref(b.get()), k);
    mag_zero(arb_radref(b.get()));
    arb_mul(b.get(), b.get(), factors[static_cast<std::size_t>(k)].get(), prec);
    if (k % 2)
      arb_add(c0.get(), c0.get(), b.get(), prec);
    else
      arb_sub(c0.get(), c0.get(), b.get(), prec);
    if (k < subtract.length()) arb_sub(b.get(), b.get(), subtract.coeff(k), prec);
    arb_get_mag(m, b.get());
    mag_add(out, out, m);
  }
  if (identity) arb_add_ui(c0.get(), c0.get(), 1, prec);
  if (subtract.length() > 0) arb_sub(c0.get(), c0.get(), subtract.coeff(0), prec);
  arb_get_mag(m, c0.get());
  mag_add(out, out, m);
  for (slong k = n + 1; k < subtract.length(); ++k) {
    arb_get_mag(m, subtract.coeff(k));
    mag_add(out, out, m);
  }
  // The product's remainder integrates to at most 2 |hl| rem.
  arb_get_mag(m, hl.get());
  mag_mul(m, m, rem);
  mag_mul_2exp_si(m, m, 1);
  mag_add(out, out, m);
  mag_add(out, out, subtract.remainder());
  mag_clear(m);
}

}  // namespace eulervop::detail

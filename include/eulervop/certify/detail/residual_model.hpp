// The Picard residual of a segment as a Chebyshev model (docs/certified.md, "The general path",
// step 2): r(s) = P(-1) + hl int_{-1}^s F - P(s), with F the field along P.
//
// The integral's coefficients are hl (a_{k-1} - a_{k+1}) / (2k) (hl (2 a_0 - a_2) / 2 for k = 1;
// Mason and Handscomb, "Chebyshev Polynomials", 2003, section 2.4.4), and its constant term the
// one for which it vanishes at s = -1, where T_k = (-1)^k. The weights hl / (2k) are the same
// for every component of a segment, so they are enclosed once per segment.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>

#include <arb.h>

#include <algorithm>
#include <vector>

namespace eulervop::detail {

// The integral's weights per coefficient k = 1..n, as pairs that multiply (F_{k-1}, F_{k+1}):
// (2 w_1, -w_1) and (w_k, -w_k), w_k = hl / (2k).
class integral_weights {
 public:
  void set(const ball& hl, slong n, slong prec) {
    if (static_cast<slong>(pairs_.size()) < 2 * (n + 1)) pairs_.resize(static_cast<std::size_t>(2 * (n + 1)));
    for (slong k = 1; k <= n; ++k) {
      arb_ptr p = pairs_[static_cast<std::size_t>(2 * k)].get();
      arb_div_ui(p, hl.get(), static_cast<ulong>(2 * k), prec);
      arb_neg(p + 1, p);
      if (k == 1) arb_mul_2exp_si(p, p, 1);
    }
    arb_one(one_.get());
  }
  arb_srcptr pair(slong k) const { return pairs_[static_cast<std::size_t>(2 * k)].get(); }
  arb_srcptr one() const { return one_.get(); }  // the sums' weight (a dot product of step 0)

 private:
  std::vector<ball> pairs_;  // contiguous: ball is an arb_struct
  ball one_;
};

// r = start + hl int_{-1}^s F - P and r1 = r(1) (a ball holding every value r's remainder
// allows). `at_start` holds start - p(-1) for P's polynomial p (0 where start is P's value at
// s = -1, as for a segment's interpolant); `w` holds the weights up to k = F.length(). r is
// distinct from F and P.
//
// Each coefficient k >= 1 is one dot product, w (F_{k-1} - F_{k+1}) - P_k rounded once. With
// R_odd and R_even the sums of r's odd and even coefficients (k >= 1), r(-1) = at_start gives the
// constant term at_start + R_odd - R_even, and r(1) = at_start + 2 R_odd (T_k(+-1) = (+-1)^k).
inline void picard_residual_model(chebyshev_model& r, ball& r1, const chebyshev_model& F, const ball& hl,
                                  const integral_weights& w, const ball& at_start, const chebyshev_model& P,
                                  slong prec) {
  const slong n = F.length(), np = P.length();
  const slong len = std::max(n + 1, np);
  r.reserve_length(len);
  for (slong k = 1; k < len; ++k) {
    arb_ptr c = r.coeff(k);
    arb_srcptr p = k < np ? P.coeff(k) : nullptr;
    const slong terms = k - 1 >= n ? 0 : k + 1 < n ? 2 : 1;  // F_{k-1}, F_{k+1}
    if (terms == 0) {
      if (p) arb_neg(c, p); else arb_zero(c);
      continue;
    }
    arb_dot(c, p, 1, F.coeff(k - 1), 2, w.pair(k), 1, terms, prec);  // P_k - w (...)
    arb_neg(c, c);
  }
  const slong m = len - 1;  // r_1 .. r_m
  ball odd, d;
  arb_dot(odd.get(), nullptr, 0, r.coeff(1), 2, w.one(), 0, (m + 1) / 2, prec);
  arb_add(d.get(), at_start.get(), odd.get(), prec);
  if (m >= 2)
    arb_dot(r.coeff(0), d.get(), 1, r.coeff(2), 2, w.one(), 0, m / 2, prec);
  else
    arb_set(r.coeff(0), d.get());
  arb_get_mag(r.remainder(), hl.get());
  mag_mul(r.remainder(), r.remainder(), F.remainder());
  mag_mul_2exp_si(r.remainder(), r.remainder(), 1);
  mag_add(r.remainder(), r.remainder(), P.remainder());
  arb_mul_2exp_si(r1.get(), odd.get(), 1);
  arb_add(r1.get(), r1.get(), at_start.get(), prec);
  arb_add_error_mag(r1.get(), r.remainder());
}

}  // namespace eulervop::detail

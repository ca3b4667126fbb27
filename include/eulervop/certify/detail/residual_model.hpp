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

// hl / (2k) for k = 1..n.
class integral_weights {
 public:
  void set(const ball& hl, slong n, slong prec) {
    if (static_cast<slong>(w_.size()) < n + 1) w_.resize(static_cast<std::size_t>(n + 1));
    for (slong k = 1; k <= n; ++k) arb_div_ui(w_[k].get(), hl.get(), static_cast<ulong>(2 * k), prec);
    arb_one(one_.get());
  }
  arb_srcptr operator[](slong k) const { return w_[static_cast<std::size_t>(k)].get(); }
  arb_srcptr one() const { return one_.get(); }  // the sums' weight (a dot product of step 0)

 private:
  std::vector<ball> w_;
  ball one_;
};

// r = start + hl int_{-1}^s F - P and r1 = r(1) (a ball holding every value r's remainder
// allows), `end` a ball holding P(1). `w` holds hl / (2k) up to k = F.length(). r is distinct from
// F and P.
//
// With b_k the integral's coefficients and S_odd, S_even the sums of its odd and even ones, the
// constant term is start + S_odd - S_even (so that the integral vanishes at s = -1), and since
// T_k(1) = 1 the integral at s = 1 is 2 S_odd: r(1) = start - P(1) + 2 S_odd, each sum one of
// Arb's dot products over half the coefficients.
inline void picard_residual_model(chebyshev_model& r, ball& r1, const chebyshev_model& F, const ball& hl,
                                  const integral_weights& w, const ball& start, const chebyshev_model& P,
                                  const ball& end, slong prec) {
  const slong n = F.length();
  const slong len = std::max(n + 1, P.length());
  r.reserve_length(len);
  ball d;
  for (slong k = 1; k < len; ++k) {
    arb_ptr b = r.coeff(k);
    if (k > n) {
      arb_zero(b);
      continue;
    }
    arb_srcptr next = k + 1 < n ? F.coeff(k + 1) : nullptr;
    if (k == 1) {
      arb_mul_2exp_si(d.get(), F.coeff(0), 1);
      if (next) arb_sub(d.get(), d.get(), next, prec);
      arb_mul(b, d.get(), w[k], prec);
    } else if (next) {
      arb_sub(d.get(), F.coeff(k - 1), next, prec);
      arb_mul(b, d.get(), w[k], prec);
    } else {
      arb_mul(b, F.coeff(k - 1), w[k], prec);
    }
  }
  const slong m = std::min(n, len - 1);  // b_1 .. b_m
  ball odd;
  arb_dot(odd.get(), nullptr, 0, r.coeff(1), 2, w.one(), 0, (m + 1) / 2, prec);
  arb_add(d.get(), start.get(), odd.get(), prec);
  if (m >= 2)
    arb_dot(r.coeff(0), d.get(), 1, r.coeff(2), 2, w.one(), 0, m / 2, prec);
  else
    arb_set(r.coeff(0), d.get());
  const slong np = P.length();
  for (slong k = 0; k < np; ++k) arb_sub(r.coeff(k), r.coeff(k), P.coeff(k), prec);
  arb_get_mag(r.remainder(), hl.get());
  mag_mul(r.remainder(), r.remainder(), F.remainder());
  mag_mul_2exp_si(r.remainder(), r.remainder(), 1);
  mag_add(r.remainder(), r.remainder(), P.remainder());
  arb_mul_2exp_si(r1.get(), odd.get(), 1);
  arb_add(r1.get(), r1.get(), start.get(), prec);
  arb_sub(r1.get(), r1.get(), end.get(), prec);
  arb_add_error_mag(r1.get(), r.remainder());
}

}  // namespace eulervop::detail

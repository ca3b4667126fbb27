// The Picard residual of a segment as a Chebyshev model (docs/certified.md, "The general path",
// step 2): r(s) = P(-1) + hl int_{-1}^s F - P(s), with F the field along P.
//
// The integral's coefficients are hl (a_{k-1} - a_{k+1}) / (2k) (hl (2 a_0 - a_2) / 2 for k = 1;
// Mason and Handscomb, "Chebyshev Polynomials", 2003, section 2.4.4), and its constant term the
// one for which it vanishes at s = -1, where T_k = (-1)^k. The weights hl / (2k) are the same
// for every component of a segment, so they are enclosed once per segment; the alternating sum
// and r(1) = sum_k r_k are Arb's dot products (one rounding each instead of one per term).
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>

#include <arb.h>

#include <algorithm>
#include <vector>

namespace eulervop::detail {

// hl / (2k) for k = 1..n, and the signs the sums take (for sums of up to `terms` terms).
class integral_weights {
 public:
  void set(const ball& hl, slong n, slong terms, slong prec) {
    if (static_cast<slong>(w_.size()) < n + 1) w_.resize(static_cast<std::size_t>(n + 1));
    for (slong k = 1; k <= n; ++k) arb_div_ui(w_[k].get(), hl.get(), static_cast<ulong>(2 * k), prec);
    while (static_cast<slong>(alternating_.size()) < std::max(n + 1, terms)) {
      alternating_.push_back(alternating_.size() % 2 ? 1 : -1);  // (-1)^(k+1)
      ones_.push_back(1);
    }
  }
  arb_srcptr operator[](slong k) const { return w_[static_cast<std::size_t>(k)].get(); }
  const slong* alternating() const { return alternating_.data(); }  // (-1)^(k+1) at k
  const slong* ones() const { return ones_.data(); }

 private:
  std::vector<ball> w_;
  std::vector<slong> alternating_, ones_;
};

// r = start + hl int_{-1}^s F - P and r1 = r(1) (a ball holding every value r's remainder
// allows). `w` holds hl / (2k) up to k = F.length(), and signs for F.length() + 1 and P.length()
// terms. r is distinct from F and P.
inline void picard_residual_model(chebyshev_model& r, ball& r1, const chebyshev_model& F, const ball& hl,
                                  const integral_weights& w, const ball& start, const chebyshev_model& P,
                                  slong prec) {
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
  // The constant term: start + sum_{k >= 1} (-1)^(k+1) b_k, before P.
  arb_dot_si(r.coeff(0), start.get(), 0, r.coeff(1), 1, w.alternating() + 1, 1, std::min(n, len - 1), prec);
  const slong np = P.length();
  for (slong k = 0; k < np; ++k) arb_sub(r.coeff(k), r.coeff(k), P.coeff(k), prec);
  arb_get_mag(r.remainder(), hl.get());
  mag_mul(r.remainder(), r.remainder(), F.remainder());
  mag_mul_2exp_si(r.remainder(), r.remainder(), 1);
  mag_add(r.remainder(), r.remainder(), P.remainder());
  arb_dot_si(r1.get(), nullptr, 0, r.coeffs(), 1, w.ones(), 1, len, prec);
  arb_add_error_mag(r1.get(), r.remainder());
}

}  // namespace eulervop::detail

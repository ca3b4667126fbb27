// The linear equation along a segment's polynomial P that the certificate's error terms obey
// (docs/certified.md, "How", step 3): E' = J E with J = DN(P) the Jacobian of the quadratic part
// of Euler's equations, its entries as the double-precision parts compute them, and the bound at
// the segment's end of a solution from its Picard residual.
#pragma once

#include <eulervop/certify/detail/segment_polynomial.hpp>
#include <eulervop/certify/exact_problem.hpp>
#include <eulervop/certify/interval.hpp>

#include <mpfi.h>

#include <array>
#include <cmath>
#include <utility>

namespace eulervop::detail {

// The precision of the enclosures that leave the linear parts for the error box: r(b), Phi(b),
// u(b) and their error bounds. They are errors far below the state, or factors of them, whose
// last digits do not matter; what cancels is computed before, at the working precision.
inline constexpr mpfr_prec_t error_bits = 64;

// J_ik = coefficient * P_c.
struct jacobian_entry {
  int k, c;
  double coefficient;
};
// The two nonzero entries of each row, columns ascending (the order of the double sums).
using jacobian_rows = std::array<std::array<jacobian_entry, 2>, 3>;

// From the quadratic pairs: row i with (j, k) = quadratic_pair[i] has J_ij = a_i P_k and
// J_ik = a_i P_j (euler_problem::jacobian). `a`: unit_coefficients.
inline jacobian_rows jacobian_pattern(const std::array<int, 3>& a) {
  jacobian_rows rows;
  for (int i = 0; i < 3; ++i) {
    const auto [j, k] = exact_problem::quadratic_pair[i];
    jacobian_entry first{j, k, static_cast<double>(a[i])}, second{k, j, static_cast<double>(a[i])};
    if (second.k < first.k) std::swap(first, second);
    rows[i] = {first, second};
  }
  return rows;
}

// A segment's bounds as doubles rounded up (hl itself as the nearest double, and hl_error >= its
// distance to the exact hl): mu >= the logarithmic norm of J, jmax >= |J|_2, h = 2 hl.
struct linear_growth {
  double hl, mu, jmax, h, hl_error;

  // A Picard residual bound sup|R| of a linear solution on the segment, as an error bound at its
  // end: E = R + hl int J E gives |E(1)| <= sup|R| (1 + h exp(mu h) |J|).
  void error_at_end(interval& out, double supR, const segment_polynomial& P) const {
    if (!std::isfinite(supR)) P.fail(outcome_kind::certify_non_finite);
    mpfi_set_d(out.get(), mu);
    mpfi_mul_d(out.get(), out.get(), h);
    exp_at_64_bits(out);
    mpfi_mul_d(out.get(), out.get(), h);
    mpfi_mul_d(out.get(), out.get(), jmax);
    mpfi_add_ui(out.get(), out.get(), 1);
    mpfi_mul_d(out.get(), out.get(), supR);
  }
};

}  // namespace eulervop::detail

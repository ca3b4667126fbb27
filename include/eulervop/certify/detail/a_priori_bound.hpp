// The a-priori bound of a segment (docs/certified.md, "How", step 2) and the bounds around it.
//
// With e = y - P, e(tau) = e(a) + r(tau) + int_a^tau (J e + N(e)), J = DN(P) and N the quadratic
// part, |J|_2 <= jmax and |N(e)|_2 <= c |e|_2^2 (euler_problem.hpp: jacobian_norm_bound,
// remainder_bound). With C = |e(a)| + sup |r| and L = jmax + c R, |e| stays below R on the
// segment if C exp(L h) < R (Gronwall, continued while |e| < R). We try R = 2 C exp(jmax h).
// mu bounds the logarithmic norm of J (log_norm_bound), so |Phi(b, s)| <= exp(mu (b - s)).
#pragma once

#include <eulervop/certify/detail/linearized_flow.hpp>
#include <eulervop/certify/detail/segment_polynomial.hpp>
#include <eulervop/certify/exact_problem.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/model/euler_problem.hpp>

#include <mpfi.h>

#include <vector>

namespace eulervop::detail {

// At error_bits (linearized_flow.hpp): bounds of magnitudes and of errors far below the state.
struct segment_bounds {
  segment_bounds()
      : rho_a(interval::zero(error_bits)), mu(interval::zero(error_bits)), jmax(interval::zero(error_bits)),
        rsup2(interval::zero(error_bits)), R(interval::zero(error_bits)), ell(interval::zero(error_bits)),
        C_(interval::zero(error_bits)), t_(interval::zero(error_bits)) {}

  // mu, jmax and rsup2 for P with the residual bounds `rsup`: they do not depend on e(a).
  void linear(const exact_problem& problem, const segment_polynomial& P, const std::vector<interval>& rsup);
  // R and ell, once rho_a holds |e(a)| (fails when no a-priori bound closes).
  void a_priori(const exact_problem& problem, const segment_polynomial& P);
  // The doubles of the linear parts (variational matrix, integral term).
  linear_growth growth(const segment_polynomial& P) {
    const double hl = mpfi_get_d(P.hl.get());
    mpfi_sub_d(t_.get(), P.hl.get(), hl);  // the exact hl (113 bits in quad) less its double
    return {hl, magnitude_up(mu), magnitude_up(jmax), magnitude_up(P.h), magnitude_up(t_)};
  }

  interval rho_a;  // [0, an upper bound of |e(a)|_2]
  interval mu;     // >= the logarithmic norm of J on the segment
  interval jmax;   // >= |J|_2 on the segment
  interval rsup2;  // >= sup |r|_2
  interval R;      // [0, R]: |e| <= R on the segment
  interval ell;    // h exp(mu h) c R^2: the quadratic part of the integral term at b

 private:
  interval C_, t_;
};

inline void segment_bounds::linear(const exact_problem& problem, const segment_polynomial& P,
                                   const std::vector<interval>& rsup) {
  const interval_precision_scope scope(error_bits);
  mu = log_norm_bound(problem, P.psup);
  jmax = jacobian_norm_bound(problem, P.psup);
  mpfi_set_ui(rsup2.get(), 0);
  for (int i = 0; i < 3; ++i) {
    mpfi_sqr(t_.get(), rsup[i].get());
    mpfi_add(rsup2.get(), rsup2.get(), t_.get());
  }
  mpfi_sqrt(rsup2.get(), rsup2.get());
}

inline void segment_bounds::a_priori(const exact_problem& problem, const segment_polynomial& P) {
  const interval_precision_scope scope(error_bits);
  mpfi_add(C_.get(), rho_a.get(), rsup2.get());
  mpfi_mul(t_.get(), jmax.get(), P.h.get());
  exp_at_64_bits(t_);
  mpfi_mul(R.get(), C_.get(), t_.get());
  mpfi_mul_ui(R.get(), R.get(), 2);
  to_upper_point(R);
  interval L = remainder_bound(problem, R);
  mpfi_add(L.get(), L.get(), jmax.get());
  mpfi_mul(L.get(), L.get(), P.h.get());
  exp_at_64_bits(L);
  mpfi_mul(L.get(), L.get(), C_.get());
  if (!(mpfi_cmp(L.get(), R.get()) < 0)) P.fail(outcome_kind::certify_a_priori);
  to_zero_hull(R);

  // The quadratic part of the integral term of step 3, h exp(mu h) c R^2 (its linear part,
  // int Phi J r, is signed_integral_term's).
  mpfi_sqr(t_.get(), R.get());
  ell = remainder_bound(problem, t_);
  mpfi_mul(t_.get(), mu.get(), P.h.get());
  exp_at_64_bits(t_);
  mpfi_mul(ell.get(), ell.get(), t_.get());
  mpfi_mul(ell.get(), ell.get(), P.h.get());
}

}  // namespace eulervop::detail

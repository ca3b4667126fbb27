// The radius of a physical scene's row in rad/s (docs/certified.md, "What is proven"): a bound
// of |omega(t) - omega*|_2 at the row's t, omega* the printed rates.
//
// The row's exact tau = t dtau/dt (Eq. 4) differs from its binary tau by a rounding: the bound at
// tau moves by that difference times a bound of |dOmega/dtau| there. omega is the axes' map of
// sqrt(A_i) Omega_i (Eq. 2), so |d omega| <= max sqrt(A_i) |d Omega|, plus the printed digits'
// distance to the map of P.
#pragma once

#include <eulervop/certify/interval.hpp>
#include <eulervop/certify/row_enclosure.hpp>
#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/model/physical_scaling.hpp>

#include <mpfi.h>

#include <array>
#include <string>
#include <utility>

namespace eulervop {

class omega_radius {
 public:
  // `scaling`: Eqs. 2-4 of the scene's decimals (scene/scene_exact_problem.hpp: exact_scaling_of).
  explicit omega_radius(physical_scaling<interval> scaling)
      : scaling_(std::move(scaling)), max_(interval::zero(scaling_.tau_rate().bits())) {}

  // [0, the bound] at the row (tau, t) printed as `omega_cells` (in the body's axes), from the
  // enclosure at tau. Also raises max_radius().
  template <scalar T>
  interval at(const row_enclosure& row, const T& tau, const T& t, const std::array<std::string, 3>& omega_cells);

  // The largest radius so far (its right end).
  const interval& max_radius() const { return max_; }

 private:
  physical_scaling<interval> scaling_;
  interval max_;
};

template <scalar T>
interval omega_radius::at(const row_enclosure& row, const T& tau, const T& t,
                          const std::array<std::string, 3>& omega_cells) {
  const mpfr_prec_t bits = max_.bits();
  interval d = interval::zero(bits), x = interval::zero(bits), sum = interval::zero(bits),
           scale = interval::zero(bits), err = interval::zero(bits);
  detail::set_exact(d, t);
  mpfi_mul(d.get(), d.get(), scaling_.tau_rate().get());
  detail::set_exact(x, tau);
  mpfi_sub(d.get(), d.get(), x.get());
  mpfi_abs(d.get(), d.get());
  mpfi_mul(x.get(), d.get(), row.rate.get());
  interval Y = row.state;
  detail::to_upper_point(Y);
  if (!(mpfi_cmp(x.get(), Y.get()) < 0)) {  // never near: the difference is a rounding of tau
    outcome o;
    o.kind = outcome_kind::certification_failed;
    o.cause = outcome_kind::certify_growth;
    o.tau = static_cast<double>(tau);
    throw numerical_failure(o);
  }
  mpfi_add(err.get(), row.error.get(), x.get());  // |y(t rate) - P(tau)|
  const axis_permutation& axes = scaling_.axes();
  for (int i = 0; i < 3; ++i) {
    const interval& sqrtA = scaling_.sqrt_A()[i];
    mpfi_union(scale.get(), scale.get(), sqrtA.get());
    mpfi_mul(x.get(), row.P[i].get(), sqrtA.get());
    if (axes.sign(i) < 0) mpfi_neg(x.get(), x.get());
    detail::set_decimal(d, omega_cells[axes.axis(i)]);
    mpfi_sub(x.get(), x.get(), d.get());
    mpfi_sqr(x.get(), x.get());
    mpfi_add(sum.get(), sum.get(), x.get());
  }
  mpfi_sqrt(sum.get(), sum.get());
  detail::to_upper_point(scale);
  mpfi_mul(err.get(), err.get(), scale.get());
  mpfi_add(err.get(), err.get(), sum.get());
  detail::to_zero_hull(err);
  mpfi_put(max_.get(), err.get());
  return err;
}

}  // namespace eulervop

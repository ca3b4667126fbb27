// Torque-free motion from Omega(0) = (c1, 0, c2) in closed form (Eq. 12), for the certificate's
// tests: (c1 cn u, c1 sn u, c2 dn u), u = c2 tau, modulus k = c1 / c2 < 1; for c1 > c2 the roles
// of the axes swap: (c1 dn v, c2 sn v, c2 cn v), v = c1 tau, modulus c2 / c1 (derived by
// substituting into Eq. 5: each component's derivative matches). Jacobi's functions are Boost.Math's
// jacobi_elliptic in MPFR at the caller's precision; dn is sqrt(1 - k^2 sn^2), Boost's own dn
// being a ratio that degrades near odd multiples of K.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/core/vec3.hpp>

#include <boost/math/special_functions/jacobi_elliptic.hpp>

namespace eulervop::test {

inline vec3<mpfr_real> torque_free_exact(const mpfr_real& c1, const mpfr_real& c2, const mpfr_real& tau) {
  mpfr_real cn, dn;
  if (c1 < c2) {
    const mpfr_real k = c1 / c2;
    const mpfr_real sn = boost::math::jacobi_elliptic(k, c2 * tau, &cn, &dn);
    dn = sqrt(1 - k * k * sn * sn);
    return {c1 * cn, c1 * sn, c2 * dn};
  }
  const mpfr_real k = c2 / c1;
  const mpfr_real sn = boost::math::jacobi_elliptic(k, c1 * tau, &cn, &dn);
  dn = sqrt(1 - k * k * sn * sn);
  return {c1 * dn, c2 * sn, c2 * cn};
}

}  // namespace eulervop::test

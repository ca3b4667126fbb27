// The peer the benchmarks measure against: sn, cn, dn, am, Z(u), E(u) from Boost.Math, in
// double, under a chosen policy (promote_double<false>, or Boost's default, which promotes to
// long double).
//
//   jacobi_elliptic(k, u, &cn, &dn)   -> sn, cn, dn
//   ellint_1(k), ellint_2(k)          -> K, E (the caller's, once per k)
//   am = n pi + atan2(sn, cn) with n = nearest(u / 2K)
//   jacobi_zeta(k, am)                -> Z;   E(u) = Z + (E/K) u
#pragma once

#include <boost/math/policies/policy.hpp>
#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_2.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <boost/math/special_functions/jacobi_zeta.hpp>

#include <cmath>

namespace bench {

using no_promote = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
using default_policy = boost::math::policies::policy<>;

struct six {
  double sn, cn, dn, am, Z, E;
};

template <class Policy>
six boost_set(double u, double k, double K, double E, const Policy& pol) {
  six out;
  out.sn = boost::math::jacobi_elliptic(k, u, &out.cn, &out.dn, pol);
  const double n = std::nearbyint(u / (2 * K));
  const bool even = n == 2 * std::floor(n / 2);
  out.am = n * M_PI + std::atan2(even ? out.sn : -out.sn, even ? out.cn : -out.cn);
  out.Z = boost::math::jacobi_zeta(k, out.am, pol);
  out.E = out.Z + (E / K) * u;
  return out;
}

}  // namespace bench

// The exact data of a certificate: Eq. 5's problem with G and Omega(0) the intervals of decimals
// as written (MPFI's mpfi_set_str: "0.1" means one tenth, not its binary neighbour). A scene's
// exact problem is in scene/scene_exact_problem.hpp.
#pragma once

#include <eulervop/certify/interval.hpp>
#include <eulervop/model/euler_problem.hpp>

#include <mpfr.h>

#include <array>
#include <stdexcept>
#include <string>
#include <variant>

namespace eulervop {

// Eq. 5 (or Eq. 1) with a constant torque, in intervals.
using exact_problem = euler_problem<interval>;

namespace detail {
inline vec3<interval> decimals_of(const std::array<std::string, 3>& texts, mpfr_prec_t bits) {
  vec3<interval> v = {interval::zero(bits), interval::zero(bits), interval::zero(bits)};
  for (int i = 0; i < 3; ++i) set_decimal(v[i], texts[i]);
  return v;
}
}  // namespace detail

// The coefficients a as integers: each must be exactly -1, 0 or 1 (std::invalid_argument
// otherwise), as Eq. 5's (-1, 1, -1) are. The certificate's double-precision parts multiply by
// them and count no rounding for it (bounded_chebyshev.hpp).
inline std::array<int, 3> unit_coefficients(const exact_problem& p) {
  std::array<int, 3> out{};
  for (int i = 0; i < 3; ++i) {
    const interval& a = p.a[i];
    const bool point = mpfr_equal_p(&a.get()->left, &a.get()->right);
    const long value = mpfr_get_si(&a.get()->left, MPFR_RNDN);
    if (!point || !mpfr_integer_p(&a.get()->left) || value < -1 || value > 1)
      throw std::invalid_argument("certifier: the coefficients a of Euler's equations must be -1, 0 or 1");
    out[i] = static_cast<int>(value);
  }
  return out;
}

// Eq. 5 with G and Omega(0) the decimals `G`, `Omega0`, at `bits`.
inline exact_problem exact_problem_of(const std::array<std::string, 3>& G, const std::array<std::string, 3>& Omega0,
                                      mpfr_prec_t bits) {
  const interval_precision_scope scope(bits);
  exact_problem p;
  p.torque.G = detail::decimals_of(G, bits);
  p.Omega0 = detail::decimals_of(Omega0, bits);
  return p;
}

}  // namespace eulervop

// sin and cos of one double argument, inline: the circular part of the theta-function evaluation
// (jacobi_theta.hpp). libm's sincos is an out-of-line call whose latency sits on the critical
// path of every VOP right-hand side; this version keeps it in registers.
//
// Reduction by multiples of pi/2 (Cody-Waite): n = nearest(2x/pi), r = (x - n p1) - n p2 with
// pi/2 = p1 + p2 + O(2^-84), p1 of 27 bits so that n p1 and the subtraction are exact for
// |n| < 2^26; the error of r is below |n| 2^-83 + ulp(r)/2. Beyond |x| ~ 1e8 libm's exact
// reduction is used.
// Kernel: polynomials in z = r^2 interpolated at Chebyshev points (near-minimax; coefficients
// written and checked by tools/derive_theta_tables.py), evaluated by Estrin's scheme (shallow
// dependency chain). Accuracy: within 1 ulp (0.58 sin, 0.83 cos in the script's double
// evaluation; tests/test_elliptic.cpp checks sincos_double against MPFR).
#pragma once

#include "eulervop/core/double2.hpp"
#include "eulervop/special/detail/theta_tables.hpp"

#include <bit>
#include <cmath>
#include <cstdint>

namespace eulervop::detail {

// sin r and cos r for |r| <= pi/4 (1 + 5e-5).
[[gnu::always_inline]] inline void sincos_kernel(double r, double& s, double& c) {
  const double z = r * r, z2 = z * z, z4 = z2 * z2;
  // sin r = r + r z S(z), cos r = 1 + z C(z): S and C interpolate (sin(sqrt z)/sqrt z - 1)/z and
  // (cos(sqrt z) - 1)/z at Chebyshev points (theta_tables.hpp), side by side in one register.
  using d2 = double2;
  const auto k = [](int j) { return load2(sincos_table::S_C[j]); };
  const d2 k0 = k(0), k1 = k(1), k2 = k(2), k3 = k(3), k4 = k(4), k5 = k(5), k6 = k(6);
  const d2 SC = ((k0 + k1 * z) + z2 * (k2 + k3 * z)) + z4 * ((k4 + k5 * z) + z2 * k6);
  const d2 sc = d2{r, 1} + d2{r * z, z} * SC;
  s = sc[0];
  c = sc[1];
}

// sin x and cos x for any finite x.
[[gnu::always_inline]] inline void sincos_double(double x, double& s, double& c) {
  constexpr double two_over_pi = 0x1.45f306dc9c883p-1;
  constexpr double p1 = 0x1.921fb54p+0, p2 = 0x1.10b4611a62633p-30;  // pi/2 = p1 + p2 + O(2^-84)
  const double t = x * two_over_pi;
  if (!(std::fabs(t) < 0x1p26)) {
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  // Round to nearest by adding and subtracting 1.5 * 2^52 (exact for |t| < 2^51): two adds, no
  // round trip through an integer register on the path; the quadrant is in the low bits.
  constexpr double shifter = 0x1.8p52;
  const double shifted = t + shifter;
  const double nd = shifted - shifter;
  const auto n = std::bit_cast<std::uint64_t>(shifted);
  const double r = (x - nd * p1) - nd * p2;
  double rs, rc;
  sincos_kernel(r, rs, rc);
  // x = r + n pi/2: odd n swaps sin and cos; sin changes sign for n = 2, 3 and cos for n = 1, 2
  // (mod 4). Branch-free: the quadrant of successive calls is random, and a mispredicted switch
  // costs as much as the kernel.
  const bool odd = (n & 1) != 0;
  const double a = odd ? rc : rs, b = odd ? rs : rc;
  s = std::bit_cast<double>(std::bit_cast<std::uint64_t>(a) ^ ((n & 2) << 62));
  c = std::bit_cast<double>(std::bit_cast<std::uint64_t>(b) ^ (((n + 1) & 2) << 62));
}

}  // namespace eulervop::detail

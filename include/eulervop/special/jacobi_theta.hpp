// Jacobi elliptic functions in double from Jacobi's theta functions: the fast path of the VOP
// right-hand side (Eq. 16), where the modulus k = c1/c2 changes at every Runge-Kutta stage.
//
//   theta_modulus m(k);            // 0 <= k <= theta_modulus::max_k: the nome q and constants
//   jacobi_values<double> j;
//   theta_eval(u, m, j);           // sn, cn, dn, Z(u), E(u) (not am) in one pass
//   // or, with the constants in a local (what the VOP right-hand side does):
//   const theta_constants c = theta_constants_of(k, kc2);
//   theta_values_at_phase(v, c, j);   // at v = pi u / (2K): sn, cn, dn, Z
//
// Why: the AGM route (elliptic.hpp) pays a square root and a division per Landen level to build
// the modulus, then a Gauss step per level to evaluate: about 100 ns per right-hand side with a
// new k. Through the nome q = exp(-pi K'/K) every quantity is a short sum (q <= 0.23 for
// k <= 0.99, so q^(n^2) is below 1e-16 by n = 5); the modulus is two piecewise polynomials
// and a few products, and an evaluation one inline sincos, short polynomials and one division.
//
// Formulas (A&S = Abramowitz & Stegun 16.27, 16.36, 16.38, 17.3, 17.4; DLMF 20.2, 22.2):
//   q, pi/(2K)  piecewise polynomials in d = kc^2 (detail/theta_tables.hpp, written and checked
//            to within 1 ulp against mpmath by tools/derive_theta_tables.py); q = m g(d), m = k^2, so
//            that q ~ m/16 keeps its relative accuracy for small k.
//   thetas   at v = pi u / (2K) (DLMF 20.2.1-20.2.4), with the factor 2 q^(1/4) of theta1 and
//            theta2 divided out since it cancels in every ratio below:
//            th1(v)/(2 q^1/4) = sin v * sum_n (-1)^n q^(n(n+1)) (1 + 2 sum_{j<=n} cos 2jv)
//            th2(v)/(2 q^1/4) = cos v * sum_n (-1)^n q^(n(n+1)) (1 + 2 sum_{j<=n} (-1)^j cos 2jv)
//            th3(v) = 1 + 2 sum_j q^(j^2) cos 2jv,  th4(v) = 1 + 2 sum_j (-1)^j q^(j^2) cos 2jv
//            (sin((2n+1)v)/sin v and cos((2n+1)v)/cos v written as those sums so that sn and cn
//            keep their relative accuracy at their zeros), each a polynomial in x = cos 2v
//            (cos 2jv = T_j(x), sin 2jv = sin 2v U_{j-1}(x), Chebyshev polynomials) whose
//            coefficients depend on q only: prepared with the modulus, off the path from k to
//            the sincos.
//   K        pi/2 th3(0)^2                                                          (A&S 16.38.5)
//   sn, cn, dn   (th3(0)/th2(0)) th1(v)/th4(v), (th4(0)/th2(0)) th2(v)/th4(v),
//            (th4(0)/th3(0)) th3(v)/th4(v)                                       (A&S 16.36.3)
//   Z(u)     (pi/(2K)) th4'(v)/th4(v), th4'(v) = 4 sum_j (-1)^(j+1) j q^(j^2) sin 2jv (A&S 17.4.38)
//   E/K      kc^2 - Z'(K) = kc^2 + (pi/(2K))^2 8 sum j^2 q^(j^2) / th3(0)
//            (Z' = dn^2 - E/K and dn(K) = kc; at v = pi/2, th4 becomes th3: every term > 0)
//   E(u)     Z(u) + (E/K) u.
//
// Accuracy: tests/test_elliptic.cpp (ThetaDouble) checks it against Boost.Math in MPFR with the
// same points, measures and bounds as the AGM route: within 8 eps (sn, cn, dn, Z, E(u) at
// |u| <= K; dn relative times its condition number) and 8 eps forward-backward at any u; K, E,
// pi/(2K) within 4 ulp. Above max_k (the table's end) callers use elliptic_modulus.
#pragma once

#include "eulervop/special/detail/sincos_double.hpp"
#include "eulervop/core/double2.hpp"
#include "eulervop/special/detail/theta_tables.hpp"
#include "eulervop/special/elliptic.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace eulervop {

namespace detail {

// (g, pi/(2K)) at t for one interval of nome_table: c0 + t R(t), R by Estrin's scheme over
// c1..c13, both polynomials at once. A short dependency chain, and the dominant c0 meets a
// single rounding (the order tools/derive_theta_tables.py checks: within 1 ulp).
[[gnu::always_inline]] inline double2 nome_poly(const double (&c)[nome_table::coefficients][2], double t) {
  const double t2 = t * t, t4 = t2 * t2, t8 = t4 * t4;
  auto C = [&](int j) { return load2(c[j]); };
  const double2 lo = ((C(1) + C(2) * t) + t2 * (C(3) + C(4) * t)) + t4 * ((C(5) + C(6) * t) + t2 * (C(7) + C(8) * t));
  const double2 hi = ((C(9) + C(10) * t) + t2 * (C(11) + C(12) * t)) + t4 * C(13);
  return C(0) + t * (lo + t8 * hi);
}

}  // namespace detail

// The modulus-dependent constants of the theta route, by value: a caller that keeps them in a
// local (the VOP right-hand side) lets the compiler hold them in registers instead of storing and
// reloading them between the modulus and the evaluation.
struct theta_constants {
  double k = 0, kc2 = 1, q = 0, K = 0, rate = 1, e_over_k = 1;
  double sn_scale = 1, cn_scale = 1, dn_scale = 1;
  // Monomial coefficients (x^0, x^1, ...) of A, P and D (see theta_constants_of).
  std::array<double, 6> A{1, 0, 0, 0, 0, 0};
  std::array<double, 5> P{1, 0, 0, 0, 0}, D{0, 0, 0, 0, 0};
};

// Largest modulus served: at k = 0.99, q = 0.227 and the theta sums are complete to q^30 ~ 5e-20;
// the nome table ends at d = kc^2 = 2^-6 (k = 0.992).
inline constexpr double theta_max_k = 0.99;

namespace detail {
[[noreturn, gnu::noinline, gnu::cold]] inline void theta_out_of_range(double k) {
  throw std::domain_error("eulervop::theta_modulus: modulus k = " + to_text<double>(k) + " is outside [0, " +
                          to_text<double>(theta_max_k) + "]");
}
}  // namespace detail

// The constants for k in [0, theta_max_k], with kc^2 = 1 - k^2 supplied to full relative accuracy
// (the VOP right-hand side has it as (c2 - c1)(c2 + c1) / c2^2, off the path through k).
[[gnu::always_inline]] inline theta_constants theta_constants_of(double k, double kc2) {
  if (!(k >= 0 && k <= theta_max_k)) [[unlikely]]
    detail::theta_out_of_range(k);
  theta_constants m;
  m.k = k;
  m.kc2 = kc2;
  // q and pi/(2K) from the piecewise polynomials in d (theta_tables.hpp): the interval is the
  // binade of d and its top two mantissa bits; t = (d - centre) / halfwidth is exact.
  const auto bits = std::bit_cast<std::uint64_t>(kc2);
  int e = static_cast<int>((bits >> 52) & 0x7ff) - 1023;  // d in [2^e, 2^(e+1))
  int quarter = static_cast<int>((bits >> 50) & 3);
  if (e >= 0) {  // d = 1 (k = 0 or k^2 below half an ulp): the closed end of the last interval
    e = -1;
    quarter = 3;
  }
  const double scale = std::bit_cast<double>(static_cast<std::uint64_t>(1023 + 3 - e) << 52);  // 8 / 2^e
  const double t = kc2 * scale - (9 + 2 * quarter);
  const detail::double2 g_rate =
      detail::nome_poly(detail::nome_table::g_rate[(-e - 1) * detail::nome_table::per_binade + quarter], t);
  const double q = (k * k) * g_rate[0];
  m.rate = g_rate[1];
  const double q2 = q * q, q4 = q2 * q2, q6 = q4 * q2, q8 = q4 * q4, q9 = q8 * q;
  const double q12 = q6 * q6, q16 = q8 * q8, q20 = q16 * q4, q25 = q16 * q9;
  m.q = q;
  const double th3 = 1 + 2 * ((q + q4) + (q9 + q16 + q25));
  const double th4 = 1 - 2 * ((q - q4) + (q9 - q16 + q25));
  const double th2h = 1 + ((q2 + q6) + (q12 + q20));  // th2(0) / (2 q^1/4)
  const double inv_th3 = 1 / th3;
  const double inv_th2h = 1 / th2h;
  m.K = boost::math::constants::half_pi<double>() * (th3 * th3);
  m.sn_scale = th3 * inv_th2h;
  m.cn_scale = th4 * inv_th2h;
  m.dn_scale = th4 * inv_th3;
  // E/K = kc^2 - Z'(K) with Z'(K) = (pi/(2K))^2 th3''(0)/th3(0): all terms positive. (The
  // form at u = 0, 1 - (pi/(2K))^2 th4''(0)/th4(0), cancels as k -> 1: 4.7 ulp at k = 0.99.)
  const double th3pp = 8 * ((q + 4 * q4) + (9 * q9 + 16 * q16 + 25 * q25));  // -th3''(0)
  m.e_over_k = kc2 + m.rate * m.rate * th3pp * inv_th3;
  // The theta sums at v as polynomials in x = cos 2v (see the header note):
  //   th4(v)            = A(x) = 1 + 2 sum_j (-1)^j q^(j^2) T_j(x);   th3(v) = A(-x)
  //   th1/(2q^1/4 sin v) = P(x) = sum_n (-1)^n q^(n(n+1)) (1 + 2 sum_{j<=n} T_j(x));
  //   th2/(2q^1/4 cos v) = P(-x)
  //   th4'(v) / sin 2v  = D(x) = 4 sum_j (-1)^(j+1) j q^(j^2) U_{j-1}(x)
  m.A = {1 - 2 * q4 + 2 * q16, -2 * q + 6 * q9 - 10 * q25, 4 * q4 - 16 * q16, -8 * q9 + 40 * q25, 16 * q16,
         -32 * q25};
  m.P = {1 - q2 - q6 + q12 + q20, -2 * q2 + 2 * q6 + 4 * q12 - 4 * q20, 4 * q6 - 4 * q12 - 12 * q20,
         -8 * q12 + 8 * q20, 16 * q20};
  m.D = {4 * (q - 3 * q9 + 5 * q25), 64 * q16 - 16 * q4, 48 * q9 - 240 * q25, -128 * q16, 320 * q25};
  return m;
}

// sn, cn, dn and Z(u) at the phase v = pi u / (2K) (E(u) and am are left unset: E needs u).
[[gnu::always_inline]] inline void theta_values_at_phase(double v, const theta_constants& m, jacobi_values<double>& out) {
  // th4, th3, dn and Z have period pi in v, and every sum below is a function of x = cos 2v, so
  // only sin v and cos v are needed (reduced by pi/2 inside sincos_double).
  double s, c;
  detail::sincos_double(v, s, c);
  // x = cos 2v; A and P at +x and -x side by side in one register, th4 = A(x) first in the
  // shallowest order (it feeds the one division).
  const double x = (c - s) * (c + s), x2 = x * x;
  const detail::double2 X = {x, -x};
  const auto& A = m.A;
  const auto& P = m.P;
  const auto& D = m.D;
  const detail::double2 th43 = (A[0] + A[1] * X) + x2 * ((A[2] + A[3] * X) + x2 * (A[4] + A[5] * X));
  const detail::double2 P_pm = (P[0] + P[1] * X) + x2 * ((P[2] + P[3] * X) + x2 * P[4]);
  const double Dx = (D[0] + D[1] * x) + x2 * ((D[2] + D[3] * x) + x2 * D[4]);
  const double th4 = th43[0], th3 = th43[1];
  const double dth4 = 2 * s * c * Dx;
  const double inv = 1 / th4;
  const detail::double2 sn_cn = detail::double2{m.sn_scale * s, m.cn_scale * c} * P_pm * inv;
  out.sn = sn_cn[0];
  out.cn = sn_cn[1];
  out.dn = m.dn_scale * th3 * inv;
  out.Z = m.rate * dth4 * inv;
}

// sn, cn, dn, Z(u) and E(u) at u (am is left unset).
[[gnu::always_inline]] inline void theta_values_at_u(double u, const theta_constants& m, jacobi_values<double>& out) {
  theta_values_at_phase(u * m.rate, m, out);
  out.E = out.Z + m.e_over_k * u;
}

// The constants kept for repeated evaluations at one modulus.
class theta_modulus {
 public:
  static constexpr double max_k = theta_max_k;
  static bool covers(double k) { return k >= 0 && k <= max_k; }

  theta_modulus() { assign(0); }
  explicit theta_modulus(double k) { assign(k); }

  void assign(double k) { assign(k, (1 - k) * (1 + k)); }
  void assign(double k, double kc2) { c_ = theta_constants_of(k, kc2); }

  double k() const { return c_.k; }
  double kc2() const { return c_.kc2; }
  double q() const { return c_.q; }                     // the nome
  double K() const { return c_.K; }                     // complete integral of the first kind
  const double& pi_over_2K() const { return c_.rate; }  // pi / (2K) = 1 / th3(0)^2
  double e_over_k() const { return c_.e_over_k; }       // E(k) / K(k)
  double E() const { return c_.e_over_k * c_.K; }       // complete integral of the second kind
  const theta_constants& constants() const { return c_; }

 private:
  theta_constants c_;
};

// sn, cn, dn, Z(u) and E(u) at u (am is left unset).
inline void theta_eval(double u, const theta_modulus& m, jacobi_values<double>& out) {
  theta_values_at_u(u, m.constants(), out);
}

}  // namespace eulervop

// Jacobi elliptic functions, the complete integrals and the Jacobi zeta / epsilon functions,
// all from one arithmetic-geometric mean (descending Landen) sequence, templated on the scalar.
//
//   elliptic_modulus<T> m(k);        // the k-dependent part: AGM sequence, K(k), E(k), kc^2
//   jacobi_values<T> j = jacobi_eval(u, m);   // sn, cn, dn, am(u), Z(u), E(u) in one pass
//   T u = elliptic_f(j.am, m);       // F(phi|k), continuous in phi: the inverse of am
//
// The modulus is k (not the parameter m = k^2). 0 <= k < 1; anything else throws
// std::domain_error with the value.
//
// Formulas (A&S = Abramowitz & Stegun; DLMF = NIST Digital Library of Mathematical Functions):
//   AGM       a_0 = 1, b_0 = kc, c_0 = k;  a_n = (a_{n-1}+b_{n-1})/2,  b_n = sqrt(a_{n-1} b_{n-1}),
//             c_n = (a_{n-1}-b_{n-1})/2 computed without cancellation: as k_n a_n with
//             k_n = 1 - b_{n-1}/a_n while k_n > 1/2, then as c_{n-1}^2 / (4 a_n).
//             Stops on the relative test c_N <= eps a_N (A&S 16.4, 17.6).  An absolute test
//             would never stop for k -> 1 in wide types (docs/design.md section 2).
//   K         pi / (2 a_N)                                                        (A&S 17.6.3)
//   E/K       1 - sum_{n>=0} 2^{n-1} c_n^2                                        (A&S 17.6.4)
//             evaluated without its cancellation (it loses log2 K bits as k -> 1):
//             kc >= 1/16: E/K = a_N^2 + sum_{n>=2} c_n (a_{n-1} + a_n - 2^{n-1} c_n), the same
//                         sum telescoped with c_n^2 = (a_{n-1}-a_n)... (derivation below);
//             kc <  1/16: Legendre's relation E K' + E' K - K K' = pi/2 (A&S 17.3.13) with
//                         K' = pi/(2 a'_N) from the complementary AGM (a'_0 = 1, b'_0 = k):
//                         E/K = 2 a_N a'_N / pi + sum_{n>=0} 2^{n-1} c'_n^2  (all terms > 0).
//   sn,cn,dn  descending Gauss transformation, level n has modulus k_n = c_n/a_n and argument
//             a_n u (DLMF 22.7.1-22.7.3): with s,c,d at level n and D = 1 + k_n s^2,
//               sn = (1+k_n) s / D,  cn = c d / D,
//               dn = (1 - k_n s^2) / D        where k_n s^2 <= 1/2,
//               dn = ((1-k_n) + k_n c^2) / D  elsewhere,
//             with 1 - k_n = b_{n-1}/a_n.  The dn forms are DLMF 22.7.3 rewritten without the
//             0/0 of a ratio at odd multiples of K (docs/design.md section 2) and without the
//             cancellation of 1 - k_n s^2 near s = 1.  Bottom level: sin, cos, 1 of a_N u
//             (error O(k_N^2) <= eps^2), or equivalently level N-1 to first order in
//             k_{N-1}^2 (A&S 16.13), which is what the code does.
//   am        n pi + atan2(sn(r), cn(r)) with r = u - 2nK, n = nearest(u/2K); continuous in u.
//   Z(u)      sum_{n=1}^N 2^n c_n sn_n cn_n dn_n / (1 + k_n sn_n^2), the level-n values from
//             the same upward pass. This is the Gauss transformation of Z,
//               Z(u|k) = (1+kc) Z(v|k_1) + (1-kc) sn cn dn(v|k_1) / (1 + k_1 sn^2(v|k_1)),
//             v = u/(1+k_1), unrolled (derived from the Fourier series of Z; checked against
//             mpmath to 1e-40 and against Boost.Math jacobi_zeta in the tests). It replaces the
//             A&S 17.6 sum c_n sin(phi_n) over the Landen angles, which needs a second pass.
//   E(u)      Jacobi's epsilon function = E(am u | k) = Z(u) + (E/K) u.
//   F(phi)    A&S 17.6.8-17.6.9: phi_n = phi_{n-1} + atan((b_{n-1}/a_{n-1}) tan phi_{n-1}) on the
//             branch that keeps phi_n - phi_{n-1} within pi/2 of phi_{n-1}; F = phi_N / (2^N a_N).
//             Continuous: F(phi + j pi) = F(phi) + 2 j K.
//
// Derivation of the telescoped E/K (checked numerically to 1e-50 with mpmath): let
// T_n = 1 - sum_{j<=n} 2^{j-1} c_j^2 and D_n = T_n - a_n^2.  D_0 = -k^2/2, and
// a_{n-1}^2 - a_n^2 = c_n (a_{n-1} + a_n), so D_n = D_{n-1} + c_n (a_{n-1} + a_n - 2^{n-1} c_n),
// with D_1 = 0 exactly.  The terms are positive unless a_{n-1} > 5 b_{n-1}-ish, which only happens
// for small kc, hence the Legendre branch there.
//
// Accuracy (measured in tests/test_elliptic.cpp against Boost.Math in MPFR at 2 bits(T) + 256;
// the same multiples of eps for double, quad and MPFR):
//   |u| <= K: sn, cn (absolute), am, Z, E(u) within ~6 ulp; dn relative within ~5 ulp times
//     max(1, |u dn'/dn|) (the ~1 ulp rounding of the argument a_n u, amplified by the condition
//     number of dn, which reaches ~|u| for k -> 1 where dn ~ kc: up to ~22 ulp relative in double
//     at k = 1 - 1e-12, |u| ~ 5..15; the absolute error there is tiny).
//   any u: |error| <= ~6 eps (|f| + |u f'(u)|) (forward-backward stable). For large |u| the
//     reduction u - 2nK carries the rounding of K (n ulp(K) ~ eps |u|): log2(|u|/K) bits of the
//     input are lost, the same as the sensitivity to the last bit of u itself.
//   K, E(k): within 1.5 ulp.  F(phi): within ~1.5 eps (|F| + |phi| dF/dphi).
//
// Cost (double, AMD EPYC 2.1 GHz, benchmarks/bench_elliptic.cpp): jacobi_eval ~50 ns with the
// modulus cached, elliptic_modulus construction ~50 ns. No heap allocation for double and quad
// (fixed arrays of max_levels); for MPFR each temporary allocates (use the in-place overloads and
// assign(), and keep the objects alive in hot loops).
#pragma once

#include <eulervop/core/scalar_traits.hpp>

#include <boost/math/constants/constants.hpp>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace eulervop {

namespace detail {

// Nearest integer (ties either way; for double, off by one when x + 1/2 rounds up), as a T.
template <scalar T>
inline T elliptic_nearest(const T& x) {
  if constexpr (std::is_same_v<T, double>) {
    // Truncation of x +- 1/2 is one inline instruction; std::nearbyint and std::round are libm
    // calls unless SSE4.1 is enabled (GCC even turns the (x + 1.5*2^52) - 1.5*2^52 trick into
    // one). Ties and the rounding of x + 1/2 may go either way: callers only need a nearby integer.
    if (std::fabs(x) < 0x1p52) return static_cast<double>(static_cast<long long>(x + (x < 0 ? -0.5 : 0.5)));
    return x;  // already an integer
  } else {
    using std::round;
    return round(x);
  }
}

// True when the integer-valued x is odd.
template <scalar T>
inline bool elliptic_is_odd(const T& x) {
  if constexpr (std::is_same_v<T, double>) {
    if (std::fabs(x) < 0x1p62) return (static_cast<long long>(x) & 1) != 0;
  }
  using std::floor;
  T half = x / 2;
  return half != floor(half);
}

}  // namespace detail

// The modulus-dependent part: everything that depends on k only. Build it once per k and reuse
// it while k is unchanged.
template <scalar T>
class elliptic_modulus {
 public:
  // Levels of the AGM that fit. The AGM converges quadratically once a_n/b_n is near 1; before
  // that, a_n/b_n falls like its square root, which takes log2(log2(1/kc)) levels.  With
  // kc >= sqrt(eps) (k < 1 in T) and eps >= 2^-16384 this is at most about 2 * 14 = 28 levels.
  static constexpr int max_levels = 40;

  explicit elliptic_modulus(const T& k) { assign(k); }

  // Recomputes for a new modulus, reusing this object's storage (useful for MPFR).
  void assign(const T& k) {
    using std::sqrt;
    if (!(k >= 0 && k < 1))
      throw std::domain_error("eulervop::elliptic_modulus: modulus k = " + to_text<T>(k) +
                              " is outside [0, 1)");
    k_ = k;
    kc2_ = (1 - k) * (1 + k);  // 1 - k is exact for k >= 1/2 (Sterbenz), so kc^2 keeps its bits
    kc_ = sqrt(kc2_);
    pi_ = boost::math::constants::pi<T>();
    levels_ = descend(k);
    const int n = levels_;
    zw_[0] = 0;
    {
      T p = 1;
      for (int j = 1; j <= n; ++j) {
        p *= 2;
        zw_[j] = c_[j] * p;
      }
    }
    const T& aN = a_[n];
    K_ = pi_ / (2 * aN);
    two_K_ = 2 * K_;  // exact
    inv_two_K_ = aN * boost::math::constants::one_div_pi<T>();
    if (kc_ * 16 >= 1)
      e_over_k_ = e_over_k_from_descent();
    else
      e_over_k_ = e_over_k_complementary(k);
    E_ = e_over_k_ * K_;
  }

  const T& k() const { return k_; }
  const T& kc() const { return kc_; }          // sqrt(1 - k^2)
  const T& kc2() const { return kc2_; }        // 1 - k^2, computed as (1-k)(1+k)
  const T& K() const { return K_; }            // complete integral of the first kind K(k)
  const T& E() const { return E_; }            // complete integral of the second kind E(k)
  const T& e_over_k() const { return e_over_k_; }  // E(k)/K(k)
  const T& two_K() const { return two_K_; }    // 2K, the period of dn and Z
  const T& pi() const { return pi_; }
  int levels() const { return levels_; }       // N: the AGM index at which c_N <= eps a_N
  // The AGM sequence (A&S 17.6.1), n = 0..levels().
  const T& a(int n) const { return a_[n]; }
  const T& b(int n) const { return b_[n]; }
  const T& c(int n) const { return c_[n]; }
  const T& k_level(int n) const { return kn_[n]; }              // k_n = c_n / a_n, n >= 1
  const T& one_minus_k_level(int n) const { return omkn_[n]; }  // 1 - k_n = b_{n-1} / a_n
  const T& inv_two_K() const { return inv_two_K_; }              // 1 / (2K) = a_N / pi
  const T& z_weight(int n) const { return zw_[n]; }              // 2^n c_n, weights of Z

 private:
  // The AGM descent from (a_0, b_0, c_0) = (1, kc, k): a_n, b_n, c_n, k_n and 1 - k_n until the
  // stopping test. Returns the last level N.
  int descend(const T& k) {
    using std::sqrt;
    a_[0] = 1;
    b_[0] = kc_;
    c_[0] = k;
    kn_[0] = k;
    omkn_[0] = 1 - k;
    int n = 0;
    // Relative stopping test. At least one level when k > 0, so that Z (whose first term is
    // c_1 ~ k^2/4) keeps its relative accuracy for tiny k.
    // The descent may stop once c_N <= sqrt(eps)/64 a_N rather than eps a_N: the bottom level
    // L = N-1 is evaluated to first order in k_L^2 ~ 4 c_N / a_N (error O(k_L^4) <= eps/256),
    // and a_N differs from the AGM limit by ~c_N^2 / (4 a_N) <= eps a_N / 16384. For most k
    // this saves one level of the descent (measured against the eps test: within 8 ulp still).
    const T stop = sqrt(epsilon<T>()) / 64;
    while (n == 0 ? c_[0] > 0 : c_[n] > stop * a_[n]) {
      if (n + 1 >= max_levels)
        throw std::runtime_error("eulervop::elliptic_modulus: AGM did not converge in " +
                                 std::to_string(max_levels) + " levels for k = " + to_text<T>(k));
      a_[n + 1] = (a_[n] + b_[n]) / 2;
      ++n;
      const T inv_a = 1 / a_[n];
      omkn_[n] = b_[n - 1] * inv_a;  // 1 - k_n, relative error ~eps at every level
      if (omkn_[n] * 2 < 1) {
        // Slow phase (k -> 1): k_n > 1/2, so 1 - (1 - k_n) has no cancellation and keeps
        // k_n + (1 - k_n) = 1 to an ulp. The squaring c_{n-1}^2/(4 a_n) would double the
        // relative error of c_n at every level, and this phase can last log2(log2(1/kc)) levels.
        kn_[n] = 1 - omkn_[n];
        c_[n] = kn_[n] * a_[n];
      } else {
        // Fast phase: c_n = (a_{n-1} - b_{n-1})/2 would cancel; square instead (its relative
        // error doubles per level, but c_n falls doubly exponentially, so its absolute error
        // stays far below eps a_n).
        c_[n] = c_[n - 1] * c_[n - 1] * inv_a / 4;
        kn_[n] = c_[n] * inv_a;
      }
      // b_n = sqrt(a_{n-1} b_{n-1}), except at the last level: there a_n - b_n = 2 c_{n+1}
      // ~ c_n^2 / (2 a_n) <= eps^2 a_n, so b_n = a_n to rounding and the square root is saved.
      b_[n] = c_[n] > stop * a_[n] ? T(sqrt(a_[n - 1] * b_[n - 1])) : a_[n];
    }
    return n;
  }

  // E/K for kc >= 1/16: the telescoped A&S 17.6.4 of the header note,
  // a_N^2 + sum_{j>=2} c_j (a_{j-1} + a_j - 2^{j-1} c_j).
  T e_over_k_from_descent() const {
    const int n = levels_;
    const T& aN = a_[n];
    T d = aN * aN;
    T p = 1;  // 2^{j-1}
    for (int j = 2; j <= n; ++j) {
      p *= 2;
      d += c_[j] * (a_[j - 1] + a_[j] - p * c_[j]);
    }
    return d;
  }

  // E/K for kc < 1/16: Legendre's relation (A&S 17.3.13) with the complementary AGM of the
  // header note, streamed (only a'_N and the sum are needed).
  T e_over_k_complementary(const T& k) const {
    using std::sqrt;
    const T eps = epsilon<T>();
    T a = 1, b = k, c = kc_;
    T s = c * c / 2;  // 2^{-1} c'_0^2
    T p = T(1) / 2;
    for (int j = 0; c > eps * a; ++j) {
      if (j + 1 >= max_levels)
        throw std::runtime_error("eulervop::elliptic_modulus: complementary AGM did not converge");
      T an = (a + b) / 2;
      b = sqrt(a * b);
      c = c * c / (4 * an);
      a = an;
      p *= 2;
      s += p * c * c;
    }
    return 2 * a_[levels_] * a / pi_ + s;
  }

  T k_, kc_, kc2_, pi_, K_, E_, e_over_k_, two_K_, inv_two_K_;
  int levels_ = 0;
  std::array<T, max_levels> a_, b_, c_;
  std::array<T, max_levels> kn_;    // k_n = c_n / a_n (n >= 1), the modulus of level n
  std::array<T, max_levels> omkn_;  // 1 - k_n = b_{n-1} / a_n (n >= 1), without cancellation
  std::array<T, max_levels> zw_;    // 2^n c_n
};

namespace detail {

// sn, cn, dn of one level of the Gauss transformation in homogeneous coordinates,
// (s, c, d) = (S, C, D) / W, and the partial sum z of Z(r) over the levels below.
template <scalar T>
struct gauss_level {
  T S, C, D, W, z;
};

// The bottom of jacobi_eval at the reduced argument r (N = m.levels() >= 1): level L = N-1,
// whose modulus k_L ~ 2 sqrt(k_N) <= 2 sqrt(eps) (the AGM stopped at k_N <= eps), argument
// a_L r, first order in m = k_L^2 (A&S 16.13.1-16.13.3); the remainder is O(m^2) <= 16 eps^2.
// This saves the last Gauss step.
template <scalar T>
[[gnu::always_inline]] inline gauss_level<T> jacobi_bottom(const T& r, const elliptic_modulus<T>& m) {
  using std::cos;
  using std::sin;
  const int N = m.levels();
  const int L = N - 1;
  const T v = m.a(L) * r;
  const T sv = sin(v), cv = cos(v);
  const T mL = m.k_level(L) * m.k_level(L);
  const T w = mL / 4 * (v - sv * cv);
  T s = sv - w * cv, c = cv + w * sv, d = 1 - mL / 2 * (sv * sv);
  // Z(r) = sum_{n=1}^N 2^n c_n sn_n cn_n dn_n / (1 + k_n sn_n^2), with sn_n, cn_n, dn_n the
  // level-n values; all terms have the sign of r (no cancellation). It is the Gauss
  // transformation Z(u|k) = (1+kc) Z(v|k_1) + (1-kc) sn cn dn(v|k_1) / (1 + k_1 sn^2(v|k_1)),
  // v = u/(1+k_1) (derived from the Fourier series of Z, checked to 1e-40 with mpmath), unrolled.
  // Level N: its term 2^N c_N sn_N cn_N dn_N / (1 + k_N sn_N^2) plus the remainder of the
  // unrolled sum, 2^N a_N Z(a_N r | k_N) = 2^N a_N (k_N^2/4) sin(2 a_N r) + O(k_N^4) (A&S 17.4
  // Maclaurin series: Z(u|m) = (m/4) sin 2u + O(m^2)), together to first order in k_N:
  //   2^N c_N s c (1 + k_N (c^2 - s^2) / 2),   (s, c) = (sin, cos)(a_N r).
  // With the descent stopped at k_N <= sqrt(eps)/64 the first-order terms matter: for small k
  // this is nearly all of Z (N = 1, Z ~ c_1), and dropping them costs a relative error ~ k_N/4
  // (checked against mpmath: 1e-10 before, 1e-19 after, at k = 3e-5). The level-N argument is
  // v + delta, delta = (a_N - a_L) r = -c_N r (a_L - a_N = c_N), to first order:
  // (s, c) = (sv + delta cv, cv - delta sv).
  const T delta = -m.c(N) * r;
  const T sN = sv + delta * cv, cN = cv - delta * sv;
  T z = m.z_weight(N) * sN * cN * (1 + m.k_level(N) * ((cN - sN) * (cN + sN)) / 2);
  return {s, c, d, T(1), z};
}

// Up the Gauss transformation (DLMF 22.7.1-22.7.3), level L -> 0, in homogeneous coordinates
// (s, c, d) = (S, C, D)/W so that no division sits on the dependency chain: with
// W' = W^2 + k_n S^2 (that is, D = 1 + k_n s^2 times W^2),
//   S' = (1 + k_n) S W,   C' = C D,   D' = W^2 - k_n S^2  or  (1 - k_n) W^2 + k_n C^2.
// All four are homogeneous of degree 2, so a power-of-two rescaling is exact and harmless.
// dn: the first form, (1 - k_n s^2)/D, depends on s alone and is used while it has no
// cancellation. Computing d from c everywhere feeds the error of c back into d, so that
// (s, c, d) drift off sn^2 + cn^2 = 1 and the error doubles at every level with k_n ~ 1
// (k -> 1). Where k_n s^2 > 1/2, c^2 < 1/2 and that feedback gain stays below ~1.
template <scalar T>
[[gnu::always_inline]] inline void jacobi_ascend(gauss_level<T>& g, const elliptic_modulus<T>& m) {
  T& S = g.S;
  T& C = g.C;
  T& D = g.D;
  T& W = g.W;
  for (int n = m.levels() - 1; n >= 1; --n) {
    const T& kn = m.k_level(n);
    const T kS2 = kn * (S * S);
    const T W2 = W * W;
    const T Wn = W2 + kS2;
    const T Sn = (1 + kn) * S * W;
    const T Cn = C * D;
    if (2 * kS2 <= W2)
      D = W2 - kS2;
    else
      D = m.one_minus_k_level(n) * W2 + kn * (C * C);
    // Z term 2^n c_n sn_n cn_n dn_n / (1 + k_n sn_n^2) = 2^n c_n s_n c_{n-1}: off the chain.
    g.z += m.z_weight(n) * S * Cn / (W * Wn);
    S = Sn;
    C = Cn;
    W = Wn;
    if (W > T(0x1p64)) {  // W >= 1 grows like 2^(2^levels); keep it far from overflow
      const T scale = T(0x1p-64);
      S *= scale;
      C *= scale;
      D *= scale;
      W *= scale;
    }
  }
}

}  // namespace detail

// Everything one evaluation at u returns.
template <scalar T>
struct jacobi_values {
  T sn, cn, dn;
  T am;  // amplitude, continuous in u: am(u + 2K) = am(u) + pi
  T Z;   // Jacobi zeta function Z(u), period 2K
  T E;   // Jacobi's epsilon function E(u) = integral_0^u dn^2 = E(am u | k) = Z(u) + (E/K) u
};

// Evaluates sn, cn, dn, am, Z and E(u) at u for the cached modulus m, in place.
// Which outputs a caller needs: the amplitude costs an atan2 (about a fifth of an evaluation in
// double) that right-hand sides such as Eq. 16 never use.
enum class jacobi_outputs { all, without_amplitude };

template <scalar T, jacobi_outputs Outputs = jacobi_outputs::all>
void jacobi_eval(const T& u, const elliptic_modulus<T>& m, jacobi_values<T>& out) {
  using std::atan2;
  using std::cos;
  using std::sin;
  const int N = m.levels();
  if (N == 0) {  // k == 0 exactly: circular functions, no reduction needed
    out.sn = sin(u);
    out.cn = cos(u);
    out.dn = 1;
    out.am = u;
    out.Z = 0;
    out.E = u;
    return;
  }
  // Reduce u modulo 2K first, in T: r in about [-K, K], where cn(r) >= 0.
  const T q = detail::elliptic_nearest<T>(u * m.inv_two_K());
  const T r = u - q * m.two_K();
  detail::gauss_level<T> g = detail::jacobi_bottom(r, m);
  detail::jacobi_ascend(g, m);
  const T inv_w = 1 / g.W;
  const bool odd = detail::elliptic_is_odd(q);
  if constexpr (Outputs == jacobi_outputs::all) out.am = q * m.pi() + atan2(g.S, g.C);
  const T s = g.S * inv_w;
  const T c = g.C * inv_w;
  out.sn = odd ? T(-s) : s;
  out.cn = odd ? T(-c) : c;
  out.dn = g.D * inv_w;
  out.E = g.z + m.e_over_k() * u;
  out.Z = g.z;
}

template <scalar T>
jacobi_values<T> jacobi_eval(const T& u, const elliptic_modulus<T>& m) {
  jacobi_values<T> out;
  jacobi_eval(u, m, out);
  return out;
}

template <scalar T>
jacobi_values<T> jacobi_eval(const T& u, const T& k) {
  return jacobi_eval(u, elliptic_modulus<T>(k));
}

// Incomplete elliptic integral of the first kind F(phi | k) = integral_0^phi dt/sqrt(1-k^2 sin^2 t),
// for any real phi (continuous: F(phi + j pi) = F(phi) + 2 j K). Inverse of am: F(am(u)) = u.
template <scalar T>
T elliptic_f(const T& phi, const elliptic_modulus<T>& m) {
  using std::atan2;
  using std::cos;
  using std::fabs;
  using std::sin;
  using std::sqrt;
  const int N = m.levels();
  if (N == 0) return phi;
  // phi = j pi + x, |x| <= pi/2 (about): F = 2 j K + sign(x) F(|x|).
  const T j = detail::elliptic_nearest<T>(phi / m.pi());
  const T xr = phi - j * m.pi();
  const bool negative = xr < 0;
  T x = fabs(xr);
  T S = sin(x), C = cos(x);
  const T two_pi = 2 * m.pi();
  T scale = 1;  // 2^-n
  for (int n = 1; n <= N; ++n) {
    const T& a = m.a(n - 1);
    const T& b = m.b(n - 1);
    const T aC = a * C, bS = b * S;
    // phi_n - phi_{n-1} = atan((b/a) tan phi_{n-1}) on the branch within pi/2 of phi_{n-1}.
    T delta = atan2(bS, aC);
    const T turns = detail::elliptic_nearest<T>((x - delta) / two_pi);
    if (turns != 0) delta += turns * two_pi;
    x += delta;  // all terms >= 0: no cancellation
    const T inv_h = 1 / sqrt(aC * aC + bS * bS);
    const T S_new = 2 * m.a(n) * S * C * inv_h;
    C = (aC * C - bS * S) * inv_h;
    S = S_new;
    scale /= 2;
  }
  T f = x * scale / m.a(N);
  if (negative) f = -f;
  return j * m.two_K() + f;
}

template <scalar T>
T elliptic_f(const T& phi, const T& k) {
  return elliptic_f(phi, elliptic_modulus<T>(k));
}

}  // namespace eulervop

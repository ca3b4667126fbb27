// Sines and cosines of an argument affine in the node coordinate, alpha + beta s_j, at the
// Chebyshev-Lobatto nodes s_j = -cos(j pi / N) of a segment: a torque of time such as
// sin(omega t + phi) sees exactly such arguments at the nodes, t_j = (tau + hl) + hl s_j.
//
// The Jacobi-Anger expansions (DLMF 10.12.2 and 10.12.3, with z = beta, theta = arccos s)
//   cos(beta s) = J_0(beta) + 2 sum_{k>=1} (-1)^k J_{2k}(beta) T_{2k}(s),
//   sin(beta s) = 2 sum_{k>=0} (-1)^k J_{2k+1}(beta) T_{2k+1}(s)
// make sin(alpha + beta s) = sin(alpha) cos(beta s) + cos(alpha) sin(beta s) one Chebyshev series
// in s whose coefficients take sin(alpha), cos(alpha) and the Bessel functions J_n(beta). So a
// segment costs one sine and one cosine, the Bessel functions by Miller's backward recurrence
// (DLMF 3.6(vi)), normalized by 1 = J_0 + 2 sum_{k>=1} J_{2k} (DLMF 10.12.4), and one exact
// fixed-point product (fixed_point_matvec.hpp) with the matrix T_n(s_j) for the values at every
// node: no soft-float operation per node, where a sine per node cost about a microsecond in quad.
//
// Accuracy: the series stops where the bound |J_n(beta)| <= (|beta|/2)^n / n! (DLMF 10.14.4)
// leaves a tail below 2^-118; the recurrence starts 16 orders beyond, where its start value's
// error has decayed by far more than 2^-113 (its ratios are about 2n / beta). The product adds at
// most 2^-116 n max|x| + 2 ulp (its header). Measured against 300-bit MPFR on 2000 random
// arguments (tests/test_node_sines.cpp): within 2.7 units of 2^-113 for |beta| <= 1, against
// about one for a correctly rounded sine at each node; the roundings of the recurrence grow with
// beta (25 units at |beta| = 1..10), so larger beta are declined.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/detail/fixed_point_matvec.hpp>

#include <cmath>
#include <cstddef>
#include <map>
#include <vector>

namespace eulervop::detail {

class node_sines {
 public:
  // evaluate() declines |beta| above this.
  static constexpr double max_beta = 1;
  static constexpr std::size_t max_terms = 40;  // enough for |beta| <= 1

  explicit node_sines(std::size_t degree) : N_(degree), n1_(degree + 1), cosines_(2 * degree) {
    using std::cos;
    const quad pi = pi_in<quad>();
    for (std::size_t m = 0; m < 2 * N_; ++m) cosines_[m] = cos(pi * quad(static_cast<int>(m)) / quad(static_cast<int>(N_)));
  }

  std::size_t degree() const { return N_; }

  // out[j] = sin(alpha + alpha_lo + beta s_j), or its cosine, for j = 0..N (alpha_lo: far below
  // an ulp of alpha, taken to first order). False (out untouched) where beta is zero, above
  // max_beta or not finite, or alpha not finite: the caller evaluates per node there.
  bool evaluate(const quad& alpha, const quad& alpha_lo, const quad& beta, bool cosine, std::vector<quad>& out) {
    using std::isfinite;
    const double b = std::abs(static_cast<double>(beta));
    if (!(b > 0) || !(b <= max_beta) || !isfinite(alpha)) return false;
    const std::size_t terms = terms_for(b);
    if (terms == 0) return false;
    // Miller: j_{n-1} = (2n / beta) j_n - j_{n+1} from j_{M+1} = 0, j_M = 1, then normalized. In
    // double down to the order `quad_from`, below which |J_n| may exceed 2^-60 of the largest
    // (the bound above), and in quad from there: the orders above it enter the result only
    // 2^-60 below it, where double's 2^-53 suffices, and the backward recurrence damps the
    // seeds' own rounding (Gautschi 1967, section 3: the minimal solution dominates backwards).
    const std::size_t M = terms + 16;
    std::size_t quad_from = 1;
    for (double b_n = 1; quad_from < terms; ++quad_from) {
      b_n *= b / 2 / static_cast<double>(quad_from);
      if (b_n < 0x1p-62 && static_cast<double>(quad_from) > b) break;
    }
    Jd_.assign(M + 2, 0.0);
    Jd_[M] = 1;
    const double two_over_beta_d = 2 / static_cast<double>(beta);
    for (std::size_t n = M; n > quad_from; --n)
      Jd_[n - 1] = static_cast<double>(n) * two_over_beta_d * Jd_[n] - Jd_[n + 1];
    J_.assign(M + 2, quad(0));
    for (std::size_t n = quad_from; n <= M; ++n) J_[n] = Jd_[n];
    const quad two_over_beta = 2 / beta;
    for (std::size_t n = quad_from; n >= 1; --n) J_[n - 1] = quad(static_cast<int>(n)) * two_over_beta * J_[n] - J_[n + 1];
    quad half_rest = 0;  // sum over even n >= 2 of j_n, the small ones summed in double
    double small = 0;
    for (std::size_t n = 2; n <= M; n += 2) {
      if (n <= quad_from) half_rest += J_[n];
      else small += Jd_[n];
    }
    half_rest += small;
    const quad norm = J_[0] + (half_rest + half_rest);
    // x_n: the Chebyshev coefficients of the result, the normalization folded into the factors.
    // sin and cos of alpha + alpha_lo: alpha_lo's term to first order (its square lies 2^-226 down).
    // Both from one sincosq: one argument reduction instead of two (0.6 us of 1.7 per segment),
    // and the same bits as sinq and cosq (libquadmath's sincos kernel evaluates the same
    // polynomials; tests/test_node_sines.cpp compares them on random arguments).
    __float128 sa_value, ca_value;
    sincosq(alpha.backend().value(), &sa_value, &ca_value);
    const quad sa(sa_value), ca(ca_value);
    const quad s = (sa + alpha_lo * ca) / norm, c = (ca - alpha_lo * sa) / norm;
    const quad even = cosine ? c : s, odd = cosine ? -s : c;
    const quad even2 = even + even, odd2 = odd + odd;  // the series' factor 2, exact
    x_.resize(terms);
    x_[0] = even * J_[0];
    for (std::size_t n = 1; n < terms; ++n) {
      const bool negative = (n % 2 ? (n - 1) / 2 : n / 2) % 2 == 1;
      x_[n] = (n % 2 ? odd2 : even2) * J_[n];
      if (negative) x_[n] = -x_[n];
    }
    out.resize(n1_);
    matrix(terms).multiply(x_.data(), out.data());
    return true;
  }

 private:
  // Terms: the first n with n > |beta| and (|beta|/2)^n / n! below 2^-118 (with room for the
  // tail's geometric sum, whose ratio is then below 1/2); 0 where max_terms do not reach it.
  static std::size_t terms_for(double b) {
    double bound = 1;
    for (std::size_t n = 1; n <= max_terms; ++n) {
      bound *= b / 2 / static_cast<double>(n);
      if (static_cast<double>(n) > b && bound < 0x1p-119) return n;
    }
    return 0;
  }

  // T_n(s_j) = (-1)^n cos(n j pi / N) for n < terms, rows j = 0..N.
  fixed_point_matrix<quad>& matrix(std::size_t terms) {
    auto it = matrices_.find(terms);
    if (it != matrices_.end()) return it->second;
    std::vector<quad> a(n1_ * terms);
    for (std::size_t j = 0; j < n1_; ++j)
      for (std::size_t n = 0; n < terms; ++n) {
        const quad& c = cosines_[(n * j) % (2 * N_)];
        a[j * terms + n] = n % 2 ? quad(-c) : c;
      }
    return matrices_.emplace(terms, fixed_point_matrix<quad>(a, n1_, terms)).first->second;
  }

  std::size_t N_, n1_;
  std::vector<quad> cosines_;  // cos(m pi / N), m = 0 .. 2N - 1
  std::map<std::size_t, fixed_point_matrix<quad>> matrices_;
  std::vector<quad> J_, x_;
  std::vector<double> Jd_;
};

}  // namespace eulervop::detail

// Chebyshev series in double with a bound of every rounding, for the parts of the certificate
// (certify/certifier.hpp) whose accuracy only needs to be modest: the variational matrix and the
// signed integral term. A polynomial is its double coefficients (exact by definition) or, where
// it stands for an exactly known one, those coefficients plus `radius` >= sum |exact_k - c_k|.
//
// The bounds use gamma_n = n u / (1 - n u): a computed sum of n products differs from the exact
// one by at most gamma_n times the sum of the products' magnitudes (Higham, "Accuracy and
// Stability of Numerical Algorithms", 2002, section 3.1). On [-1, 1], |T_k| <= 1, so a sum of
// coefficient errors bounds the error of the function.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace eulervop::detail {

inline double gamma_of(std::size_t n) {
  const double nu = static_cast<double>(n) * std::numeric_limits<double>::epsilon() / 2;
  return nu / (1 - nu);
}

// Beyond gamma_n, an operation whose result is subnormal or zero may err by denorm_min in
// absolute terms: this allows for `operations` of them.
inline double underflow_allowance(std::size_t operations) {
  return 2 * static_cast<double>(operations) * std::numeric_limits<double>::denorm_min();
}

inline double abs_sum(const double* c, std::size_t n) {
  double s = 0;
  for (std::size_t k = 0; k < n; ++k) s += std::abs(c[k]);
  return s;
}

// A Chebyshev series c[0..n) with a bound of its distance to the polynomial it stands for.
struct series_view {
  const double* c = nullptr;
  std::size_t n = 0;
  double radius = 0;
};

// One term sign * a * b of a sum of products; sign is -1, 0 or 1, so that a product by it is
// exact (the certificate's coefficients a_i, exact_problem.hpp: unit_coefficients).
struct product_term {
  double sign = 1;
  series_view a, b;
};

// H(s) = hl int_{-1}^s sum_t sign_t a_t(x) b_t(x) dx in Chebyshev form (coefficients `out`, of
// length max(na + nb) + 1), with `error` bounding sup |exact H - computed H| on [-1, 1], where
// "exact" uses the exact polynomials the views stand for and the exact hl, of which `hl` is the
// nearest double and hl_error bounds the distance (the exact integral, over a length of at most
// 2, is at most the products' magnitudes, with the views' radii, times 2: hl_error times that).
struct integrated_products {
  std::vector<double> coeffs;
  double error = 0;
  double hl_error = 0;

  void compute(double hl, std::span<const product_term> terms) {
    std::size_t ng = 0, count = 0;
    for (const product_term& t : terms) {
      ng = std::max(ng, t.a.n + t.b.n - 1);
      count += 2 * (t.a.n + t.b.n);
    }
    g_.assign(ng, 0.0);
    double magnitude = 0, from_radii = 0;
    for (const product_term& t : terms) {
      // T_m T_n = (T_{m+n} + T_{|m-n|}) / 2, in three runs of contiguous indices (n >= 0 to
      // g_{m+n}, n <= m to g_{m-n}, n > m to g_{n-m}) that the compiler vectorizes.
      double* __restrict g = g_.data();
      const double* __restrict b = t.b.c;
      for (std::size_t m = 0; m < t.a.n; ++m) {
        const double am = 0.5 * t.sign * t.a.c[m];
        for (std::size_t n = 0; n < t.b.n; ++n) g[m + n] += am * b[n];
        const std::size_t below = std::min(m + 1, t.b.n);
        for (std::size_t n = 0; n < below; ++n) g[m - n] += am * b[n];
        for (std::size_t n = m + 1; n < t.b.n; ++n) g[n - m] += am * b[n];
      }
      const double aa = abs_sum(t.a.c, t.a.n), ba = abs_sum(t.b.c, t.b.n);
      magnitude += aa * ba;
      from_radii += t.a.radius * ba + aa * t.b.radius + t.a.radius * t.b.radius;
    }
    const double gamma = gamma_of(count + ng + 16);
    // Integral: b_1 = g_0 - g_2/2, b_k = (g_{k-1} - g_{k+1}) / (2k), b_0 so that H(-1) = 0.
    const std::size_t nF = ng + 1;
    coeffs.assign(nF, 0.0);
    for (std::size_t k = 1; k < nF; ++k) {
      const double lo = g_[k - 1], hi = k + 1 < ng ? g_[k + 1] : 0.0;
      coeffs[k] = k == 1 ? lo - hi / 2 : (lo - hi) / static_cast<double>(2 * k);
    }
    for (std::size_t k = 1; k < nF; ++k) coeffs[0] += (k % 2) ? coeffs[k] : -coeffs[k];
    const double abs_g = abs_sum(g_.data(), ng), abs_F = abs_sum(coeffs.data(), nF);
    for (double& c : coeffs) c *= hl;
    // Products (and the views' radii), integrated over a length of at most 2; the integral's
    // roundings; the scaling by hl.
    error = std::abs(hl) * ((2 * (gamma * magnitude + from_radii) + gamma * (abs_g + 2 * abs_F)) * (1 + gamma) +
                            gamma * abs_F);
    error += 2 * hl_error * (magnitude + from_radii) * (1 + gamma);
    error += underflow_allowance(4 * count * count + 4 * nF);
    error *= 1 + 1e-12;  // the roundings of this bound's own arithmetic (relative ~ n u)
  }

 private:
  std::vector<double> g_;
};

// An upper bound of sup_{[-1,1]} |c0 + H - q| for the exact polynomials: H from
// integrated_products, q a view.
inline double residual_bound(double c0, const integrated_products& H, series_view q) {
  const std::size_t n = std::max(H.coeffs.size(), q.n);
  double sup = 0, magnitude = std::abs(c0);
  for (std::size_t k = 0; k < n; ++k) {
    const double h = k < H.coeffs.size() ? H.coeffs[k] : 0.0;
    const double qk = k < q.n ? q.c[k] : 0.0;
    double r = h - qk;
    if (k == 0) r += c0;
    sup += std::abs(r);
    magnitude += std::abs(h) + std::abs(qk);
  }
  return (sup + H.error + q.radius + gamma_of(n + 8) * magnitude + underflow_allowance(4 * n)) * (1 + 1e-12);
}

}  // namespace eulervop::detail

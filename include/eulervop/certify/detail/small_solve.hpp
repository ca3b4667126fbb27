// Small dense linear algebra in double for the certificate's iterations and its Lohner box: a
// solve by Gaussian elimination with partial pivoting, and an approximate inverse from it. What
// they return is only a starting point: the Lohner box encloses the true inverse from it in balls
// (ball_lohner_box.hpp), and the linear flow's u_num is a polynomial whose residual is bounded.
#pragma once

#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace eulervop::detail {

// Solves A x = v in place (A: D x D row-major, overwritten; v: D), by Gaussian elimination with
// partial pivoting in double. false where a pivot is zero or not finite. N > 0 fixes D at compile
// time (the same operations, unrolled).
template <std::size_t N>
bool solve_in_place(double* A, double* v, std::size_t dimension) {
  const std::size_t D = N > 0 ? N : dimension;
  for (std::size_t c = 0; c < D; ++c) {
    std::size_t p = c;
    for (std::size_t r = c + 1; r < D; ++r)
      if (std::abs(A[r * D + c]) > std::abs(A[p * D + c])) p = r;
    if (!(std::abs(A[p * D + c]) > 0) || !std::isfinite(A[p * D + c])) return false;
    if (p != c) {
      for (std::size_t k = 0; k < D; ++k) std::swap(A[p * D + k], A[c * D + k]);
      std::swap(v[p], v[c]);
    }
    for (std::size_t r = c + 1; r < D; ++r) {
      const double f = A[r * D + c] / A[c * D + c];
      for (std::size_t k = c; k < D; ++k) A[r * D + k] -= f * A[c * D + k];
      v[r] -= f * v[c];
    }
  }
  for (std::size_t c = D; c-- > 0;) {
    double x = v[c];
    for (std::size_t k = c + 1; k < D; ++k) x -= A[c * D + k] * v[k];
    v[c] = x / A[c * D + c];
  }
  return true;
}

// X ~ M^-1 (D x D, row-major), column by column; false where M is singular in double.
inline bool approximate_inverse(const std::vector<double>& M, std::size_t D, std::vector<double>& X) {
  std::vector<double> lu(D * D), column(D);
  X.assign(D * D, 0.0);
  for (std::size_t j = 0; j < D; ++j) {
    lu = M;
    for (std::size_t i = 0; i < D; ++i) column[i] = i == j ? 1.0 : 0.0;
    if (!solve_in_place<0>(lu.data(), column.data(), D)) return false;
    for (std::size_t i = 0; i < D; ++i) X[i * D + j] = column[i];
  }
  return true;
}

}  // namespace eulervop::detail

// Chebyshev-Gauss-Lobatto nodes and the matrices of the Picard iteration, built in the scalar T.
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/detail/fixed_point_matvec.hpp>

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace eulervop::detail {

// The (N+1)x(N+1) row-major matrix taking values at the Lobatto nodes s_j = -cos(j pi / N) to the
// Chebyshev coefficients a_k of their interpolant (discrete Chebyshev transform on Lobatto nodes):
// a_k = (2/N) sum_j'' F_j T_k(s_j), the end terms j = 0, N halved, and a_0, a_N halved, with
// T_k(s_j) = T_k(cos(pi - j pi/N)) = (-1)^k cos(k j pi / N). The angle k*j is reduced modulo 2N
// first so that cos is evaluated on [0, 2 pi) in T, and the 2N cosines are tabulated (a cosine per
// entry cost several milliseconds at start-up in quad).
template <scalar T>
std::vector<T> lobatto_cosines(std::size_t N) {
  using std::cos;
  const T pi = boost::math::constants::pi<T>();
  std::vector<T> cosines(2 * N);
  for (std::size_t m = 0; m < 2 * N; ++m) cosines[m] = cos(pi * T(m) / T(N));
  return cosines;
}

template <scalar T>
std::vector<T> lobatto_to_chebyshev(std::size_t N, const std::vector<T>& cosines) {
  const std::size_t n1 = N + 1;
  std::vector<T> a(n1 * n1, T(0));
  const T two_over_N = T(2) / T(N);
  for (std::size_t k = 0; k < n1; ++k)
    for (std::size_t j = 0; j < n1; ++j) {
      T w = two_over_N;
      if (j == 0 || j == N) w /= 2;
      if (k == 0 || k == N) w /= 2;
      const T& c = cosines[(k * j) % (2 * N)];
      a[k * n1 + j] = w * ((k % 2) ? T(-c) : c);
    }
  return a;
}

// Degree-N basis on s in [-1, 1] with nodes s_j = -cos(j pi / N), j = 0..N, so that node 0 is the
// segment start and node N its end.
//
// integral: the (N+1)x(N+1) matrix S with (S F)_j = integral_{-1}^{s_j} p(s) ds, where p is the
//   degree-N interpolant of the values F at the nodes (the Picard map of Clenshaw-Norton and
//   Bai-Junkins, here applied to node values directly).
// to_coeffs: the (N+2)x(N+1) matrix Q with (Q F)_k = coefficient k of that same integral in
//   T_0..T_{N+1} (the integral of a degree-N polynomial has degree N+1), whose decay drives the
//   segment length (the integrator's truncation estimate).
// coeffs: the (N+1)x(N+1) matrix giving the Chebyshev coefficients a_k of p itself; the
//   integrator extrapolates a segment's values with them into the next one's warm start.
// (Dense output needs none of these: it interpolates the node values directly.)
template <scalar T>
struct chebyshev_basis {
  std::size_t degree = 0;
  std::vector<T> nodes;      // s_j
  std::vector<T> integral;   // S, row-major (N+1)x(N+1)
  std::vector<T> to_coeffs;  // Q, row-major (N+2)x(N+1)
  std::vector<T> coeffs;     // values -> Chebyshev coefficients a_k of p, row-major (N+1)x(N+1)

  explicit chebyshev_basis(std::size_t N) : degree(N) {
    const std::size_t n1 = N + 1;
    const std::vector<T> cosines = lobatto_cosines<T>(N);
    nodes.resize(n1);
    for (std::size_t j = 0; j < n1; ++j) nodes[j] = -cosines[j];  // -cos(pi j / N), the same expression
    auto Tk = [&](std::size_t k, std::size_t j) {
      const T& c = cosines[(k * j) % (2 * N)];
      return (k % 2) ? T(-c) : c;
    };
    coeffs = lobatto_to_chebyshev<T>(N, cosines);
    // Integration of a Chebyshev series sum a_k T_k (full coefficients):
    //   b_1 = a_0 - a_2/2, b_k = (a_{k-1} - a_{k+1}) / (2k) for k >= 2 (a_{N+1} = a_{N+2} = 0),
    //   b_0 = -sum_{k>=1} (-1)^k b_k so that the integral vanishes at s = -1.
    const std::size_t n2 = N + 2;
    to_coeffs.assign(n2 * n1, T(0));
    auto a = [&](std::size_t k, std::size_t j) -> T { return k <= N ? coeffs[k * n1 + j] : T(0); };
    for (std::size_t j = 0; j < n1; ++j) {
      T b0 = 0;
      for (std::size_t k = 1; k < n2; ++k) {
        T bk = (k == 1) ? T(a(0, j) - a(2, j) / 2) : T((a(k - 1, j) - a(k + 1, j)) / T(2 * k));
        to_coeffs[k * n1 + j] = bk;
        if (k % 2) b0 += bk; else b0 -= bk;
      }
      to_coeffs[j] = b0;
    }
    // S = E Q with E_jk = T_k(s_j) for k = 0..N+1.
    std::vector<T> E(n1 * n2);
    for (std::size_t j = 0; j < n1; ++j)
      for (std::size_t k = 0; k < n2; ++k) E[j * n2 + k] = Tk(k, j);
    integral.assign(n1 * n1, T(0));
    if constexpr (std::is_same_v<T, double>) {
      for (std::size_t j = 0; j < n1; ++j)
        for (std::size_t i = 0; i < n1; ++i) {
          T acc = 0;
          for (std::size_t k = 0; k < n2; ++k) acc += E[j * n2 + k] * to_coeffs[k * n1 + i];
          integral[j * n1 + i] = acc;
        }
    } else {
      // Column by column as exact integer dot products rounded once (fixed_point_matvec.hpp):
      // the (N+1)^2 (N+2) products in soft-float quad took several milliseconds at start-up.
      fixed_point_matrix<T> e = [&] {
        if constexpr (std::is_same_v<T, quad>)
          return fixed_point_matrix<T>(E, n1, n2);
        else
          return fixed_point_matrix<T>(E, n1, n2, significand_bits<T>());
      }();
      std::vector<T> column(n2), out(n1, T(0));
      for (std::size_t i = 0; i < n1; ++i) {
        for (std::size_t k = 0; k < n2; ++k) column[k] = to_coeffs[k * n1 + i];
        e.multiply(column.data(), out.data());
        for (std::size_t j = 0; j < n1; ++j) integral[j * n1 + i] = out[j];
      }
    }
    // The first row integrates over an empty interval: exactly zero, not rounding noise.
    for (std::size_t i = 0; i < n1; ++i) integral[i] = 0;
  }
};

// Clenshaw evaluation of sum_{k=0}^{n-1} c[k] T_k(s).
template <scalar T, scalar C>
T clenshaw(const C* c, std::size_t n, std::size_t stride, const T& s) {
  T b1 = 0, b2 = 0;
  const T two_s = s + s;
  for (std::size_t k = n; k-- > 1;) {
    T b0 = two_s * b1;
    b0 -= b2;
    b0 += c[k * stride];
    b2 = b1;
    b1 = b0;
  }
  return s * b1 - b2 + c[0];
}

}  // namespace eulervop::detail

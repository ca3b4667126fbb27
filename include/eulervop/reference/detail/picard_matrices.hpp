// The matrices of one Chebyshev degree, in every form the reference integrator multiplies by:
// in T, in double, in double-double and in exact fixed point (docs/design.md section 3.2).
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/detail/chebyshev_basis.hpp>
#include <eulervop/reference/detail/double_double_matvec.hpp>
#include <eulervop/reference/detail/fixed_point_matvec.hpp>

#include <algorithm>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace eulervop::detail {

template <scalar T>
struct picard_matrices {
  std::size_t N, n1;            // the degree, and the number of nodes N + 1
  chebyshev_basis<T> basis;     // S (integral), Q (to_coeffs), C (coeffs) and the nodes, in T
  std::vector<T> nodes_plus_one;  // s_j + 1 in T, for the node times tau + hl (s_j + 1) of every segment
  std::vector<double> S_d, S_dt;  // S in double, and transposed: column k contiguous
  std::vector<double> Q_d, C_d;  // Q and C in double
  double_double_matrix S_dd;    // S in double-double (wide T)
  // S and Q in fixed point (wide T): exact integer products rounded once.
  struct none {};
  using fixed_point = std::conditional_t<std::is_same_v<T, double>, none, fixed_point_matrix<T>>;
  fixed_point S_fx, Q_fx;
  // MPFR: S on three limbs (188 bits) for a segment's first residual in T, where the products
  // of S_fx take more limbs; empty (rows() == 0) otherwise.
  fixed_point S_fx_first;
  static constexpr unsigned first_residual_bits = 188;

  bool has_first_residual_matrix() const {
    if constexpr (std::is_same_v<T, mpfr_real>) return S_fx_first.rows() > 0;
    else return false;
  }

  // `product_bits`: the bits the MPFR products must resolve (the run's effective bits).
  picard_matrices(std::size_t degree, unsigned product_bits);

  // y_i = S g_i (rows 1..N) in double for each component. Column order (y += S[:,k] g[k])
  // keeps the rows independent, so the compiler vectorizes across them without reassociating
  // any sum (a row-by-row dot product is bound by the latency of its serial additions); four
  // columns per pass over y quarter its loads and stores, which bound the plain column loop.
  template <class Components>
  [[gnu::always_inline]] void double_integral(const Components& g, Components& y) const {
    for (std::size_t i = 0; i < g.size(); ++i) {
      double* out = y[i].data();
      const double* gi = g[i].data();
      std::fill(out, out + n1, 0.0);
      std::size_t k = 0;
      for (; k + 4 <= n1; k += 4) {
        const double* c0 = &S_dt[k * n1];
        const double* c1 = c0 + n1;
        const double* c2 = c1 + n1;
        const double* c3 = c2 + n1;
        const double g0 = gi[k], g1 = gi[k + 1], g2 = gi[k + 2], g3 = gi[k + 3];
        for (std::size_t j = 0; j < n1; ++j) out[j] += (c0[j] * g0 + c1[j] * g1) + (c2[j] * g2 + c3[j] * g3);
      }
      for (; k < n1; ++k) {
        const double* col = &S_dt[k * n1];
        const double gk = gi[k];
        for (std::size_t j = 0; j < n1; ++j) out[j] += col[j] * gk;
      }
    }
  }
};

// Out of the class, so that a unit that declares the matrices extern (reference/integrate.hpp)
// compiles none of their construction, which the compiled kernels hold once per scalar.
template <scalar T>
picard_matrices<T>::picard_matrices(std::size_t degree, unsigned product_bits)
    : N(degree), n1(degree + 1), basis(degree) {
  nodes_plus_one.resize(n1);
  for (std::size_t j = 0; j < n1; ++j) nodes_plus_one[j] = basis.nodes[j] + 1;
  S_d.resize(n1 * n1);
  for (std::size_t k = 0; k < n1 * n1; ++k) S_d[k] = static_cast<double>(basis.integral[k]);
  S_dt.resize(n1 * n1);
  for (std::size_t j = 0; j < n1; ++j)
    for (std::size_t k = 0; k < n1; ++k) S_dt[k * n1 + j] = static_cast<double>(basis.integral[j * n1 + k]);
  Q_d.resize((N + 2) * n1);
  for (std::size_t k = 0; k < (N + 2) * n1; ++k) Q_d[k] = static_cast<double>(basis.to_coeffs[k]);
  C_d.resize(n1 * n1);
  for (std::size_t k = 0; k < n1 * n1; ++k) C_d[k] = static_cast<double>(basis.coeffs[k]);
  if constexpr (!std::is_same_v<T, double>) S_dd = double_double_matrix(basis.integral, n1, n1);
  if constexpr (std::is_same_v<T, quad>) {
    S_fx = fixed_point_matrix<T>(basis.integral, n1, n1);
    Q_fx = fixed_point_matrix<T>(basis.to_coeffs, N + 2, n1);
  } else if constexpr (std::is_same_v<T, mpfr_real>) {
    // The products resolve the bits the run must resolve and 24 more (the sums of N+1 terms
    // lose a few): with a tolerance looser than the precision, fewer limbs per product.
    const unsigned bits = std::min(significand_bits<T>(), product_bits + 24);
    S_fx = fixed_point_matrix<T>(basis.integral, n1, n1, bits);
    Q_fx = fixed_point_matrix<T>(basis.to_coeffs, N + 2, n1, bits);
    if (bits > first_residual_bits) S_fx_first = fixed_point_matrix<T>(basis.integral, n1, n1, first_residual_bits);
  }
}

}  // namespace eulervop::detail

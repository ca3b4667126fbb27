// The variational matrix of a segment, Phi' = hl J(P(s)) Phi on s in [-1, 1], Phi(-1) = I
// (docs/certified.md, "How", step 4): Gauss-Seidel sweeps in double on 17 Lobatto nodes; Phi_num is
// the polynomial of its Chebyshev coefficients (exact doubles by definition). Its residual
// R(s) = I + hl int J Phi_num - Phi_num is bounded with every rounding (bounded_chebyshev.hpp);
// E = Phi - Phi_num solves E = R + hl int J E, so |E(1)| <= sup|R| (1 + h exp(mu h) |J|). That
// error only multiplies e(a), which is far below double's precision, so double is enough.
#pragma once

#include <eulervop/certify/detail/bounded_chebyshev.hpp>
#include <eulervop/certify/detail/linearized_flow.hpp>
#include <eulervop/certify/detail/real.hpp>
#include <eulervop/certify/detail/segment_polynomial.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/reference/detail/chebyshev_basis.hpp>

#include <mpfi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace eulervop::detail {

// adj = the adjugate of the 3x3 matrix A (both row-major), so that A^-1 = adj / det; returns det.
inline double adjugate_3x3(const double* A, double* adj) {
  adj[0] = A[4] * A[8] - A[5] * A[7];
  adj[1] = A[2] * A[7] - A[1] * A[8];
  adj[2] = A[1] * A[5] - A[2] * A[4];
  adj[3] = A[5] * A[6] - A[3] * A[8];
  adj[4] = A[0] * A[8] - A[2] * A[6];
  adj[5] = A[2] * A[3] - A[0] * A[5];
  adj[6] = A[3] * A[7] - A[4] * A[6];
  adj[7] = A[1] * A[6] - A[0] * A[7];
  adj[8] = A[0] * A[4] - A[1] * A[3];
  return A[0] * adj[0] + A[1] * adj[3] + A[2] * adj[6];
}

class variational_matrix {
 public:
  variational_matrix()
      : Phi1(9, interval::zero(error_bits)), eps(interval::zero(error_bits)), scratch_(interval::zero(error_bits)) {}

  void compute(const segment_polynomial& P, const jacobian_rows& rows, const linear_growth& g,
               integrated_products& sums);

  // Phi_num's entry q = 3 i + j: its coefficient_count Chebyshev coefficients.
  static constexpr std::size_t coefficient_count = 17;
  const double* coefficients(int q) const { return &phi_[q * m1_]; }

  std::vector<interval> Phi1;  // 3x3: Phi_num(1), enclosed
  interval eps;                // |Phi(b, a) - Phi_num(1)|_2 <= eps

 private:
  static constexpr std::size_t m1_ = coefficient_count;
  void jacobian_at_nodes(const segment_polynomial& P, const jacobian_rows& rows);
  void iterate(const segment_polynomial& P, double hl);
  void coefficients();
  double residual_sup(const segment_polynomial& P, const jacobian_rows& rows, double hl, integrated_products& sums);

  chebyshev_basis<double> basis_{m1_ - 1};
  // At node l, entry q = 3 i + j: J, Phi and J Phi; phi_: entry q's coefficients k at q m1 + k.
  // inverse_: (I - hl S_ll J_l)^-1 at node l, for the implicit step of iterate().
  std::vector<double> J_ = std::vector<double>(m1_ * 9), Phi_ = J_, F_ = J_, phi_ = J_, inverse_ = J_;
  interval scratch_;
};

inline void variational_matrix::compute(const segment_polynomial& P, const jacobian_rows& rows,
                                        const linear_growth& g, integrated_products& sums) {
  jacobian_at_nodes(P, rows);
  iterate(P, g.hl);
  coefficients();
  sums.hl_error = g.hl_error;
  g.error_at_end(eps, residual_sup(P, rows, g.hl, sums), P);
  for (int q = 0; q < 9; ++q) enclose_double_sum(Phi1[q], &phi_[q * m1_], m1_, scratch_);  // Phi_num(1)
}

inline void variational_matrix::jacobian_at_nodes(const segment_polynomial& P, const jacobian_rows& rows) {
  for (std::size_t l = 0; l < m1_; ++l) {
    double y[3];
    for (int i = 0; i < 3; ++i) y[i] = clenshaw(&P.cd[i * P.n1], P.n1, 1, basis_.nodes[l]);
    double* Jl = &J_[l * 9];
    std::fill(Jl, Jl + 9, 0.0);
    for (int i = 0; i < 3; ++i)
      for (const jacobian_entry& e : rows[i]) Jl[i * 3 + e.k] = e.coefficient * y[e.c];
  }
}

// Gauss-Seidel over the nodes, as the reference's correction (reference/detail/picard_correction.hpp):
// node l's integral takes the newest Phi of the nodes before it, and its own term is implicit,
// (I - c J_l) Phi_l = I + hl sum_{k != l} S_lk J_k Phi_k with c = hl S_ll. About a third of the
// plain Picard iterations (all nodes from the previous one). Any Phi_num will do for soundness:
// its residual is bounded afterwards (residual_sup); this only makes the bound small.
inline void variational_matrix::iterate(const segment_polynomial& P, double hl) {
  for (std::size_t l = 0; l < m1_; ++l)
    for (int q = 0; q < 9; ++q) {
      Phi_[l * 9 + q] = (q % 4 == 0) ? 1.0 : 0.0;
      F_[l * 9 + q] = J_[l * 9 + q];
    }
  // (I - c J_l)^-1 by its adjugate: c |J| is about hl |J| / m1, far from singular.
  for (std::size_t l = 1; l < m1_; ++l) {
    const double c = hl * basis_.integral[l * m1_ + l];
    double A[9];
    for (int q = 0; q < 9; ++q) A[q] = ((q % 4 == 0) ? 1.0 : 0.0) - c * J_[l * 9 + q];
    double* Ml = &inverse_[l * 9];
    const double det = adjugate_3x3(A, Ml);
    if (!std::isfinite(det) || det == 0) P.fail(outcome_kind::certify_non_finite);
    for (int q = 0; q < 9; ++q) Ml[q] /= det;
  }
  for (int it = 0; it < 200; ++it) {
    double change = 0, size = 0;
    for (std::size_t l = 1; l < m1_; ++l) {
      // The nine entries side by side (each still summed over k in order), so that the
      // compiler vectorizes across them.
      double acc[9] = {};
      for (std::size_t k = 0; k < m1_; ++k) {
        if (k == l) continue;
        const double s = basis_.integral[l * m1_ + k];
        for (int q = 0; q < 9; ++q) acc[q] += s * F_[k * 9 + q];
      }
      double rhs[9];
      for (int q = 0; q < 9; ++q) rhs[q] = ((q % 4 == 0) ? 1.0 : 0.0) + hl * acc[q];
      const double* Ml = &inverse_[l * 9];
      const double* Jl = &J_[l * 9];
      double* Phil = &Phi_[l * 9];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const double next = Ml[i * 3] * rhs[j] + Ml[i * 3 + 1] * rhs[3 + j] + Ml[i * 3 + 2] * rhs[6 + j];
          change = std::max(change, std::abs(next - Phil[i * 3 + j]));
          size = std::max(size, std::abs(next));
          Phil[i * 3 + j] = next;
        }
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          F_[l * 9 + i * 3 + j] = Jl[i * 3] * Phil[j] + Jl[i * 3 + 1] * Phil[3 + j] + Jl[i * 3 + 2] * Phil[6 + j];
    }
    if (!std::isfinite(change)) P.fail(outcome_kind::certify_non_finite);
    if (change <= 1e-10 * size) break;  // its error multiplies |e(a)|: ten digits are plenty
  }
}

inline void variational_matrix::coefficients() {
  for (int q = 0; q < 9; ++q)
    for (std::size_t k = 0; k < m1_; ++k) {
      double acc = 0;
      for (std::size_t l = 0; l < m1_; ++l) acc += basis_.coeffs[k * m1_ + l] * Phi_[l * 9 + q];
      phi_[q * m1_ + k] = acc;
    }
}

// sup |R|_2 <= the root of the sum over the entries of sup |R_ij|^2.
inline double variational_matrix::residual_sup(const segment_polynomial& P, const jacobian_rows& rows, double hl,
                                               integrated_products& sums) {
  double sup2 = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      std::array<product_term, 2> terms;
      for (int t = 0; t < 2; ++t) {
        const jacobian_entry& e = rows[i][t];
        terms[t] = {e.coefficient, P.short_view(e.c), {&phi_[(e.k * 3 + j) * m1_], m1_, 0.0}};
      }
      sums.compute(hl, terms);
      const double b = residual_bound(i == j ? 1.0 : 0.0, sums, {&phi_[(i * 3 + j) * m1_], m1_, 0.0});
      sup2 += b * b;
    }
  return std::sqrt(sup2) * (1 + 1e-12);
}

}  // namespace eulervop::detail

// The double-precision half of the linear flow (ball_linear_flow.hpp): Picard iteration on
// Chebyshev-Lobatto nodes (Clenshaw and Norton 1963; Bai and Junkins 2011), where no rounding
// matters, since its result only proposes a polynomial that the flow then defines as exact and
// checks by its residual. Two linear Volterra equations on s in [-1, 1]:
//   Phi = I + hl S (J Phi)      (the variational matrix, D x D per node)
//   u   = hl S (J (u + r))      (the signed integral term, D per node)
// with S the integration matrix of chebyshev_basis.hpp ((S F)_l = int_{-1}^{s_l} of the
// interpolant of F); u also by variation of constants, u = Phi S (Phi^-1 hl J r), in one pass
// of the same sums. Each sweep visits the nodes in order and updates J Y at a node as soon as Y
// is (Gauss-Seidel): the operator is a Volterra one, so this converges in a few sweeps where
// Jacobi's takes about e |J| h of them. The rounding order of every sum is fixed here, whatever
// the dimension, so that a run gives the same bits on any number of threads and in any build.
#pragma once

#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/reference/detail/chebyshev_basis.hpp>

#include <flint/fmpz_poly.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace eulervop::detail {

// The bases of a few node counts, built once per process and shared by every check (each costs
// O(n^3) to build).
inline const chebyshev_basis<double>& lobatto_basis(std::size_t nodes) {
  static std::mutex mutex;
  static std::map<std::size_t, std::unique_ptr<const chebyshev_basis<double>>> bases;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& b = bases[nodes];
  if (!b) b = std::make_unique<const chebyshev_basis<double>>(nodes - 1);
  return *b;
}

// One Gauss-Seidel sweep's integrals: for each node l in order, acc[i] = sum_{k < m} S[l m + k]
// F[k n + i] (i < n), each sum from k = 0 up and from 0.0, then finish(l, acc), which updates F's
// row l before the next node's sums read it. N > 0 fixes n at compile time, so that the sums stay
// in registers: the loop over memory (N = 0) carries each sum through a store and a load per
// term, a dependency of several cycles that made it the flow's largest cost. With N > 0 the
// nodes also go in blocks of B: the terms k < l0 of a block's rows are final before the block
// starts, so those B n sums run side by side; each row then adds its terms k >= l0 in order, after
// the rows before it have finished. Every sum has the same terms in the same order as the loop
// over memory: the same bits (test_ball_linear_flow_reuse.cpp compares them).
template <std::size_t N, class Finish>
void gauss_seidel_sweep(const double* S, const double* F, std::size_t m, std::size_t n, std::vector<double>& acc,
                        Finish&& finish) {
  if constexpr (N == 0) {
    acc.resize(n);
    for (std::size_t l = 0; l < m; ++l) {
      std::fill(acc.begin(), acc.end(), 0.0);
      for (std::size_t k = 0; k < m; ++k) {
        const double sk = S[l * m + k];
        for (std::size_t i = 0; i < n; ++i) acc[i] += sk * F[k * n + i];
      }
      finish(l, static_cast<const double*>(acc.data()));
    }
  } else {
    constexpr std::size_t B = N <= 4 ? 4 : 2;  // B N <= 18 sums: within the 32 doubles of SSE2's 16 registers
    for (std::size_t l0 = 0; l0 < m; l0 += B) {
      const std::size_t rows = std::min(B, m - l0);
      double a[B][N] = {};
      for (std::size_t k = 0; k < l0; ++k)
        for (std::size_t r = 0; r < B; ++r) {
          if (r >= rows) break;
          const double s = S[(l0 + r) * m + k];
          for (std::size_t i = 0; i < N; ++i) a[r][i] += s * F[k * N + i];
        }
      for (std::size_t r = 0; r < rows; ++r) {
        const double* Sl = S + (l0 + r) * m;
        for (std::size_t k = l0; k < m; ++k)
          for (std::size_t i = 0; i < N; ++i) a[r][i] += Sl[k] * F[k * N + i];
        finish(l0 + r, static_cast<const double*>(a[r]));
      }
    }
  }
}

// The scratch and the steps of the iterations, reused from segment to segment.
class node_picard {
 public:
  // T_k at the nodes for k < n, by the recurrence run across all nodes at once (T_k(s_l) at
  // [k m + l]). Kept per basis (the bases live as long as the program: lobatto_basis()), so that a
  // segment reuses the tables of the segments before it; the same values as recomputing them.
  void chebyshev_at_nodes(const chebyshev_basis<double>& b, std::size_t n) {
    n = std::max<std::size_t>(n, 2);
    auto t = std::find_if(tables_.begin(), tables_.end(), [&](const node_table& x) { return x.basis == &b; });
    if (t == tables_.end()) t = tables_.insert(tables_.end(), node_table{&b, 0, {}});
    if (t->n < n) {
      const std::size_t m = b.nodes.size();
      std::vector<double>& T = t->T;
      T.resize(n * m);
      for (std::size_t l = 0; l < m; ++l) {
        T[l] = 1;
        T[m + l] = b.nodes[l];
      }
      for (std::size_t k = 2; k < n; ++k)
        for (std::size_t l = 0; l < m; ++l) T[k * m + l] = 2 * b.nodes[l] * T[(k - 1) * m + l] - T[(k - 2) * m + l];
      t->n = n;
    }
    Tn_ = t->T.data();
  }

  // sum_k c_k T_k at the m nodes, into out[l * stride] (chebyshev_at_nodes for at least c's length).
  void series_at_nodes(const double* c, std::size_t length, std::size_t m, double* out, std::size_t stride) {
    v_.assign(m, 0.0);
    for (std::size_t k = 0; k < length; ++k) {
      const double ck = c[k];
      const double* T = Tn_ + k * m;
      for (std::size_t l = 0; l < m; ++l) v_[l] += ck * T[l];
    }
    for (std::size_t l = 0; l < m; ++l) out[l * stride] = v_[l];
  }

  // The coefficients of the values at the nodes (values[l * stride + q], q < count), on the grid
  // 2^e with `bits` bits below their largest (e returned): the polynomials they define, exactly.
  slong grid_coefficients(const chebyshev_basis<double>& b, const double* values, std::size_t stride,
                          std::size_t count, std::vector<integer_poly>& out, slong bits);

  // Phi on the nodes of b into Y (m x D x D, node-major), from the Jacobian at the nodes Jn (the
  // same layout). Only the entries `entries` (q = i D + j) can be nonzero; through[q] lists the k
  // with J_ik != 0 and Phi_kj live. false when a sweep's change is not finite.
  bool variational_sweeps(const chebyshev_basis<double>& b, const double* Jn, std::size_t D, double hl,
                          const std::vector<std::size_t>& entries,
                          const std::vector<std::vector<std::size_t>>& through, std::vector<double>& Y);
  // u on the nodes of b into Y (m x D) by variation of constants, u(s) = Phi(s) int_{-1}^s
  // Phi^-1 hl J r, from Jn, r at the nodes rn (m x D) and Phi at the nodes Pn (m x D x D): one
  // pass where the sweeps below take several. false where a Phi is singular in double or a value
  // is not finite.
  bool integral_term_by_variation(const chebyshev_basis<double>& b, const double* Jn, const double* rn,
                                  const double* Pn, std::size_t D, double hl, std::vector<double>& Y);
  // u on the nodes of b into Y (m x D), from Jn and r at the nodes rn (m x D).
  bool integral_term_sweeps(const chebyshev_basis<double>& b, const double* Jn, const double* rn, std::size_t D,
                            double hl, std::vector<double>& Y);

 private:
  template <std::size_t N>
  bool variational_kernel(const chebyshev_basis<double>& b, const double* Jn, std::size_t D, double hl,
                          const std::vector<std::size_t>& entries,
                          const std::vector<std::vector<std::size_t>>& through, std::vector<double>& Y);
  template <std::size_t N>
  bool integral_term_kernel(const chebyshev_basis<double>& b, const double* Jn, const double* rn, std::size_t D,
                            double hl, std::vector<double>& Y);

  struct node_table {
    const chebyshev_basis<double>* basis;
    std::size_t n;  // T_0 .. T_{n-1}
    std::vector<double> T;
  };
  std::vector<node_table> tables_;
  const double* Tn_ = nullptr;  // chebyshev_at_nodes' table
  std::vector<double> v_, F_, acc_, c_, lu_;
};

// Solves A x = v in place (A: D x D row-major, overwritten; v: D), by Gaussian elimination with
// partial pivoting in double. false where a pivot is zero or not finite.
inline bool solve_in_place(double* A, double* v, std::size_t D) {
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

inline bool node_picard::integral_term_by_variation(const chebyshev_basis<double>& b, const double* Jn,
                                                    const double* rn, const double* Pn, std::size_t D, double hl,
                                                    std::vector<double>& Y) {
  const std::size_t m = b.nodes.size(), DD = D * D;
  F_.assign(m * D, 0.0);  // g = Phi^-1 hl J r at the nodes
  lu_.resize(DD);
  for (std::size_t l = 0; l < m; ++l) {
    double* g = F_.data() + l * D;
    for (std::size_t i = 0; i < D; ++i) {
      double acc = 0;
      for (std::size_t k = 0; k < D; ++k) acc += Jn[l * DD + i * D + k] * rn[l * D + k];
      g[i] = hl * acc;
    }
    std::copy(Pn + l * DD, Pn + (l + 1) * DD, lu_.begin());
    if (!solve_in_place(lu_.data(), g, D)) return false;
  }
  // w = S g (the integral from -1 at each node: one pass of the sweep's sums, g fixed), then
  // u = Phi w.
  Y.assign(m * D, 0.0);
  bool finite = true;
  const auto finish = [&](std::size_t l, const double* w) {
    for (std::size_t i = 0; i < D; ++i) {
      double u = 0;
      for (std::size_t k = 0; k < D; ++k) u += Pn[l * DD + i * D + k] * w[k];
      finite = finite && std::isfinite(u);
      Y[l * D + i] = u;
    }
  };
  if (D == 3)
    gauss_seidel_sweep<3>(b.integral.data(), F_.data(), m, D, acc_, finish);
  else if (D == 7)
    gauss_seidel_sweep<7>(b.integral.data(), F_.data(), m, D, acc_, finish);
  else
    gauss_seidel_sweep<0>(b.integral.data(), F_.data(), m, D, acc_, finish);
  return finite;
}

inline slong node_picard::grid_coefficients(const chebyshev_basis<double>& b, const double* values,
                                            std::size_t stride, std::size_t count, std::vector<integer_poly>& out,
                                            slong bits) {
  const std::size_t m = b.nodes.size();
  c_.resize(count * m);
  double big = 0;
  for (std::size_t q = 0; q < count; ++q) {
    // c_k = sum_l coeffs_kl values_l from l = 0 up; four k side by side (independent sums, each
    // in its own order), the rest one by one.
    std::size_t k = 0;
    for (; k + 4 <= m; k += 4) {
      double acc[4] = {};
      for (std::size_t l = 0; l < m; ++l) {
        const double v = values[l * stride + q];
        for (std::size_t t = 0; t < 4; ++t) acc[t] += b.coeffs[(k + t) * m + l] * v;
      }
      for (std::size_t t = 0; t < 4; ++t) c_[q * m + k + t] = acc[t];
    }
    for (; k < m; ++k) {
      double acc = 0;
      for (std::size_t l = 0; l < m; ++l) acc += b.coeffs[k * m + l] * values[l * stride + q];
      c_[q * m + k] = acc;
    }
    for (k = 0; k < m; ++k) big = std::max(big, std::abs(c_[q * m + k]));
  }
  const slong e = big > 0 ? static_cast<slong>(std::ilogb(big)) + 1 - bits : 0;
  out.resize(count);
  for (std::size_t q = 0; q < count; ++q) {
    fmpz_poly_struct* p = out[q].p;
    fmpz_poly_fit_length(p, static_cast<slong>(m));
    for (std::size_t k = 0; k < m; ++k)  // trunc(c 2^-e): exact, as c 2^-e has at most 53 bits above the grid
      fmpz_set_d(p->coeffs + k, std::trunc(std::ldexp(c_[q * m + k], static_cast<int>(-e))));
    _fmpz_poly_set_length(p, static_cast<slong>(m));
    _fmpz_poly_normalise(p);
  }
  return e;
}

inline bool node_picard::variational_sweeps(const chebyshev_basis<double>& b, const double* Jn, std::size_t D,
                                            double hl, const std::vector<std::size_t>& entries,
                                            const std::vector<std::vector<std::size_t>>& through,
                                            std::vector<double>& Y) {
  if (D == 3) return variational_kernel<9>(b, Jn, D, hl, entries, through, Y);
  return variational_kernel<0>(b, Jn, D, hl, entries, through, Y);
}

inline bool node_picard::integral_term_sweeps(const chebyshev_basis<double>& b, const double* Jn, const double* rn,
                                              std::size_t D, double hl, std::vector<double>& Y) {
  if (D == 3) return integral_term_kernel<3>(b, Jn, rn, D, hl, Y);
  if (D == 7) return integral_term_kernel<7>(b, Jn, rn, D, hl, Y);
  return integral_term_kernel<0>(b, Jn, rn, D, hl, Y);
}

// Until the largest change is below 1e-13 of the largest entry (twelve digits: what the nodes
// resolve), at most 400 sweeps.
template <std::size_t N>
bool node_picard::variational_kernel(const chebyshev_basis<double>& b, const double* Jn, std::size_t D, double hl,
                                     const std::vector<std::size_t>& entries,
                                     const std::vector<std::vector<std::size_t>>& through, std::vector<double>& Y) {
  const std::size_t m = b.nodes.size(), DD = D * D;
  Y.assign(m * DD, 0.0);
  F_.assign(m * DD, 0.0);
  for (std::size_t l = 0; l < m; ++l)
    for (std::size_t i = 0; i < D; ++i) Y[l * DD + i * D + i] = 1;
  const auto product_at = [&](std::size_t l) {
    const double* Jl = Jn + l * DD;
    const double* Yl = Y.data() + l * DD;
    for (const std::size_t q : entries) {
      const std::size_t i = q / D, j = q % D;
      double acc = 0;
      for (const std::size_t k : through[q]) acc += Jl[i * D + k] * Yl[k * D + j];
      F_[l * DD + q] = acc;
    }
  };
  for (std::size_t l = 0; l < m; ++l) product_at(l);
  for (int sweep = 0; sweep < 400; ++sweep) {
    double change = 0, size = 0;
    gauss_seidel_sweep<N>(b.integral.data(), F_.data(), m, DD, acc_, [&](std::size_t l, const double* acc) {
      for (const std::size_t q : entries) {
        const double next = (q % (D + 1) == 0 ? 1.0 : 0.0) + hl * acc[q];
        change = std::max(change, std::abs(next - Y[l * DD + q]));
        size = std::max(size, std::abs(next));
        Y[l * DD + q] = next;
      }
      product_at(l);
    });
    if (!std::isfinite(change)) return false;
    if (change <= 1e-13 * size) break;
  }
  return true;
}

// Until the largest change is below 1e-10 of the largest entry (u only needs a few digits: its
// error is bounded relative to it), at most 400 sweeps.
template <std::size_t N>
bool node_picard::integral_term_kernel(const chebyshev_basis<double>& b, const double* Jn, const double* rn,
                                       std::size_t D, double hl, std::vector<double>& Y) {
  const std::size_t m = b.nodes.size(), DD = D * D;
  Y.assign(m * D, 0.0);
  F_.assign(m * D, 0.0);
  const auto product_at = [&](std::size_t l) {
    for (std::size_t i = 0; i < D; ++i) {
      double acc = 0;
      for (std::size_t k = 0; k < D; ++k) acc += Jn[l * DD + i * D + k] * (Y[l * D + k] + rn[l * D + k]);
      F_[l * D + i] = acc;
    }
  };
  for (std::size_t l = 0; l < m; ++l) product_at(l);
  for (int sweep = 0; sweep < 400; ++sweep) {
    double change = 0, size = 0;
    gauss_seidel_sweep<N>(b.integral.data(), F_.data(), m, D, acc_, [&](std::size_t l, const double* acc) {
      for (std::size_t i = 0; i < D; ++i) {
        const double next = hl * acc[i];
        change = std::max(change, std::abs(next - Y[l * D + i]));
        size = std::max(size, std::abs(next));
        Y[l * D + i] = next;
      }
      product_at(l);
    });
    if (!std::isfinite(change)) return false;
    if (change <= 1e-10 * size || size == 0) break;
  }
  return true;
}

}  // namespace eulervop::detail

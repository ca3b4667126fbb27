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
#include <eulervop/certify/detail/small_solve.hpp>
#include <eulervop/reference/detail/chebyshev_basis.hpp>

#include <flint/fmpz_poly.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
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

// out[t] = sum_{k < n} x[k xs] M[k ms + t] for t < W (W even), each sum from 0.0 and k = 0 up: W
// sums side by side, in W / 2 pairs of GCC's vector extension (SSE2's registers), which are the
// same IEEE operations lane by lane. Written out because the compiler's own vectorisation of the
// scalar loop pairs consecutive k and shuffles, at about twice the instructions.
template <std::size_t W>
void strided_sums(const double* x, std::size_t xs, const double* M, std::size_t ms, std::size_t n, double* out) {
  using pair = double __attribute__((vector_size(16)));
  pair a[W / 2] = {};
  for (std::size_t k = 0; k < n; ++k) {
    const double xk = x[k * xs];
    const pair s = {xk, xk};
    const double* Mk = M + k * ms;
    for (std::size_t t = 0; t < W / 2; ++t) {
      pair v;
      std::memcpy(&v, Mk + 2 * t, sizeof v);
      a[t] += s * v;
    }
  }
  std::memcpy(out, a, sizeof a);
}

// The same sweep, node by node: F's rows have `stride` entries (a multiple of W; the columns from
// n up are zero and their sums unused), and each row's sums go in chunks of W side by side
// (strided_sums), over all k from k = 0 up, so that they stay in registers whatever n is. Every
// sum has the terms of gauss_seidel_sweep<0> in its order: the same bits.
template <std::size_t W, class Finish>
void chunked_sweep(const double* S, const double* F, std::size_t m, std::size_t stride, std::vector<double>& acc,
                   Finish&& finish) {
  acc.resize(stride);
  for (std::size_t l = 0; l < m; ++l) {
    for (std::size_t c0 = 0; c0 < stride; c0 += W) strided_sums<W>(S + l * m, 1, F + c0, stride, m, acc.data() + c0);
    finish(l, static_cast<const double*>(acc.data()));
  }
}

// A node's products (J Y)_e of the live entries into Fl, each over its terms in order, from J's
// and Y's rows at the node (variational_kernel's layout and cases; the terms t of entry e are
// [start[e], start[e + 1]), J's entry tj[t] times Y's ty[t]).
template <std::size_t N, unsigned Mask>
void products_at(const double* Jl, const double* Yl, double* Fl, std::size_t L, const std::size_t* start,
                 const std::size_t* tj, const std::size_t* ty) {
  if constexpr (Mask != 0) {  // J_ik Y_kj over the k of the pattern, in order
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < 3; ++j) {
        double acc = 0;
        for (std::size_t k = 0; k < 3; ++k)
          if ((Mask >> (i * 3 + k)) & 1u) acc += Jl[i * 3 + k] * Yl[k * 3 + j];
        Fl[i * 3 + j] = acc;
      }
  } else if constexpr (N > 0) {
    for (std::size_t e = 0; e < N; ++e) {
      double acc = 0;
      for (std::size_t t = 3 * e; t < 3 * e + 3; ++t) acc += Jl[tj[t]] * Yl[ty[t]];
      Fl[e] = acc;
    }
  } else {
    for (std::size_t e = 0; e < L; ++e) {
      // The terms in order; up to 8 without a loop (the compiler turns the loop into gathers in
      // pairs, at twice the instructions for these few terms).
      const std::size_t t0 = start[e], end = start[e + 1];
      const auto term = [&](std::size_t t) { return Jl[tj[t]] * Yl[ty[t]]; };
      double acc = 0;
      switch (end - t0) {
        case 8: acc += term(end - 8); [[fallthrough]];
        case 7: acc += term(end - 7); [[fallthrough]];
        case 6: acc += term(end - 6); [[fallthrough]];
        case 5: acc += term(end - 5); [[fallthrough]];
        case 4: acc += term(end - 4); [[fallthrough]];
        case 3: acc += term(end - 3); [[fallthrough]];
        case 2: acc += term(end - 2); [[fallthrough]];
        case 1: acc += term(end - 1); [[fallthrough]];
        case 0: break;
        default:
          for (std::size_t t = t0; t < end; ++t) acc += term(t);
      }
      Fl[e] = acc;
    }
  }
}

// out[k] = std::ldexp(fmpz_get_d(p_k), e), p's coefficients times 2^e as doubles: by a product with
// 2^e where that is a normal double, which rounds once as ldexp does (the same value, without a
// call per coefficient).
inline void scaled_doubles(const fmpz_poly_struct* p, slong e, std::vector<double>& out) {
  out.resize(static_cast<std::size_t>(p->length));
  if (e >= -1022 && e <= 1023) {
    const double scale = std::ldexp(1.0, static_cast<int>(e));
    for (slong k = 0; k < p->length; ++k) out[k] = fmpz_get_d(p->coeffs + k) * scale;
  } else {
    for (slong k = 0; k < p->length; ++k) out[k] = std::ldexp(fmpz_get_d(p->coeffs + k), static_cast<int>(e));
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
    // v_l = sum_k c_k T_k(s_l) from k = 0 up and from 0.0: eight nodes side by side, the last few
    // one by one (the table's rows are not padded).
    v_.resize(m);
    std::size_t l0 = 0;
    for (; l0 + 8 <= m; l0 += 8) strided_sums<8>(c, 1, Tn_ + l0, m, length, v_.data() + l0);
    for (std::size_t l = l0; l < m; ++l) {
      double acc = 0;
      for (std::size_t k = 0; k < length; ++k) acc += c[k] * Tn_[k * m + l];
      v_[l] = acc;
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
  void flatten_entries(std::size_t D, const std::vector<std::size_t>& entries,
                       const std::vector<std::vector<std::size_t>>& through, std::size_t terms);
  template <std::size_t N, unsigned Mask = 0>
  bool variational_kernel(const chebyshev_basis<double>& b, const double* Jn, std::size_t DD, double hl);
  template <std::size_t N>
  bool variation_kernel(const chebyshev_basis<double>& b, const double* Jn, const double* rn, const double* Pn,
                        std::size_t dimension, double hl, std::vector<double>& Y);
  const std::vector<double>& transposed(const std::vector<double>& M, std::size_t m);
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
  // The live entries of Phi as flat arrays (flatten_entries): Yc_ and F_ hold entry e = 0..L-1
  // of each node (the entry entries[e]) at [l stride + e]; diag_[e] is the identity's entry; the
  // terms of e's product are t in [term_start_[e], term_start_[e + 1]), J's entry term_j_[t] at
  // the node times Yc_'s column term_y_[t], in through's order.
  std::vector<double> Yc_, diag_, Jp_;
  std::vector<std::size_t> term_start_, term_j_, term_y_, column_;
  std::map<const double*, std::vector<double>> transposed_;  // transposed()
};

inline bool node_picard::integral_term_by_variation(const chebyshev_basis<double>& b, const double* Jn,
                                                    const double* rn, const double* Pn, std::size_t D, double hl,
                                                    std::vector<double>& Y) {
  if (D == 3) return variation_kernel<3>(b, Jn, rn, Pn, D, hl, Y);
  if (D == 7) return variation_kernel<7>(b, Jn, rn, Pn, D, hl, Y);
  return variation_kernel<0>(b, Jn, rn, Pn, D, hl, Y);
}

template <std::size_t N>
bool node_picard::variation_kernel(const chebyshev_basis<double>& b, const double* Jn, const double* rn,
                                   const double* Pn, std::size_t dimension, double hl, std::vector<double>& Y) {
  const std::size_t D = N > 0 ? N : dimension, m = b.nodes.size(), DD = D * D, P = (m + 7) / 8 * 8;
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
    if (!solve_in_place<N>(lu_.data(), g, D)) return false;
  }
  // w = S g (the integral from -1 at each node), w_li = sum_k S_lk g_ki from k = 0 up and from 0.0
  // (the sweep's sums; g is fixed, so all nodes at once): eight nodes side by side, through S's
  // transpose. Then u = Phi w.
  const double* ST = transposed(b.integral, m).data();
  acc_.resize(D * P);  // w_li at [i P + l]
  for (std::size_t i = 0; i < D; ++i)
    for (std::size_t l0 = 0; l0 < P; l0 += 8) strided_sums<8>(F_.data() + i, D, ST + l0, P, m, acc_.data() + i * P + l0);
  Y.assign(m * D, 0.0);
  bool finite = true;
  for (std::size_t l = 0; l < m; ++l)
    for (std::size_t i = 0; i < D; ++i) {
      double u = 0;
      for (std::size_t k = 0; k < D; ++k) u += Pn[l * DD + i * D + k] * acc_[k * P + l];
      finite = finite && std::isfinite(u);
      Y[l * D + i] = u;
    }
  return finite;
}

// M (m x m, row-major) transposed, its rows padded with zeros to a multiple of 8; built once per
// matrix (the bases' matrices live as long as the program).
inline const std::vector<double>& node_picard::transposed(const std::vector<double>& M, std::size_t m) {
  std::vector<double>& t = transposed_[M.data()];
  const std::size_t P = (m + 7) / 8 * 8;
  if (t.size() == m * P) return t;
  t.assign(m * P, 0.0);
  for (std::size_t r = 0; r < m; ++r)
    for (std::size_t c = 0; c < m; ++c) t[c * P + r] = M[r * m + c];
  return t;
}

inline slong node_picard::grid_coefficients(const chebyshev_basis<double>& b, const double* values,
                                            std::size_t stride, std::size_t count, std::vector<integer_poly>& out,
                                            slong bits) {
  const std::size_t m = b.nodes.size(), P = (m + 7) / 8 * 8;
  const double* CT = transposed(b.coeffs, m).data();  // CT[l P + k] = coeffs_kl
  c_.resize(count * P);
  double big = 0;
  for (std::size_t q = 0; q < count; ++q) {
    // c_k = sum_l coeffs_kl values_l from l = 0 up and from 0.0; eight k side by side (independent
    // sums, each in its own order).
    for (std::size_t k0 = 0; k0 < P; k0 += 8) strided_sums<8>(values + q, stride, CT + k0, P, m, c_.data() + q * P + k0);
    for (std::size_t k = 0; k < m; ++k) big = std::max(big, std::abs(c_[q * P + k]));
  }
  const slong e = big > 0 ? static_cast<slong>(std::ilogb(big)) + 1 - bits : 0;
  // trunc(c 2^-e): exact, as c 2^-e has at most 53 bits above the grid; below 2^bits (bits < 63), so
  // a cast truncates it. c 2^-e is ldexp's value whenever 2^-e is a (normal) double: both round once.
  const bool by_product = -e >= -1022 && -e <= 1023;
  const double scale = by_product ? std::ldexp(1.0, static_cast<int>(-e)) : 0.0;
  out.resize(count);
  for (std::size_t q = 0; q < count; ++q) {
    fmpz_poly_struct* p = out[q].p;
    fmpz_poly_fit_length(p, static_cast<slong>(m));
    for (std::size_t k = 0; k < m; ++k) {
      const double x = by_product ? c_[q * P + k] * scale : std::ldexp(c_[q * P + k], static_cast<int>(-e));
      if (std::abs(x) < 0x1p62)
        fmpz_set_si(p->coeffs + k, static_cast<slong>(x));
      else  // not a value of these iterations (they return false first); as before
        fmpz_set_d(p->coeffs + k, std::trunc(x));
    }
    _fmpz_poly_set_length(p, static_cast<slong>(m));
    _fmpz_poly_normalise(p);
  }
  return e;
}

// `terms` > 0 pads every product to that many terms with 0 x 0 (J's entry D^2 and Yc_'s column L,
// kept zero), which leaves each sum's bits as they are: a sum from +0.0 is never -0.0 in rounding
// to nearest, so adding +0.0 changes no value, infinite or NaN ones included.
inline void node_picard::flatten_entries(std::size_t D, const std::vector<std::size_t>& entries,
                                         const std::vector<std::vector<std::size_t>>& through, std::size_t terms) {
  const std::size_t L = entries.size();
  column_.assign(D * D, 0);
  for (std::size_t e = 0; e < L; ++e) column_[entries[e]] = e;
  diag_.resize(L);
  term_start_.assign(1, 0);
  term_j_.clear();
  term_y_.clear();
  for (std::size_t e = 0; e < L; ++e) {
    const std::size_t q = entries[e], i = q / D, j = q % D;
    diag_[e] = q % (D + 1) == 0 ? 1.0 : 0.0;
    for (const std::size_t k : through[q]) {  // Phi_kj is live: it has a column
      term_j_.push_back(i * D + k);
      term_y_.push_back(column_[k * D + j]);
    }
    for (std::size_t t = through[q].size(); t < terms; ++t) {
      term_j_.push_back(D * D);
      term_y_.push_back(L);
    }
    term_start_.push_back(term_j_.size());
  }
}

inline bool node_picard::variational_sweeps(const chebyshev_basis<double>& b, const double* Jn, std::size_t D,
                                            double hl, const std::vector<std::size_t>& entries,
                                            const std::vector<std::vector<std::size_t>>& through,
                                            std::vector<double>& Y) {
  // 3 x 3 with all of Phi live (every product of at most 3 terms): the registers' kernel, with J's
  // pattern known at compile time for the two common ones (Euler's equations' zero diagonal, and a
  // full J), else the products padded to 3 terms.
  const std::size_t m = b.nodes.size(), DD = D * D, L = entries.size();
  const bool small = D == 3 && L == 9;
  flatten_entries(D, entries, through, small ? 3 : 0);
  unsigned mask = 0;  // bit i D + k: J_ik != 0, that is k in through[i D + j] for every j
  if (small)
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t k : through[i * 3]) mask |= 1u << (i * 3 + k);
  bool ok = false;
  if (small && mask == 0x0ee)
    ok = variational_kernel<9, 0x0ee>(b, Jn, DD, hl);
  else if (small && mask == 0x1ff)
    ok = variational_kernel<9, 0x1ff>(b, Jn, DD, hl);
  else
    ok = small ? variational_kernel<9>(b, Jn, DD, hl) : variational_kernel<0>(b, Jn, DD, hl);
  const std::size_t stride = small ? 10 : (L + 7) / 8 * 8;
  Y.assign(m * DD, 0.0);  // the entries that are not live stay exactly zero
  for (std::size_t l = 0; l < m; ++l)
    for (std::size_t e = 0; e < L; ++e) Y[l * DD + entries[e]] = Yc_[l * stride + e];
  return ok;
}

inline bool node_picard::integral_term_sweeps(const chebyshev_basis<double>& b, const double* Jn, const double* rn,
                                              std::size_t D, double hl, std::vector<double>& Y) {
  if (D == 3) return integral_term_kernel<3>(b, Jn, rn, D, hl, Y);
  if (D == 7) return integral_term_kernel<7>(b, Jn, rn, D, hl, Y);
  return integral_term_kernel<0>(b, Jn, rn, D, hl, Y);
}

// Until the largest change is below 1e-13 of the largest entry (twelve digits: what the nodes
// resolve), at most 400 sweeps. Only the live entries are iterated (the rest of Phi is exactly
// zero). N = 9: a 3 x 3 Phi, all live, the rows padded to 10 (the sums in five pairs of
// registers), J's pattern Mask (bit i 3 + k: J_ik != 0) or, Mask = 0, each product padded to 3
// terms (flatten_entries); N = 0: any count, the sums in chunks of 8.
template <std::size_t N, unsigned Mask>
bool node_picard::variational_kernel(const chebyshev_basis<double>& b, const double* Jn, std::size_t DD, double hl) {
  const std::size_t m = b.nodes.size(), L = N > 0 ? N : diag_.size(), stride = N > 0 ? N + 1 : (L + 7) / 8 * 8;
  Yc_.assign(m * stride, 0.0);
  F_.assign(m * stride, 0.0);
  for (std::size_t l = 0; l < m; ++l) std::copy(diag_.begin(), diag_.end(), Yc_.begin() + static_cast<std::ptrdiff_t>(l * stride));
  if constexpr (N > 0 && Mask == 0) {  // J with a zero after each node's entries, for the padding's terms
    Jp_.assign(m * (DD + 1), 0.0);
    for (std::size_t l = 0; l < m; ++l) std::copy(Jn + l * DD, Jn + (l + 1) * DD, Jp_.begin() + static_cast<std::ptrdiff_t>(l * (DD + 1)));
  }
  const double* diag = diag_.data();
  const double* J = N > 0 && Mask == 0 ? Jp_.data() : Jn;  // J's rows: DD + 1 apart in Jp_, else DD
  const std::size_t Jstride = N > 0 && Mask == 0 ? DD + 1 : DD;
  double *Y = Yc_.data(), *F = F_.data();
  const std::size_t *start = term_start_.data(), *tj = term_j_.data(), *ty = term_y_.data();
  const auto product_at = [&](std::size_t l) {
    products_at<N, Mask>(J + l * Jstride, Y + l * stride, F + l * stride, L, start, tj, ty);
  };
  for (std::size_t l = 0; l < m; ++l) product_at(l);
  for (int sweep = 0; sweep < 400; ++sweep) {
    double change = 0, size = 0;
    const auto finish = [&](std::size_t l, const double* acc) {
      double* Yl = Yc_.data() + l * stride;
      for (std::size_t e = 0; e < L; ++e) {
        const double next = diag[e] + hl * acc[e];
        change = std::max(change, std::abs(next - Yl[e]));
        size = std::max(size, std::abs(next));
        Yl[e] = next;
      }
      product_at(l);
    };
    if constexpr (N > 0)
      chunked_sweep<N + 1>(b.integral.data(), F_.data(), m, stride, acc_, finish);
    else
      chunked_sweep<8>(b.integral.data(), F_.data(), m, stride, acc_, finish);
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

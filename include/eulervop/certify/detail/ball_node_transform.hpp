// The Chebyshev coefficients of a segment's polynomial from its node values, in balls, for the
// general path of --certify: the degree-N interpolant of the values at the Lobatto nodes
// s_j = -cos(j pi / N) has the coefficients
//   c_k = (2/N) sum_j'' v_j T_k(s_j),  T_k(s_j) = (-1)^k cos(k j pi / N),
// the sum's end terms halved, and c_0, c_N halved too (the same map as node_transform.hpp). The
// matrix is enclosed once. Since T_k(-s) = (-1)^k T_k(s) and the nodes are symmetric, the columns
// j and N - j differ by (-1)^k: even coefficients take the sums v_j + v_{N-j}, odd ones the
// differences, which halves the products. Each product of a row by the values is one of Arb's
// matrix products (exact integer dot products with one error bound).
#pragma once

#include <arb.h>
#include <arb_mat.h>
#include <flint/fmpq.h>

#include <cstddef>

namespace eulervop::detail {

class ball_node_transform {
 public:
  ball_node_transform(slong prec, std::size_t degree, std::size_t components);
  ~ball_node_transform();
  ball_node_transform(const ball_node_transform& o);
  ball_node_transform& operator=(const ball_node_transform&) = delete;

  std::size_t nodes() const { return n1_; }
  // The node values: entry (j, i) is component i at node j (exact balls).
  arb_ptr value(std::size_t j, std::size_t i) { return arb_mat_entry(values_, j, i); }
  // The coefficients from the values: entry (k, i) of `out` (n1 x components; its old entries
  // become scratch).
  void apply(arb_mat_t out);

 private:
  void allocate();  // the matrices, of the sizes above
  void fold();

  slong prec_;
  std::size_t N_, n1_, D_, half_, even_, odd_;
  arb_mat_t values_;
  arb_mat_t M_even_, M_odd_;     // rows k = 0, 2, ... and k = 1, 3, ...; columns j < (N + 2) / 2
  arb_mat_t plus_, minus_;        // folded values
  arb_mat_t c_even_, c_odd_;
};

inline void ball_node_transform::allocate() {
  const auto rows = [](std::size_t n) { return static_cast<slong>(n); };
  arb_mat_init(values_, rows(n1_), rows(D_));
  arb_mat_init(M_even_, rows(even_), rows(half_));
  arb_mat_init(M_odd_, rows(odd_), rows(half_));
  arb_mat_init(plus_, rows(half_), rows(D_));
  arb_mat_init(minus_, rows(half_), rows(D_));
  arb_mat_init(c_even_, rows(even_), rows(D_));
  arb_mat_init(c_odd_, rows(odd_), rows(D_));
}

inline ball_node_transform::ball_node_transform(slong prec, std::size_t degree, std::size_t components)
    : prec_(prec), N_(degree), n1_(degree + 1), D_(components), half_((degree + 2) / 2), even_((degree + 2) / 2),
      odd_((degree + 1) / 2) {
  allocate();
  // cos(pi m / N) for m = 0 .. 2N - 1, enclosed once (m = k j reduced modulo 2N below).
  arb_ptr cosines = _arb_vec_init(static_cast<slong>(2 * N_));
  fmpq_t angle;
  fmpq_init(angle);
  for (std::size_t m = 0; m < 2 * N_; ++m) {
    fmpq_set_si(angle, static_cast<slong>(m), static_cast<ulong>(N_));
    arb_cos_pi_fmpq(cosines + m, angle, prec_);
  }
  fmpq_clear(angle);
  arb_t w;
  arb_init(w);
  for (std::size_t k = 0; k < n1_; ++k)
    for (std::size_t j = 0; j < half_; ++j) {
      // (-1)^k cos(pi k j / N) 2 / N
      arb_set(w, cosines + (k * j) % (2 * N_));
      if (k % 2) arb_neg(w, w);
      arb_mul_2exp_si(w, w, 1);
      arb_div_ui(w, w, static_cast<ulong>(N_), prec_);
      // The end columns j = 0 and N (folded together) and the rows k = 0 and N are halved.
      if (j == 0) arb_mul_2exp_si(w, w, -1);
      if (k == 0 || k == N_) arb_mul_2exp_si(w, w, -1);
      arb_set(arb_mat_entry(k % 2 ? M_odd_ : M_even_, static_cast<slong>(k / 2), static_cast<slong>(j)), w);
    }
  arb_clear(w);
  _arb_vec_clear(cosines, static_cast<slong>(2 * N_));
}

inline ball_node_transform::~ball_node_transform() {
  arb_mat_clear(values_);
  arb_mat_clear(M_even_);
  arb_mat_clear(M_odd_);
  arb_mat_clear(plus_);
  arb_mat_clear(minus_);
  arb_mat_clear(c_even_);
  arb_mat_clear(c_odd_);
}

inline ball_node_transform::ball_node_transform(const ball_node_transform& o)
    : prec_(o.prec_), N_(o.N_), n1_(o.n1_), D_(o.D_), half_(o.half_), even_(o.even_), odd_(o.odd_) {
  allocate();
  arb_mat_set(M_even_, o.M_even_);
  arb_mat_set(M_odd_, o.M_odd_);
}

// The sums and differences of mirrored values (the middle node, N even, is its own mirror: once).
inline void ball_node_transform::fold() {
  for (std::size_t j = 0; j < half_; ++j)
    for (std::size_t i = 0; i < D_; ++i) {
      const slong J = static_cast<slong>(j), I = static_cast<slong>(i), mirror = static_cast<slong>(N_ - j);
      if (2 * j == N_) {
        arb_set(arb_mat_entry(plus_, J, I), arb_mat_entry(values_, J, I));
        arb_set(arb_mat_entry(minus_, J, I), arb_mat_entry(values_, J, I));
      } else {
        arb_add(arb_mat_entry(plus_, J, I), arb_mat_entry(values_, J, I), arb_mat_entry(values_, mirror, I), prec_);
        arb_sub(arb_mat_entry(minus_, J, I), arb_mat_entry(values_, J, I), arb_mat_entry(values_, mirror, I), prec_);
      }
    }
}

inline void ball_node_transform::apply(arb_mat_t out) {
  fold();
  arb_mat_mul(c_even_, M_even_, plus_, prec_);
  if (odd_ > 0) arb_mat_mul(c_odd_, M_odd_, minus_, prec_);
  // Swapped, not copied: the products overwrite c_even_ and c_odd_ on the next call, and the
  // numbers' storage (at the working precision, on the heap) goes round instead of being copied.
  for (std::size_t k = 0; k < n1_; ++k)
    for (std::size_t i = 0; i < D_; ++i)
      arb_swap(arb_mat_entry(out, static_cast<slong>(k), static_cast<slong>(i)),
               arb_mat_entry(k % 2 ? c_odd_ : c_even_, static_cast<slong>(k / 2), static_cast<slong>(i)));
}

}  // namespace eulervop::detail

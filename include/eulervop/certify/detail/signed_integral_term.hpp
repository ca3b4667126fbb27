// The signed integral term of a segment (docs/certified.md, "How", step 3):
//   u(b) = int_a^b Phi(b, s) J(s) r(s) ds,
// which solves u = hl int J (u + r) (s from -1). It is computed in double by variation of
// constants on 2N + 2 Lobatto nodes (degree 2N + 1, like r), u(s) = Phi(s) int Phi^-1 hl J r with
// the variational matrix's polynomial as Phi, then bounded: with
// R_u = hl int J (u_num + r) - u_num, E = u - u_num solves E = R_u + hl int J E, so
// |E(1)| <= sup|R_u| (1 + h exp(mu h) |J|). u_num(1) joins r(1) as a signed vector; only |E(1)|
// is a ball. It is about ten times r(1) where a segment spans a good part of a rotation, so
// bounding it by norms would dominate the whole bound.
#pragma once

#include <eulervop/certify/detail/bounded_chebyshev.hpp>
#include <eulervop/certify/detail/linearized_flow.hpp>
#include <eulervop/certify/detail/picard_residual.hpp>
#include <eulervop/certify/detail/real.hpp>
#include <eulervop/certify/detail/segment_polynomial.hpp>
#include <eulervop/certify/detail/variational_matrix.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/reference/detail/chebyshev_basis.hpp>

#include <mpfi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <memory>
#include <vector>

namespace eulervop::detail {

// The nodes of the integral term (degree 2N + 1, a segment's reference of degree N), shared by
// every segment's check. The nodes come in pairs s_(M-l) = -s_l (n = 2N + 2 is even), where
// T_k(-s) = (-1)^k T_k(s): values from coefficients are the even and odd parts' sum and
// difference, and coefficients from values sums and differences of mirrored values, each half the
// products. The matrices are stored column by column, so that their products are sums of columns,
// which the compiler vectorizes (a dot product in double is not, its order of summation fixed).
struct integral_term_nodes {
  explicit integral_term_nodes(std::size_t degree);
  std::size_t n, h;              // 2N + 2 nodes and coefficients; h = n / 2
  std::vector<double> T;         // T_k(s_l) at k h + l, l < h
  std::vector<double> S;         // the integral from -1 (chebyshev_basis::integral), (l, k) at k n + l
  std::vector<double> even, odd; // values -> coefficients (chebyshev_basis::coeffs): (2m, l) and
                                 // (2m + 1, l) at l h + m, l < h
};

inline integral_term_nodes::integral_term_nodes(std::size_t degree)
    : n(2 * degree + 2), h(degree + 1), T(n * h), S(n * n), even(h * h), odd(h * h) {
  const std::size_t M = n - 1;
  const double pi = 3.14159265358979323846;
  // s_l = -cos(l pi / M), so T_k(s_l) = (-1)^k cos(k l pi / M), the angle reduced modulo 2M.
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t l = 0; l < h; ++l) {
      const double c = std::cos(pi * static_cast<double>((k * l) % (2 * M)) / static_cast<double>(M));
      T[k * h + l] = (k % 2) ? -c : c;
    }
  const chebyshev_basis<double> basis(M);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) S[j * n + i] = basis.integral[i * n + j];
  for (std::size_t m = 0; m < h; ++m)
    for (std::size_t l = 0; l < h; ++l) {
      even[l * h + m] = basis.coeffs[(2 * m) * n + l];
      odd[l * h + m] = basis.coeffs[(2 * m + 1) * n + l];
    }
}

class signed_integral_term {
 public:
  explicit signed_integral_term(std::shared_ptr<const integral_term_nodes> nodes)
      : u1(3, interval::zero(error_bits)), eps(interval::zero(error_bits)), nodes_(std::move(nodes)), nr_(nodes_->n),
        ud_(3 * nr_), w_(3 * nr_), y_(3 * nr_), Phi_(9 * nr_), g_(3 * nr_), G_(3 * nr_), fold_(nr_),
        scratch_(interval::zero(error_bits)) {}

  // `phi`: the segment's variational matrix, computed.
  void compute(const segment_polynomial& P, const picard_residual& r, const variational_matrix& phi,
               const jacobian_rows& rows, const linear_growth& g, integrated_products& sums);

  std::vector<interval> u1;  // u_num(1), signed
  interval eps;              // |u(b) - u_num(1)|_2 <= eps

 private:
  void shorten(const segment_polynomial& P);
  void J_times(const segment_polynomial& P, const jacobian_rows& rows, int i, const double* w,
               const std::array<double, 3>& wrad, double hl, integrated_products& sums) const;
  void solve(const segment_polynomial& P, const picard_residual& r, const variational_matrix& phi,
             const jacobian_rows& rows, double hl);
  void values_at_nodes(const double* c, std::size_t length, double* __restrict out);
  void coefficients_of_values(const double* v, double* __restrict out);
  double residual_sup(const segment_polynomial& P, const picard_residual& r, const jacobian_rows& rows, double hl,
                      integrated_products& sums);

  std::shared_ptr<const integral_term_nodes> nodes_;
  std::size_t nr_;
  std::array<std::size_t, 3> short_length_{};
  std::vector<double> ud_, w_;  // u_num (3 x nr), u_num + r
  // At the nodes (component at i nr + l): P, Phi (entry q at q nr + l), Phi^-1 hl J r, its integral.
  std::vector<double> y_, Phi_, g_, G_;
  std::vector<double> fold_;  // even and odd parts (values), or sums (coefficients)
  interval scratch_;
};

inline void signed_integral_term::compute(const segment_polynomial& P, const picard_residual& r,
                                          const variational_matrix& phi, const jacobian_rows& rows,
                                          const linear_growth& g, integrated_products& sums) {
  shorten(P);
  solve(P, r, phi, rows, g.hl);
  sums.hl_error = g.hl_error;
  g.error_at_end(eps, residual_sup(P, r, rows, g.hl, sums), P);
  for (int i = 0; i < 3; ++i) {
    enclose_double_sum(u1[i], &ud_[i * nr_], nr_, scratch_);  // u_num(1) = sum_k u_k
    mpfi_mul_2si(u1[i].get(), u1[i].get(), -r.r_scale);  // back from r's scaling
  }
  mpfi_mul_2si(eps.get(), eps.get(), -r.r_scale);
}

// The solve needs u to a few digits only, so it drops P's coefficients below 1e-9 of the
// largest (the final residual uses them all).
inline void signed_integral_term::shorten(const segment_polynomial& P) {
  for (int c = 0; c < 3; ++c) {
    double big = 0;
    for (std::size_t k = 0; k < P.n1; ++k) big = std::max(big, std::abs(P.cd[c * P.n1 + k]));
    std::size_t n = P.n1;
    while (n > 1 && std::abs(P.cd[c * P.n1 + n - 1]) < 1e-9 * big) --n;
    short_length_[c] = n;
  }
}

// sums = hl int (J w)_i, w three series of nr_ coefficients within wrad of the exact ones.
inline void signed_integral_term::J_times(const segment_polynomial& P, const jacobian_rows& rows, int i,
                                          const double* w, const std::array<double, 3>& wrad, double hl,
                                          integrated_products& sums) const {
  std::array<product_term, 2> terms;
  for (int t = 0; t < 2; ++t) {
    const jacobian_entry& e = rows[i][t];
    terms[t] = {e.coefficient, P.short_view(e.c),
                {&w[e.k * nr_], nr_, wrad[e.k]}};
  }
  sums.compute(hl, terms);
}

// u = hl int J (u + r) is u' = hl J u + hl J r, u(-1) = 0, so u(s) = Phi(s) int_{-1}^s Phi^-1 hl J r
// with Phi' = hl J Phi, Phi(-1) = I: at the nodes, with Phi_num for Phi (ten digits) and S for the
// integral, then back to coefficients. Only a few digits matter (the residual bound covers the
// rest); one pass replaces a Picard iteration whose contraction is |J| h, a good part of one.
inline void signed_integral_term::solve(const segment_polynomial& P, const picard_residual& r,
                                        const variational_matrix& phi, const jacobian_rows& rows, double hl) {
  const std::size_t n = nr_;
  // Values at the nodes from coefficients: P (y_), r (w_), Phi_num (Phi_).
  for (int c = 0; c < 3; ++c) {
    values_at_nodes(&P.cd[c * P.n1], short_length_[c], &y_[c * n]);
    values_at_nodes(&r.rd[c * n], n, &w_[c * n]);
  }
  for (int q = 0; q < 9; ++q) values_at_nodes(phi.coefficients(q), variational_matrix::coefficient_count, &Phi_[q * n]);
  for (std::size_t l = 0; l < n; ++l) {
    double Jr[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i)
      for (const jacobian_entry& e : rows[i]) Jr[i] += e.coefficient * y_[e.c * n + l] * w_[e.k * n + l];
    // Phi^-1 (hl J r) by the adjugate.
    double Ph[9];
    for (int q = 0; q < 9; ++q) Ph[q] = Phi_[q * n + l];
    double A[9];
    const double scale = hl / adjugate_3x3(Ph, A);
    for (int i = 0; i < 3; ++i)
      g_[i * n + l] = scale * (A[3 * i] * Jr[0] + A[3 * i + 1] * Jr[1] + A[3 * i + 2] * Jr[2]);
  }
  // G = S g (the integrals at the nodes), then u = Phi G there (into w_), then u's coefficients.
  for (int i = 0; i < 3; ++i) {
    double* __restrict out = &G_[i * n];
    const double* x = &g_[i * n];
    std::fill(out, out + n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      const double* __restrict Sk = &nodes_->S[k * n];
      for (std::size_t l = 0; l < n; ++l) out[l] += x[k] * Sk[l];
    }
  }
  for (int i = 0; i < 3; ++i)
    for (std::size_t l = 0; l < n; ++l) {
      double acc = 0;
      for (int j = 0; j < 3; ++j) acc += Phi_[(i * 3 + j) * n + l] * G_[j * n + l];
      w_[i * n + l] = acc;
    }
  for (int i = 0; i < 3; ++i) coefficients_of_values(&w_[i * n], &ud_[i * n]);
  for (double x : ud_)
    if (!std::isfinite(x)) P.fail(outcome_kind::certify_non_finite);
}

// out (at the nr_ nodes) from `length` Chebyshev coefficients c: the even and odd parts on half
// the nodes, then their sum and difference.
inline void signed_integral_term::values_at_nodes(const double* c, std::size_t length, double* __restrict out) {
  const std::size_t n = nr_, h = nodes_->h;
  double* __restrict e = fold_.data();
  double* __restrict o = fold_.data() + h;
  std::fill(fold_.begin(), fold_.end(), 0.0);
  for (std::size_t k = 0; k < length; ++k) {
    const double* __restrict Tk = &nodes_->T[k * h];
    double* __restrict part = (k % 2) ? o : e;
    for (std::size_t l = 0; l < h; ++l) part[l] += c[k] * Tk[l];
  }
  for (std::size_t l = 0; l < h; ++l) {
    out[l] = e[l] + o[l];
    out[n - 1 - l] = e[l] - o[l];
  }
}

// nr_ Chebyshev coefficients (out) from the values v at the nodes: sums and differences of
// mirrored values, each half the products.
inline void signed_integral_term::coefficients_of_values(const double* v, double* __restrict out) {
  const std::size_t n = nr_, h = nodes_->h;
  double* __restrict e = fold_.data();
  double* __restrict o = fold_.data() + h;
  std::fill(fold_.begin(), fold_.end(), 0.0);
  for (std::size_t l = 0; l < h; ++l) {
    const double plus = v[l] + v[n - 1 - l], minus = v[l] - v[n - 1 - l];
    const double* __restrict ce = &nodes_->even[l * h];
    const double* __restrict co = &nodes_->odd[l * h];
    for (std::size_t m = 0; m < h; ++m) {
      e[m] += plus * ce[m];
      o[m] += minus * co[m];
    }
  }
  for (std::size_t m = 0; m < h; ++m) {
    out[2 * m] = e[m];
    out[2 * m + 1] = o[m];
  }
}

// The residual of the exact polynomials: u_num exact, r = rd + (its radius); u_num + r as a view,
// the sum rounded, its error in the radius.
inline double signed_integral_term::residual_sup(const segment_polynomial& P, const picard_residual& r,
                                                 const jacobian_rows& rows, double hl, integrated_products& sums) {
  for (std::size_t q = 0; q < 3 * nr_; ++q) w_[q] = ud_[q] + r.rd[q];
  double sup2 = 0;
  for (int i = 0; i < 3; ++i) {
    std::array<double, 3> rad;
    for (int k = 0; k < 3; ++k)
      rad[k] = r.rrad[k] + gamma_of(2) * (abs_sum(&ud_[k * nr_], nr_) + abs_sum(&r.rd[k * nr_], nr_));
    J_times(P, rows, i, w_.data(), rad, hl, sums);
    const double b = residual_bound(0.0, sums, {&ud_[i * nr_], nr_, 0.0});
    sup2 += b * b;
  }
  return std::sqrt(sup2) * (1 + 1e-12);
}

}  // namespace eulervop::detail

// The linear parts of a segment's error for the general path of --certify (docs/certified.md,
// "The general path", steps 3 and 4), on s in [-1, 1] with tau = a + hl (s + 1):
//   - the variational matrix Phi' = hl J Phi, Phi(-1) = I;
//   - the signed integral term u' = hl J (u + r), u(-1) = 0, r the Picard residual, so that
//     u(tau) = int_a^tau Phi(tau, s) J(s) r(s) ds.
// Each is computed in double by Picard iteration on Lobatto nodes, where no rounding matters:
// the result is a polynomial with exact coefficients (Phi_num, u_num, on a binary grid), which
// defines it. What is proven is the distance to the exact solution, from the residual of that
// polynomial:
//   R = I + hl int J Phi_num - Phi_num, and E = Phi - Phi_num solves E = R + hl int J E, so
//   |E(tau)| <= sup|R| (1 + dt exp(mu dt) |J|), dt = tau - a (variation of constants);
// the same for u with rho = hl int J (u_num + r) - u_num. Both only need a few digits (Phi's error
// multiplies |e(a)|, u's is relative to u), so the Jacobian enters with its smallest coefficients
// moved into the models' remainders (chebyshev_model.hpp), and every product of the residuals is
// exact in integers on binary grids: the Jacobian's entries on one grid, Phi_num's (or u_num + r)
// on another, so that the sums over k of J_ik Phi_kj are exact too; the only approximation is each
// Jacobian coefficient's move to its grid, which enters its remainder.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/short_integer_series.hpp>
#include <eulervop/reference/detail/chebyshev_basis.hpp>

#include <arb.h>
#include <flint/fmpz_poly.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace eulervop::detail {

// Models on one common binary grid 2^e: integer polynomials, each with a remainder (its move to
// the grid and its own remainder) and the sum of its magnitudes.
class grid_models {
 public:
  explicit grid_models(std::size_t count) : n_(count), rem_(count), mag_(count) {}

  // The models `m` on the grid `bits` bits below their largest coefficient.
  void load(const std::vector<chebyshev_model>& m, slong bits) {
    slong top = WORD_MIN;
    for (const chebyshev_model& x : m)
      if (!x.is_zero()) top = std::max(top, grid_exponent(x, 0));
    e_ = top == WORD_MIN ? 0 : top - bits;
    for (std::size_t q = 0; q < m.size(); ++q) {
      to_grid(n_[q].p, rem_[q].m, m[q], e_);
      mag_add(rem_[q].m, rem_[q].m, m[q].remainder());
      grid_magnitude(mag_[q].m, n_[q].p, e_);
    }
    short_.resize(m.size());
    short_ok_ = true;
    short_bits_ = 0;
    short_len_ = 0;
    for (std::size_t q = 0; q < m.size() && short_ok_; ++q) {
      short_ok_ = short_[q].load(n_[q].p);
      short_bits_ = std::max(short_bits_, short_[q].bits);
      short_len_ = std::max(short_len_, short_[q].c.size());
    }
  }

  slong exponent() const { return e_; }
  // The models as short_integer_series (short_integer_series.hpp), where all fit 62 bits.
  bool short_form() const { return short_ok_; }
  const short_integer_series& short_series(std::size_t q) const { return short_[q]; }
  unsigned short_bits() const { return short_bits_; }
  std::size_t short_length() const { return short_len_; }
  const fmpz_poly_struct* poly(std::size_t q) const { return n_[q].p; }
  fmpz_poly_struct* poly(std::size_t q) { return n_[q].p; }
  const mag_value& remainder(std::size_t q) const { return rem_[q]; }
  const mag_value& magnitude(std::size_t q) const { return mag_[q]; }
  std::size_t length() const {  // the longest polynomial's
    std::size_t n = 0;
    for (const integer_poly& x : n_) n = std::max(n, static_cast<std::size_t>(x.p->length));
    return n;
  }
  bool zero(std::size_t q) const { return n_[q].p->length == 0 && mag_is_zero(rem_[q].m); }

 private:
  std::vector<integer_poly> n_;
  std::vector<mag_value> rem_, mag_;
  slong e_ = 0;
  std::vector<short_integer_series> short_;
  bool short_ok_ = false;
  unsigned short_bits_ = 0;
  std::size_t short_len_ = 0;
};

class ball_linear_flow {
 public:
  // `prec`: the precision of the values given to the rows.
  ball_linear_flow(std::size_t dimension, slong prec)
      : D_(dimension), prec_(prec), J_(dimension * dimension), Ju_(dimension * dimension) {}

  // The Jacobian's models (D x D, row-major; an empty model is 0) and the weights of the norm
  // (powers of two): W J W^-1 on the grids of the two residuals, and as doubles for the iterations.
  void load_jacobian(std::vector<chebyshev_model> J, const std::vector<double>& weight);
  // Phi_num on nodes chosen for |J| h (jh), and the bound of its residual in the weighted norm
  // (|W R W^-1|, weights powers of two). false when the iteration does not converge to a finite
  // value.
  bool variational(const ball& hl, double jh);
  // u_num for the residual r (D models), and the bound of its residual (|W rho|).
  bool integral_term(const std::vector<chebyshev_model>& r, const ball& hl);

  // Phi_num(s) (D x D) and u_num(s) (D) at s in [-1, 1], in balls, from the values T_k(s) (at
  // least max_length() of them).
  void Phi_at(const chebyshev_values& T, std::vector<ball>& out) const;
  void u_at(const chebyshev_values& T, std::vector<ball>& out) const;
  slong max_length() const {
    slong n = 0;
    for (const chebyshev_model& m : phi_) n = std::max(n, m.length());
    for (const chebyshev_model& m : u_) n = std::max(n, m.length());
    return n;
  }

  const std::vector<ball>& Phi1() const { return Phi1_; }  // Phi_num(1)
  const std::vector<ball>& u1() const { return u1_; }      // u_num(1)
  const mag_struct* phi_residual() const { return phi_res_.m; }  // >= sup |W R W^-1|_2
  const mag_struct* u_residual() const { return u_res_.m; }      // >= sup |W rho|_2

  ball_linear_flow(const ball_linear_flow&) = delete;
  ball_linear_flow& operator=(const ball_linear_flow&) = delete;

 private:
  // The Jacobian's smallest coefficients enter the remainder: below 2^-36 of its largest entry
  // for Phi (whose error is then about 1e-11, multiplied by |e(a)|), below 2^-30 for u (a few
  // digits of a term far below the state's error).
  static constexpr int phi_cut = 36, u_cut = 30;
  // The grids of the residuals' products: 56 bits below the largest coefficient (exact products
  // of two limbs).
  static constexpr slong grid_bits = 56;
  // The residuals' integrals and sums: a bound needs no more.
  static constexpr slong residual_prec = 64;

  // The bases of a few node counts, built once per process and shared by every check (each costs
  // O(n^3) to build).
  static const chebyshev_basis<double>& basis(std::size_t nodes) {
    static std::mutex mutex;
    static std::map<std::size_t, std::unique_ptr<const chebyshev_basis<double>>> bases;
    const std::lock_guard<std::mutex> lock(mutex);
    auto& b = bases[nodes];
    if (!b) b = std::make_unique<const chebyshev_basis<double>>(nodes - 1);
    return *b;
  }
  void chebyshev_at_nodes(const chebyshev_basis<double>& b, std::size_t n);
  void series_at_nodes(const std::vector<double>& c, std::size_t m, double* out, std::size_t stride) const;
  void jacobian_at_nodes(const chebyshev_basis<double>& b, std::vector<double>& Jn);
  // The coefficients of the values at the nodes (stride apart), on the grid 2^e with `bits` bits
  // below their largest (e returned): the polynomial they define, exactly.
  slong grid_coefficients(const chebyshev_basis<double>& b, const double* values, std::size_t stride,
                          std::size_t count, std::vector<integer_poly>& out, slong bits, long scale_exp);
  // sup |2^e hl int S - Q + delta| bounds, for the residuals (S = sum n_k T_k on the grid 2^e
  // with the remainder `rem`; Q exact or with its own remainder; delta the identity or 0).
  template <class Sums>
  static void residual_sup(mag_t out, const Sums& sum, const std::vector<ball>& factors, const mag_t rem,
                           const ball& hl, const chebyshev_model& subtract, int identity, slong prec);

  std::size_t D_;
  slong prec_;
  grid_models J_, Ju_;
  std::vector<std::vector<double>> Jd_;  // the Jacobian's midpoints as doubles
  std::vector<chebyshev_model> phi_, u_;  // Phi_num (D x D) and u_num (D, unscaled), exact
  std::vector<integer_poly> phi_grid_, u_grid_;
  slong phi_e_ = 0, u_e_ = 0;
  std::vector<int> w_;  // log2 of the weights
  long u_exp_ = 0;  // u and r scaled by 2^u_exp_ in the iteration
  std::vector<ball> Phi1_, u1_;
  mag_value phi_res_, u_res_;
  std::vector<double> Jn_, Y_, F_, Tn_;
};

inline void ball_linear_flow::load_jacobian(std::vector<chebyshev_model> Jc, const std::vector<double>& weight) {
  // Everything below works on W J W^-1, W Phi W^-1 and W u (exact shifts): each entry's grid and
  // accuracy then follow its weight in the norm the residuals are bounded in.
  w_.resize(D_);
  for (std::size_t i = 0; i < D_; ++i) w_[i] = std::ilogb(weight[i]);
  for (std::size_t i = 0; i < D_; ++i)
    for (std::size_t k = 0; k < D_; ++k) {
      chebyshev_model& m = Jc[i * D_ + k];
      const int shift = w_[i] - w_[k];
      if (shift == 0) continue;
      for (slong c = 0; c < m.length(); ++c) arb_mul_2exp_si(m.coeff(c), m.coeff(c), shift);
      mag_mul_2exp_si(m.remainder(), m.remainder(), shift);
    }
  mag_value scale, cut, s;
  for (const chebyshev_model& m : Jc) {
    sup_bound(s.m, m);
    mag_max(scale.m, scale.m, s.m);
  }
  mag_mul_2exp_si(cut.m, scale.m, -phi_cut);
  for (chebyshev_model& m : Jc) truncate_below(m, cut.m);
  J_.load(Jc, grid_bits);
  Jd_.assign(Jc.size(), {});
  for (std::size_t q = 0; q < Jc.size(); ++q) {
    Jd_[q].resize(static_cast<std::size_t>(Jc[q].length()));
    for (slong k = 0; k < Jc[q].length(); ++k) Jd_[q][k] = arf_get_d(arb_midref(Jc[q].coeff(k)), ARF_RND_NEAR);
  }
  mag_mul_2exp_si(cut.m, scale.m, -u_cut);
  for (chebyshev_model& m : Jc) truncate_below(m, cut.m);
  Ju_.load(Jc, grid_bits);
}

// Jn[l * D^2 + q] = J_q at node l.
// T_k at the nodes for k < n, by the recurrence run across all nodes at once (Tn_[k m + l]).
inline void ball_linear_flow::chebyshev_at_nodes(const chebyshev_basis<double>& b, std::size_t n) {
  const std::size_t m = b.nodes.size();
  Tn_.resize(std::max<std::size_t>(n, 2) * m);
  for (std::size_t l = 0; l < m; ++l) {
    Tn_[l] = 1;
    Tn_[m + l] = b.nodes[l];
  }
  for (std::size_t k = 2; k < n; ++k)
    for (std::size_t l = 0; l < m; ++l) Tn_[k * m + l] = 2 * b.nodes[l] * Tn_[(k - 1) * m + l] - Tn_[(k - 2) * m + l];
}

// sum_k c_k T_k at the nodes, into out[l * stride] (Tn_ holds at least c's length).
inline void ball_linear_flow::series_at_nodes(const std::vector<double>& c, std::size_t m, double* out,
                                              std::size_t stride) const {
  thread_local std::vector<double> v;
  v.assign(m, 0.0);
  for (std::size_t k = 0; k < c.size(); ++k) {
    const double ck = c[k];
    const double* T = Tn_.data() + k * m;
    for (std::size_t l = 0; l < m; ++l) v[l] += ck * T[l];
  }
  for (std::size_t l = 0; l < m; ++l) out[l * stride] = v[l];
}

// Jn[l * D^2 + q] = J_q at node l.
inline void ball_linear_flow::jacobian_at_nodes(const chebyshev_basis<double>& b, std::vector<double>& Jn) {
  const std::size_t m = b.nodes.size(), DD = D_ * D_;
  std::size_t n = 0;
  for (const std::vector<double>& c : Jd_) n = std::max(n, c.size());
  chebyshev_at_nodes(b, n);
  Jn.assign(m * DD, 0.0);
  for (std::size_t q = 0; q < DD; ++q)
    if (!Jd_[q].empty()) series_at_nodes(Jd_[q], m, Jn.data() + q, DD);
}

inline slong ball_linear_flow::grid_coefficients(const chebyshev_basis<double>& b, const double* values, std::size_t stride,
                                                 std::size_t count, std::vector<integer_poly>& out, slong bits,
                                                 long scale_exp) {
  const std::size_t m = b.nodes.size();
  std::vector<double> c(count * m);
  double big = 0;
  for (std::size_t q = 0; q < count; ++q)
    for (std::size_t k = 0; k < m; ++k) {
      double acc = 0;
      for (std::size_t l = 0; l < m; ++l) acc += b.coeffs[k * m + l] * values[l * stride + q];
      c[q * m + k] = acc;
      big = std::max(big, std::abs(acc));
    }
  const slong e = big > 0 ? static_cast<slong>(std::ilogb(big)) + 1 - bits : 0;
  out.resize(count);
  fmpz_t n;
  fmpz_init(n);
  for (std::size_t q = 0; q < count; ++q) {
    fmpz_poly_zero(out[q].p);
    for (std::size_t k = 0; k < m; ++k) {
      // trunc(c 2^-e): exact, as c 2^-e has at most 53 significant bits above the grid.
      fmpz_set_d(n, std::trunc(std::ldexp(c[q * m + k], static_cast<int>(-e))));
      fmpz_poly_set_coeff_fmpz(out[q].p, static_cast<slong>(k), n);
    }
  }
  fmpz_clear(n);
  return e - scale_exp;
}

// The sums of products behind a residual, as the integral needs them: their length and the
// differences S_{k-1} - S_{k+1} (2 S_0 - S_2 for k = 1), exactly. Either FLINT's integers or the
// 128-bit sums of short_integer_series.hpp.
struct flint_sums {
  const fmpz_poly_struct* p;
  slong length() const { return p->length; }
  void difference(arf_t out, slong k) const {
    fmpz_t d;
    fmpz_init(d);
    const auto S = [&](slong i) -> const fmpz* { return i < p->length ? p->coeffs + i : nullptr; };
    if (k == 1) {
      fmpz_mul_2exp(d, S(0), 1);
      if (S(2)) fmpz_sub(d, d, S(2));
    } else {
      fmpz_set(d, S(k - 1));
      if (S(k + 1)) fmpz_sub(d, d, S(k + 1));
    }
    arf_set_fmpz(out, d);
    fmpz_clear(d);
  }
};
struct wide_sums {
  const std::vector<wide_int>* s;
  slong length() const {
    slong n = static_cast<slong>(s->size());
    while (n > 0 && (*s)[static_cast<std::size_t>(n - 1)] == 0) --n;
    return n;
  }
  void difference(arf_t out, slong k) const {
    const auto S = [&](slong i) -> wide_int { return i < static_cast<slong>(s->size()) ? (*s)[static_cast<std::size_t>(i)] : 0; };
    set_wide(out, k == 1 ? 2 * S(0) - S(2) : S(k - 1) - S(k + 1));
  }
};

// hl 2^e / (2k) for k = 1 .. n, the integral's factors (in balls at `prec`).
inline void integral_factors(std::vector<ball>& out, slong n, const ball& hl, slong e, slong prec) {
  out.resize(static_cast<std::size_t>(std::max<slong>(n, 0)) + 1);
  for (slong k = 1; k <= n; ++k) {
    arb_mul_2exp_si(out[static_cast<std::size_t>(k)].get(), hl.get(), e - 1);
    arb_div_ui(out[static_cast<std::size_t>(k)].get(), out[static_cast<std::size_t>(k)].get(), static_cast<ulong>(k), prec);
  }
}

// The integral and the difference in one pass over the sums' integer coefficients S_k (in units
// of 2^e): int_{-1}^s sum S_k T_k has the coefficients b_1 = S_0 - S_2 / 2, b_k = (S_{k-1} -
// S_{k+1}) / (2k) for k >= 2, and b_0 = sum_{k>=1} (-1)^(k+1) b_k, so that it vanishes at -1
// (integrate() in chebyshev_model.hpp); each difference is exact in integers, then multiplied by
// its factor hl 2^e / (2k) (`factors`, integral_factors(), at least the sums' length of them).
template <class Sums>
void ball_linear_flow::residual_sup(mag_t out, const Sums& sum, const std::vector<ball>& factors, const mag_t rem,
                                    const ball& hl, const chebyshev_model& subtract, int identity, slong prec) {
  const slong n = sum.length();
  ball b, c0;
  mag_t m;
  mag_init(m);
  mag_zero(out);
  for (slong k = 1; k <= n; ++k) {
    sum.difference(arb_midref(b.get()), k);
    mag_zero(arb_radref(b.get()));
    arb_mul(b.get(), b.get(), factors[static_cast<std::size_t>(k)].get(), prec);
    if (k % 2)
      arb_add(c0.get(), c0.get(), b.get(), prec);
    else
      arb_sub(c0.get(), c0.get(), b.get(), prec);
    if (k < subtract.length()) arb_sub(b.get(), b.get(), subtract.coeff(k), prec);
    arb_get_mag(m, b.get());
    mag_add(out, out, m);
  }
  if (identity) arb_add_ui(c0.get(), c0.get(), 1, prec);
  if (subtract.length() > 0) arb_sub(c0.get(), c0.get(), subtract.coeff(0), prec);
  arb_get_mag(m, c0.get());
  mag_add(out, out, m);
  for (slong k = n + 1; k < subtract.length(); ++k) {
    arb_get_mag(m, subtract.coeff(k));
    mag_add(out, out, m);
  }
  // The product's remainder integrates to at most 2 |hl| rem.
  arb_get_mag(m, hl.get());
  mag_mul(m, m, rem);
  mag_mul_2exp_si(m, m, 1);
  mag_add(out, out, m);
  mag_add(out, out, subtract.remainder());
  mag_clear(m);
}

// Sweeps over the nodes in order, each node's J Y updated as soon as its Y is (Gauss-Seidel): the
// integral is a Volterra operator, so this converges in a few sweeps where Jacobi's takes about
// e |J| h of them.
inline bool ball_linear_flow::variational(const ball& hl, double jh) {
  // Nodes for about twelve digits of Phi: a degree well above e |J| h / 2 (the Taylor bound of
  // the solution's coefficients; jh bounds |J| h by the Frobenius norm, which overestimates).
  const std::size_t m = jh <= 4.5 ? 15 : jh <= 6 ? 17 : jh <= 10 ? 25 : jh <= 16 ? 33 : jh <= 24 ? 49 : 65;
  const chebyshev_basis<double>& b = basis(m);
  const std::size_t DD = D_ * D_;
  const double hld = arf_get_d(arb_midref(hl.get()), ARF_RND_NEAR);
  jacobian_at_nodes(b, Jn_);
  // The entries of Phi that can be nonzero: the closure of the identity's under J's pattern
  // (Phi_ij = 0 throughout where no chain of nonzero J_ik leads from j to i); the iteration and
  // the products skip the rest, which stay exactly zero.
  std::vector<char> live(DD, 0);
  for (std::size_t i = 0; i < D_; ++i) live[i * D_ + i] = 1;
  for (bool grew = true; grew;) {
    grew = false;
    for (std::size_t i = 0; i < D_; ++i)
      for (std::size_t j = 0; j < D_; ++j)
        for (std::size_t k = 0; k < D_ && !live[i * D_ + j]; ++k)
          if (!Jd_[i * D_ + k].empty() && live[k * D_ + j]) live[i * D_ + j] = grew = true;
  }
  std::vector<std::size_t> entries;  // the live (i, j) as i * D + j
  std::vector<std::vector<std::size_t>> through(DD);  // for a live (i, j): the k with J_ik != 0, Phi_kj live
  for (std::size_t q = 0; q < DD; ++q) {
    if (!live[q]) continue;
    entries.push_back(q);
    const std::size_t i = q / D_, j = q % D_;
    for (std::size_t k = 0; k < D_; ++k)
      if (!Jd_[i * D_ + k].empty() && live[k * D_ + j]) through[q].push_back(k);
  }
  Y_.assign(m * DD, 0.0);
  F_.assign(m * DD, 0.0);
  for (std::size_t l = 0; l < m; ++l)
    for (std::size_t i = 0; i < D_; ++i) Y_[l * DD + i * D_ + i] = 1;
  const auto product_at = [&](std::size_t l) {
    const double* Jl = Jn_.data() + l * DD;
    const double* Yl = Y_.data() + l * DD;
    for (const std::size_t q : entries) {
      const std::size_t i = q / D_, j = q % D_;
      double acc = 0;
      for (const std::size_t k : through[q]) acc += Jl[i * D_ + k] * Yl[k * D_ + j];
      F_[l * DD + q] = acc;
    }
  };
  for (std::size_t l = 0; l < m; ++l) product_at(l);
  std::vector<double> acc(DD);
  for (int sweep = 0; sweep < 400; ++sweep) {
    double change = 0, size = 0;
    for (std::size_t l = 0; l < m; ++l) {
      std::fill(acc.begin(), acc.end(), 0.0);
      for (std::size_t k = 0; k < m; ++k) {
        const double sk = b.integral[l * m + k];
        const double* Fk = F_.data() + k * DD;
        for (std::size_t q = 0; q < DD; ++q) acc[q] += sk * Fk[q];
      }
      for (const std::size_t q : entries) {
        const double next = (q % (D_ + 1) == 0 ? 1.0 : 0.0) + hld * acc[q];
        change = std::max(change, std::abs(next - Y_[l * DD + q]));
        size = std::max(size, std::abs(next));
        Y_[l * DD + q] = next;
      }
      product_at(l);
    }
    if (!std::isfinite(change)) return false;
    if (change <= 1e-13 * size) break;
  }
  // Phi_num: the grid's polynomial, 40 bits below its largest coefficient (whatever polynomial we
  // take is exact; shorter ones cost less, and their residual is as small).
  phi_e_ = grid_coefficients(b, Y_.data(), DD, DD, phi_grid_, 40, 0);
  phi_.assign(DD, chebyshev_model());
  Phi1_.assign(DD, ball());
  const mag_value none;
  for (std::size_t q = 0; q < DD; ++q) {
    from_grid(phi_[q], phi_grid_[q].p, phi_e_, none.m);  // weighted
    arb_zero(Phi1_[q].get());
    for (slong k = 0; k < phi_[q].length(); ++k) arb_add(Phi1_[q].get(), Phi1_[q].get(), phi_[q].coeff(k), ARF_PREC_EXACT);
    arb_mul_2exp_si(Phi1_[q].get(), Phi1_[q].get(), w_[q % D_] - w_[q / D_]);  // Phi_kj = w_j / w_k (W Phi W^-1)_kj
  }
  // Its residual R_ij = delta_ij + hl int sum_k J_ik phi_kj - phi_ij, the sums exact on the grid
  // 2^(eJ + ePhi - 1).
  integer_poly sum, term;
  mag_value rem, s, sum2;
  std::vector<mag_value> phi_mag(DD);  // sup |phi_kj|
  for (std::size_t q = 0; q < DD; ++q) grid_magnitude(phi_mag[q].m, phi_grid_[q].p, phi_e_);
  // The short path where every sum fits 128 bits (always, at these grids' sizes).
  std::vector<short_integer_series> phi_short(DD);
  bool short_path = J_.short_form();
  std::size_t phi_len = 0;
  unsigned phi_bits = 0;
  for (std::size_t q = 0; q < DD; ++q) {
    phi_len = std::max(phi_len, static_cast<std::size_t>(phi_grid_[q].p->length));
    if (!short_path) continue;
    short_path = phi_short[q].load(phi_grid_[q].p);
    phi_bits = std::max(phi_bits, phi_short[q].bits);
  }
  short_path = short_path && fits(J_.short_bits(), phi_bits, phi_len, D_);
  std::vector<wide_int> sums;
  std::vector<ball> factors;
  integral_factors(factors, static_cast<slong>(J_.length() + phi_len) + 1, hl, J_.exponent() + phi_e_ - 1,
                   residual_prec);
  for (std::size_t i = 0; i < D_; ++i)
    for (std::size_t j = 0; j < D_; ++j) {
      fmpz_poly_zero(sum.p);
      if (short_path) sums.assign(J_.short_length() + phi_len, 0);
      mag_zero(rem.m);
      for (std::size_t k = 0; k < D_; ++k) {
        const std::size_t ik = i * D_ + k, kj = k * D_ + j;
        if (J_.zero(ik) || phi_grid_[kj].p->length == 0) continue;
        if (short_path) {
          add_chebyshev_product(sums, J_.short_series(ik), phi_short[kj]);
        } else {
          grid_product(term.p, J_.poly(ik), phi_grid_[kj].p);
          fmpz_poly_add(sum.p, sum.p, term.p);
        }
        mag_addmul(rem.m, J_.remainder(ik).m, phi_mag[kj].m);  // |J - J_grid| sup|phi|
      }
      if (short_path)
        residual_sup(s.m, wide_sums{&sums}, factors, rem.m, hl, phi_[i * D_ + j], i == j, residual_prec);
      else
        residual_sup(s.m, flint_sums{sum.p}, factors, rem.m, hl, phi_[i * D_ + j], i == j, residual_prec);
      mag_addmul(sum2.m, s.m, s.m);
    }
  mag_sqrt(phi_res_.m, sum2.m);
  return mag_is_finite(phi_res_.m);
}

// Sweeps Y = hl S (J (Y + r)) on nodes that resolve r, in double, with r scaled by a power of two
// to order one (its size is the reference's rounding, which can lie below double's range).
inline bool ball_linear_flow::integral_term(const std::vector<chebyshev_model>& r, const ball& hl) {
  slong len = 1;
  mag_value big, s;
  for (const chebyshev_model& ri : r) {
    len = std::max(len, ri.length());
    sup_bound(s.m, ri);
    mag_max(big.m, big.m, s.m);
  }
  u_exp_ = 0;
  if (!mag_is_zero(big.m)) {
    arf_t b;
    arf_init(b);
    arf_set_mag(b, big.m);
    u_exp_ = -static_cast<long>(arf_abs_bound_lt_2exp_si(b));
    arf_clear(b);
  }
  // Nodes that resolve r's low coefficients, where u's response lies (u integrates J r): 65 for a
  // quadratic field's residual of about 84, where more changed no radius (measured).
  const auto rlen = static_cast<std::size_t>(len);
  const std::size_t m = std::min(rlen + 8, std::max<std::size_t>(65, rlen / 2 + 24));
  const chebyshev_basis<double>& b = basis(m);
  const std::size_t DD = D_ * D_;
  const double hld = arf_get_d(arb_midref(hl.get()), ARF_RND_NEAR);
  jacobian_at_nodes(b, Jn_);
  // r scaled, on a grid 56 bits below its largest coefficient (its moves into its remainders),
  // and at the nodes as doubles.
  std::vector<chebyshev_model> rs(D_);  // W r 2^u_exp
  for (std::size_t i = 0; i < D_; ++i) {
    rs[i] = r[i];
    for (slong k = 0; k < rs[i].length(); ++k) arb_mul_2exp_si(rs[i].coeff(k), rs[i].coeff(k), u_exp_ + w_[i]);
    mag_mul_2exp_si(rs[i].remainder(), rs[i].remainder(), u_exp_ + w_[i]);
  }
  grid_models rg(D_);
  rg.load(rs, grid_bits);
  std::vector<double> rn(m * D_, 0.0), rc;
  const mag_value none;
  chebyshev_at_nodes(b, static_cast<std::size_t>(len));
  for (std::size_t i = 0; i < D_; ++i) {
    const fmpz_poly_struct* ri = rg.poly(i);
    rc.resize(static_cast<std::size_t>(ri->length));
    for (slong k = 0; k < ri->length; ++k) rc[k] = std::ldexp(fmpz_get_d(ri->coeffs + k), static_cast<int>(rg.exponent()));
    series_at_nodes(rc, m, rn.data() + i, D_);
  }
  Y_.assign(m * D_, 0.0);
  F_.assign(m * D_, 0.0);
  const auto product_at = [&](std::size_t l) {
    for (std::size_t i = 0; i < D_; ++i) {
      double acc = 0;
      for (std::size_t k = 0; k < D_; ++k) acc += Jn_[l * DD + i * D_ + k] * (Y_[l * D_ + k] + rn[l * D_ + k]);
      F_[l * D_ + i] = acc;
    }
  };
  for (std::size_t l = 0; l < m; ++l) product_at(l);
  std::vector<double> acc(D_);
  for (int sweep = 0; sweep < 400; ++sweep) {  // Gauss-Seidel over the nodes, as for Phi
    double change = 0, size = 0;
    for (std::size_t l = 0; l < m; ++l) {
      std::fill(acc.begin(), acc.end(), 0.0);
      for (std::size_t k = 0; k < m; ++k) {
        const double sk = b.integral[l * m + k];
        for (std::size_t i = 0; i < D_; ++i) acc[i] += sk * F_[k * D_ + i];
      }
      for (std::size_t i = 0; i < D_; ++i) {
        const double next = hld * acc[i];
        change = std::max(change, std::abs(next - Y_[l * D_ + i]));
        size = std::max(size, std::abs(next));
        Y_[l * D_ + i] = next;
      }
      product_at(l);
    }
    if (!std::isfinite(change)) return false;
    if (change <= 1e-10 * size || size == 0) break;
  }
  // u_num (scaled) on r's grid, so that w = u_num + r is one integer polynomial per component.
  const slong ue = grid_coefficients(b, Y_.data(), D_, D_, u_grid_, grid_bits, 0);
  // Both on the finer of the two grids: shift the coarser up (exact).
  const slong e = std::min(ue, rg.exponent());
  std::vector<integer_poly> w(D_);
  u_.assign(D_, chebyshev_model());
  u1_.assign(D_, ball());
  for (std::size_t i = 0; i < D_; ++i) {
    fmpz_poly_scalar_mul_2exp(u_grid_[i].p, u_grid_[i].p, static_cast<ulong>(ue - e));
    fmpz_poly_scalar_mul_2exp(w[i].p, rg.poly(i), static_cast<ulong>(rg.exponent() - e));
    fmpz_poly_add(w[i].p, w[i].p, u_grid_[i].p);
    from_grid(u_[i], u_grid_[i].p, e - u_exp_ - w_[i], none.m);  // unscaled
    arb_zero(u1_[i].get());
    for (slong k = 0; k < u_[i].length(); ++k) arb_add(u1_[i].get(), u1_[i].get(), u_[i].coeff(k), ARF_PREC_EXACT);
  }
  // rho_i = hl int sum_k J_ik (u_k + r_k) - u_i, scaled by 2^u_exp.
  integer_poly sum, term;
  mag_value rem, t, sum2;
  std::vector<mag_value> wm(D_);  // sup |w_k| plus r's move to its grid
  for (std::size_t k = 0; k < D_; ++k) {
    grid_magnitude(wm[k].m, w[k].p, e);
    mag_add(wm[k].m, wm[k].m, rg.remainder(k).m);
  }
  std::vector<short_integer_series> w_short(D_);
  bool short_path = Ju_.short_form();
  std::size_t w_len = 0;
  unsigned w_bits = 0;
  for (std::size_t k = 0; k < D_; ++k) {
    w_len = std::max(w_len, static_cast<std::size_t>(w[k].p->length));
    if (!short_path) continue;
    short_path = w_short[k].load(w[k].p);
    w_bits = std::max(w_bits, w_short[k].bits);
  }
  short_path = short_path && fits(Ju_.short_bits(), w_bits, std::min(w_len, Ju_.short_length()), D_);
  std::vector<wide_int> sums;
  std::vector<ball> factors;
  integral_factors(factors, static_cast<slong>(Ju_.length() + w_len) + 1, hl, Ju_.exponent() + e - 1, residual_prec);
  chebyshev_model ui;
  for (std::size_t i = 0; i < D_; ++i) {
    fmpz_poly_zero(sum.p);
    if (short_path) sums.assign(Ju_.short_length() + w_len, 0);
    mag_zero(rem.m);
    for (std::size_t k = 0; k < D_; ++k) {
      const std::size_t ik = i * D_ + k;
      if (Ju_.zero(ik)) continue;
      if (short_path) {
        add_chebyshev_product(sums, Ju_.short_series(ik), w_short[k]);
      } else {
        grid_product(term.p, Ju_.poly(ik), w[k].p);
        fmpz_poly_add(sum.p, sum.p, term.p);
      }
      // |J - J_grid| sup|w|, and |J_grid| times r's move to its grid.
      mag_addmul(rem.m, Ju_.remainder(ik).m, wm[k].m);
      mag_addmul(rem.m, Ju_.magnitude(ik).m, rg.remainder(k).m);
    }
    from_grid(ui, u_grid_[i].p, e, none.m);
    if (short_path)
      residual_sup(t.m, wide_sums{&sums}, factors, rem.m, hl, ui, 0, residual_prec);
    else
      residual_sup(t.m, flint_sums{sum.p}, factors, rem.m, hl, ui, 0, residual_prec);
    mag_addmul(sum2.m, t.m, t.m);
  }
  mag_sqrt(u_res_.m, sum2.m);
  mag_mul_2exp_si(u_res_.m, u_res_.m, -u_exp_);
  return mag_is_finite(u_res_.m);
}

inline void ball_linear_flow::Phi_at(const chebyshev_values& T, std::vector<ball>& out) const {
  out.resize(D_ * D_);
  for (std::size_t q = 0; q < D_ * D_; ++q) {
    evaluate(out[q], phi_[q], T, prec_);
    arb_mul_2exp_si(out[q].get(), out[q].get(), w_[q % D_] - w_[q / D_]);
  }
}

inline void ball_linear_flow::u_at(const chebyshev_values& T, std::vector<ball>& out) const {
  out.resize(D_);
  for (std::size_t i = 0; i < D_; ++i) evaluate(out[i], u_[i], T, prec_);
}

}  // namespace eulervop::detail

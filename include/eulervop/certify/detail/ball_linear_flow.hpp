// The linear parts of a segment's error for the general path of --certify (docs/certified.md,
// "The general path", steps 3 and 4), on s in [-1, 1] with tau = a + hl (s + 1):
//   - the variational matrix Phi' = hl J Phi, Phi(-1) = I;
//   - the signed integral term u' = hl J (u + r), u(-1) = 0, r the Picard residual, so that
//     u(tau) = int_a^tau Phi(tau, s) J(s) r(s) ds.
// Each is computed in double on Lobatto nodes, where no rounding matters (Phi by Picard iteration,
// u by variation of constants with Phi_num where Phi's condition allows, else by iteration):
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
// Jacobian coefficient's move to its grid, which enters its remainder.//
// The parts, one header each: node_picard.hpp (the iterations in double on Lobatto nodes),
// grid_models.hpp (models on one binary grid), integer_sum_residual.hpp (a residual's bound from
// its exact integer sums); this header joins them and keeps what each segment reuses.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/grid_models.hpp>
#include <eulervop/certify/detail/integer_sum_residual.hpp>
#include <eulervop/certify/detail/node_picard.hpp>
#include <eulervop/certify/detail/short_integer_series.hpp>
#include <eulervop/reference/detail/chebyshev_basis.hpp>

#include <arb.h>
#include <flint/fmpz_poly.h>
#include <flint/fmpz_vec.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace eulervop::detail {

class ball_linear_flow {
 public:
  explicit ball_linear_flow(std::size_t dimension)
      : D_(dimension), J_(dimension * dimension), Ju_(dimension * dimension), rg_(dimension) {}

  // The Jacobian's models (D x D, row-major; an empty model is 0) and the weights of the norm
  // (powers of two): W J W^-1 on the grids of the two residuals, and as doubles for the iterations.
  void load_jacobian(std::vector<chebyshev_model> J, const std::vector<double>& weight) {
    load_jacobian_in_place(J, weight);
  }
  // The same, working in J itself (its models are left scaled and cut, their storage kept for
  // the caller's next segment).
  void load_jacobian_in_place(std::vector<chebyshev_model>& J, const std::vector<double>& weight);
  // Phi_num on nodes chosen for |J| h (jh), and the bound of its residual in the weighted norm
  // (|W R W^-1|, weights powers of two). false when the iteration does not converge to a finite
  // value.
  bool variational(const ball& hl, double jh);
  // u_num for the residual r (D models), and the bound of its residual (|W rho|). The nodes
  // resolve a residual of `span` coefficients (r's own length where that is longer): the length
  // before r's tail went into its remainder.
  bool integral_term(const std::vector<chebyshev_model>& r, const ball& hl, slong span = 0);

  // Phi_num(s) (D x D) at s in [-1, 1], in balls at `prec` bits, from the values T_k(s) (at
  // least phi_length() of them).
  void Phi_at(const chebyshev_values& T, std::vector<ball>& out, slong prec) const;
  slong phi_length() const {
    slong n = 0;
    for (const chebyshev_model& m : phi_) n = std::max(n, m.length());
    return n;
  }
  const std::vector<chebyshev_model>& u() const { return u_; }  // u_num (D, unscaled)

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
  // u by variation of constants up to this |J| h (Phi's condition below exp(16), about 1e7).
  static constexpr double variation_jh = 8;

  void jacobian_at_nodes(const chebyshev_basis<double>& b);
  void find_live_entries();
  void phi_from_nodes();
  void bound_phi_residual(const ball& hl);
  slong scale_residual(const std::vector<chebyshev_model>& r);
  void residual_at_nodes(const chebyshev_basis<double>& b, slong len);
  void phi_at_nodes(const chebyshev_basis<double>& b);
  slong u_from_nodes(const chebyshev_basis<double>& b);
  void bound_u_residual(const ball& hl, slong e);
  static void sum_at_one(ball& x, const fmpz_poly_t p, slong e);

  std::size_t D_;
  grid_models J_, Ju_;
  std::vector<std::vector<double>> Jd_;  // the Jacobian's midpoints as doubles
  std::vector<chebyshev_model> phi_, u_;  // Phi_num (D x D) and u_num (D, unscaled), exact
  std::vector<integer_poly> phi_grid_, u_grid_;
  slong phi_e_ = 0;
  double jh_ = 0;  // variational()'s |J| h
  std::vector<int> w_;  // log2 of the weights
  long u_exp_ = 0;  // u and r scaled by 2^u_exp_ in the iteration
  std::vector<ball> Phi1_, u1_;
  mag_value phi_res_, u_res_;
  // Scratch, kept from segment to segment so that a segment allocates little.
  node_picard picard_;
  std::vector<double> Jn_, Y_, rn_, rc_, Pn_;
  std::vector<char> live_;
  std::vector<std::size_t> entries_;  // the live (i, j) of Phi as i * D + j
  std::vector<std::vector<std::size_t>> through_;  // for a live (i, j): the k with J_ik != 0, Phi_kj live
  std::vector<slong> r_shift_;  // log2 of W 2^u_exp per component
  grid_models rg_;  // W r 2^u_exp on its grid
  std::vector<integer_poly> wr_;  // u_num + W r 2^u_exp on one grid
  std::vector<mag_value> phi_mag_, w_mag_;  // sup |phi_kj|; sup |w_k| plus r's move to its grid
  std::vector<short_integer_series> phi_short_, w_short_;
  std::vector<wide_int> sums_;
  integral_residual integral_;
};

inline void ball_linear_flow::load_jacobian_in_place(std::vector<chebyshev_model>& Jc,
                                                     const std::vector<double>& weight) {
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

// Jn_[l * D^2 + q] = J_q at node l.
inline void ball_linear_flow::jacobian_at_nodes(const chebyshev_basis<double>& b) {
  const std::size_t m = b.nodes.size(), DD = D_ * D_;
  std::size_t n = 0;
  for (const std::vector<double>& c : Jd_) n = std::max(n, c.size());
  picard_.chebyshev_at_nodes(b, n);
  Jn_.assign(m * DD, 0.0);
  for (std::size_t q = 0; q < DD; ++q)
    if (!Jd_[q].empty()) picard_.series_at_nodes(Jd_[q].data(), Jd_[q].size(), m, Jn_.data() + q, DD);
}

// The entries of Phi that can be nonzero: the closure of the identity's under J's pattern
// (Phi_ij = 0 throughout where no chain of nonzero J_ik leads from j to i); the iteration and the
// products skip the rest, which stay exactly zero.
inline void ball_linear_flow::find_live_entries() {
  const std::size_t DD = D_ * D_;
  live_.assign(DD, 0);
  for (std::size_t i = 0; i < D_; ++i) live_[i * D_ + i] = 1;
  for (bool grew = true; grew;) {
    grew = false;
    for (std::size_t i = 0; i < D_; ++i)
      for (std::size_t j = 0; j < D_; ++j)
        for (std::size_t k = 0; k < D_ && !live_[i * D_ + j]; ++k)
          if (!Jd_[i * D_ + k].empty() && live_[k * D_ + j]) live_[i * D_ + j] = grew = true;
  }
  entries_.clear();
  through_.resize(DD);
  for (std::size_t q = 0; q < DD; ++q) {
    through_[q].clear();
    if (!live_[q]) continue;
    entries_.push_back(q);
    const std::size_t i = q / D_, j = q % D_;
    for (std::size_t k = 0; k < D_; ++k)
      if (!Jd_[i * D_ + k].empty() && live_[k * D_ + j]) through_[q].push_back(k);
  }
}

inline bool ball_linear_flow::variational(const ball& hl, double jh) {
  // Nodes for about twelve digits of Phi: a degree well above e |J| h / 2 (the Taylor bound of
  // the solution's coefficients; jh bounds |J| h by the Frobenius norm, which overestimates).
  jh_ = jh;
  const std::size_t m = jh <= 4.5 ? 15 : jh <= 6 ? 17 : jh <= 10 ? 25 : jh <= 16 ? 33 : jh <= 24 ? 49 : 65;
  const chebyshev_basis<double>& b = lobatto_basis(m);
  const double hld = arf_get_d(arb_midref(hl.get()), ARF_RND_NEAR);
  jacobian_at_nodes(b);
  find_live_entries();
  if (!picard_.variational_sweeps(b, Jn_.data(), D_, hld, entries_, through_, Y_)) return false;
  // Phi_num: the grid's polynomial, 40 bits below its largest coefficient (whatever polynomial we
  // take is exact; shorter ones cost less, and their residual is as small).
  phi_e_ = picard_.grid_coefficients(b, Y_.data(), D_ * D_, D_ * D_, phi_grid_, 40);
  phi_from_nodes();
  bound_phi_residual(hl);
  return mag_is_finite(phi_res_.m);
}

// phi_ (W Phi_num W^-1, exact) and Phi1_ = Phi_num(1) from phi_grid_.
inline void ball_linear_flow::phi_from_nodes() {
  const std::size_t DD = D_ * D_;
  phi_.resize(DD);
  Phi1_.resize(DD);
  const mag_value none;
  for (std::size_t q = 0; q < DD; ++q) {
    from_grid(phi_[q], phi_grid_[q].p, phi_e_, none.m);  // weighted
    // Phi_kj = w_j / w_k (W Phi W^-1)_kj
    sum_at_one(Phi1_[q], phi_grid_[q].p, phi_e_ + w_[q % D_] - w_[q / D_]);
  }
}

// x = p(1) 2^e = (sum_k p_k) 2^e exactly (T_k(1) = 1): one integer sum instead of a ball's per
// coefficient.
inline void ball_linear_flow::sum_at_one(ball& x, const fmpz_poly_t p, slong e) {
  fmpz_t s;
  fmpz_init(s);
  _fmpz_vec_sum(s, p->coeffs, p->length);
  set_fmpz_2exp(arb_midref(x.get()), s, e);
  mag_zero(arb_radref(x.get()));
  fmpz_clear(s);
}

// Phi_num's residual R_ij = delta_ij + hl int sum_k J_ik phi_kj - phi_ij, the sums exact on the
// grid 2^(eJ + ePhi - 1) (grid_product() in chebyshev_model.hpp), and |R|_2 <= its Frobenius norm.
inline void ball_linear_flow::bound_phi_residual(const ball& hl) {
  const std::size_t DD = D_ * D_;
  integer_poly sum, term;
  mag_value rem, s, sum2;
  phi_mag_.resize(DD);  // sup |phi_kj|
  for (std::size_t q = 0; q < DD; ++q) grid_magnitude(phi_mag_[q].m, phi_grid_[q].p, phi_e_);
  // The short path where every sum fits 128 bits (always, at these grids' sizes).
  phi_short_.resize(DD);
  bool short_path = J_.short_form();
  std::size_t phi_len = 0;
  unsigned phi_bits = 0;
  for (std::size_t q = 0; q < DD; ++q) {
    phi_len = std::max(phi_len, static_cast<std::size_t>(phi_grid_[q].p->length));
    if (!short_path) continue;
    short_path = phi_short_[q].load(phi_grid_[q].p);
    phi_bits = std::max(phi_bits, phi_short_[q].bits);
  }
  short_path = short_path && fits(J_.short_bits(), phi_bits, phi_len, D_);
  integral_.set_factors(static_cast<slong>(J_.length() + phi_len) + 1, hl, J_.exponent() + phi_e_ - 1, residual_prec);
  for (std::size_t i = 0; i < D_; ++i)
    for (std::size_t j = 0; j < D_; ++j) {
      fmpz_poly_zero(sum.p);
      if (short_path) sums_.assign(J_.short_length() + phi_len, 0);
      mag_zero(rem.m);
      for (std::size_t k = 0; k < D_; ++k) {
        const std::size_t ik = i * D_ + k, kj = k * D_ + j;
        if (J_.zero(ik) || phi_grid_[kj].p->length == 0) continue;
        if (short_path) {
          add_chebyshev_product(sums_, J_.short_series(ik), phi_short_[kj]);
        } else {
          grid_product(term.p, J_.poly(ik), phi_grid_[kj].p);
          fmpz_poly_add(sum.p, sum.p, term.p);
        }
        mag_addmul(rem.m, J_.remainder(ik).m, phi_mag_[kj].m);  // |J - J_grid| sup|phi|
      }
      if (short_path)
        integral_.sup(s.m, wide_sums{&sums_}, rem.m, phi_grid_[i * D_ + j].p, phi_e_, i == j);
      else
        integral_.sup(s.m, flint_sums{sum.p}, rem.m, phi_grid_[i * D_ + j].p, phi_e_, i == j);
      mag_addmul(sum2.m, s.m, s.m);
    }
  mag_sqrt(phi_res_.m, sum2.m);
}

// u_num for r: the iteration Y = hl S (J (Y + r)) on nodes that resolve r, in double, with r
// scaled by a power of two to order one (its size is the reference's rounding, which can lie
// below double's range).
inline bool ball_linear_flow::integral_term(const std::vector<chebyshev_model>& r, const ball& hl, slong span) {
  const slong len = scale_residual(r);
  // Nodes that resolve r's low coefficients, where u's response lies (u integrates J r): 65 for a
  // quadratic field's residual of about 84, where more changed no radius (measured). They follow
  // the residual's whole length, not its cut one: on fewer nodes u_num's residual, an unsigned
  // ball, grew (mpfr:256 radii 170 to 850 times, with quad's unchanged).
  const auto rlen = static_cast<std::size_t>(std::max(len, span));
  const std::size_t m = std::min(rlen + 8, std::max<std::size_t>(65, rlen / 2 + 24));
  const chebyshev_basis<double>& b = lobatto_basis(m);
  const double hld = arf_get_d(arb_midref(hl.get()), ARF_RND_NEAR);
  jacobian_at_nodes(b);
  residual_at_nodes(b, len);
  // By variation of constants with Phi_num where Phi's condition (at most exp(2 |J| h)) leaves
  // u a few digits in double; by the sweeps where it may not, or where Phi_num is singular.
  bool done = false;
  if (jh_ <= variation_jh) {
    phi_at_nodes(b);
    done = picard_.integral_term_by_variation(b, Jn_.data(), rn_.data(), Pn_.data(), D_, hld, Y_);
  }
  if (!done && !picard_.integral_term_sweeps(b, Jn_.data(), rn_.data(), D_, hld, Y_)) return false;
  const slong e = u_from_nodes(b);
  bound_u_residual(hl, e);
  return mag_is_finite(u_res_.m);
}

// rg_: W r 2^u_exp (u_exp_: r's largest sup bound to order one) on a grid 56 bits
// below its largest coefficient (the moves into its remainders). Returns r's longest length (1 at
// least).
inline slong ball_linear_flow::scale_residual(const std::vector<chebyshev_model>& r) {
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
  r_shift_.resize(D_);
  for (std::size_t i = 0; i < D_; ++i) r_shift_[i] = u_exp_ + w_[i];
  rg_.load(r, grid_bits, r_shift_);
  return len;
}

// Pn_[l * D^2 + q] = Phi_num's entry q (weighted) at node l, in double.
inline void ball_linear_flow::phi_at_nodes(const chebyshev_basis<double>& b) {
  const std::size_t m = b.nodes.size(), DD = D_ * D_;
  std::size_t n = 1;
  for (const integer_poly& p : phi_grid_) n = std::max(n, static_cast<std::size_t>(p.p->length));
  picard_.chebyshev_at_nodes(b, n);
  Pn_.assign(m * DD, 0.0);
  for (std::size_t q = 0; q < DD; ++q) {
    const fmpz_poly_struct* p = phi_grid_[q].p;
    if (p->length == 0) continue;
    scaled_doubles(p, phi_e_, rc_);
    picard_.series_at_nodes(rc_.data(), rc_.size(), m, Pn_.data() + q, DD);
  }
}

// rn_[l * D + i] = rg_'s polynomial i at node l, in double.
inline void ball_linear_flow::residual_at_nodes(const chebyshev_basis<double>& b, slong len) {
  const std::size_t m = b.nodes.size();
  rn_.assign(m * D_, 0.0);
  picard_.chebyshev_at_nodes(b, static_cast<std::size_t>(len));
  for (std::size_t i = 0; i < D_; ++i) {
    const fmpz_poly_struct* ri = rg_.poly(i);
    scaled_doubles(ri, rg_.exponent(), rc_);
    picard_.series_at_nodes(rc_.data(), rc_.size(), m, rn_.data() + i, D_);
  }
}

// u_num (scaled) from the nodes on the grid 56 bits below its largest coefficient, then with r on
// the finer of the two grids (the coarser shifted up: exact), so that w = u_num + r is one integer
// polynomial per component; u_ (unscaled) and u1_ = u_num(1). Returns the common grid's exponent.
inline slong ball_linear_flow::u_from_nodes(const chebyshev_basis<double>& b) {
  const slong ue = picard_.grid_coefficients(b, Y_.data(), D_, D_, u_grid_, grid_bits);
  const slong e = std::min(ue, rg_.exponent());
  wr_.resize(D_);
  u_.resize(D_);
  u1_.resize(D_);
  const mag_value none;
  for (std::size_t i = 0; i < D_; ++i) {
    fmpz_poly_scalar_mul_2exp(u_grid_[i].p, u_grid_[i].p, static_cast<ulong>(ue - e));
    fmpz_poly_scalar_mul_2exp(wr_[i].p, rg_.poly(i), static_cast<ulong>(rg_.exponent() - e));
    fmpz_poly_add(wr_[i].p, wr_[i].p, u_grid_[i].p);
    from_grid(u_[i], u_grid_[i].p, e - u_exp_ - w_[i], none.m);  // unscaled
    sum_at_one(u1_[i], u_grid_[i].p, e - u_exp_ - w_[i]);
  }
  return e;
}

// rho_i = hl int sum_k J_ik (u_k + r_k) - u_i, scaled by 2^u_exp, the sums exact on the grid
// 2^(eJ + e - 1); |W rho|_2 <= the 2-norm of the components' bounds.
inline void ball_linear_flow::bound_u_residual(const ball& hl, slong e) {
  integer_poly sum, term;
  mag_value rem, t, sum2;
  w_mag_.resize(D_);  // sup |w_k| plus r's move to its grid
  for (std::size_t k = 0; k < D_; ++k) {
    grid_magnitude(w_mag_[k].m, wr_[k].p, e);
    mag_add(w_mag_[k].m, w_mag_[k].m, rg_.remainder(k).m);
  }
  w_short_.resize(D_);
  bool short_path = Ju_.short_form();
  std::size_t w_len = 0;
  unsigned w_bits = 0;
  for (std::size_t k = 0; k < D_; ++k) {
    w_len = std::max(w_len, static_cast<std::size_t>(wr_[k].p->length));
    if (!short_path) continue;
    short_path = w_short_[k].load(wr_[k].p);
    w_bits = std::max(w_bits, w_short_[k].bits);
  }
  short_path = short_path && fits(Ju_.short_bits(), w_bits, std::min(w_len, Ju_.short_length()), D_);
  integral_.set_factors(static_cast<slong>(Ju_.length() + w_len) + 1, hl, Ju_.exponent() + e - 1, residual_prec);
  for (std::size_t i = 0; i < D_; ++i) {
    fmpz_poly_zero(sum.p);
    if (short_path) sums_.assign(Ju_.short_length() + w_len, 0);
    mag_zero(rem.m);
    for (std::size_t k = 0; k < D_; ++k) {
      const std::size_t ik = i * D_ + k;
      if (Ju_.zero(ik)) continue;
      if (short_path) {
        add_chebyshev_product(sums_, Ju_.short_series(ik), w_short_[k]);
      } else {
        grid_product(term.p, Ju_.poly(ik), wr_[k].p);
        fmpz_poly_add(sum.p, sum.p, term.p);
      }
      // |J - J_grid| sup|w|, and |J_grid| times r's move to its grid.
      mag_addmul(rem.m, Ju_.remainder(ik).m, w_mag_[k].m);
      mag_addmul(rem.m, Ju_.magnitude(ik).m, rg_.remainder(k).m);
    }
    if (short_path)
      integral_.sup(t.m, wide_sums{&sums_}, rem.m, u_grid_[i].p, e, 0);
    else
      integral_.sup(t.m, flint_sums{sum.p}, rem.m, u_grid_[i].p, e, 0);
    mag_addmul(sum2.m, t.m, t.m);
  }
  mag_sqrt(u_res_.m, sum2.m);
  mag_mul_2exp_si(u_res_.m, u_res_.m, -u_exp_);
}

inline void ball_linear_flow::Phi_at(const chebyshev_values& T, std::vector<ball>& out, slong prec) const {
  out.resize(D_ * D_);
  for (std::size_t q = 0; q < D_ * D_; ++q) {
    evaluate(out[q], phi_[q], T, prec);
    arb_mul_2exp_si(out[q].get(), out[q].get(), w_[q % D_] - w_[q / D_]);
  }
}

}  // namespace eulervop::detail

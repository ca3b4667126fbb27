// The Chebyshev coefficients of a segment's polynomial from its node values, in balls, for the
// general path of --certify: the degree-N interpolant of the values at the Lobatto nodes
// s_j = -cos(j pi / N) has the coefficients
//   c_k = (2/N) sum_j'' v_j T_k(s_j),  T_k(s_j) = (-1)^k cos(k j pi / N),
// the sum's end terms halved, and c_0, c_N halved too. The matrix is enclosed once. Since
// T_k(-s) = (-1)^k T_k(s) and the nodes are symmetric, the columns j and N - j differ by (-1)^k:
// even coefficients take the sums v_j + v_{N-j}, odd ones the differences, which halves the
// products. The products are exact integer sums on two binary grids: M's midpoints on the grid
// 2^-G and each component's folded values on a grid of G bits below their largest, as integers of
// L limbs (G = 64 L - 2 >= the working precision), summed exactly on fixed-size limbs
// (core/limb_arithmetic.hpp); the sum is rounded once and widened by a bound of the two grids'
// moves and M's radii. Arb's own dot products (arb_mat_mul) did the same with one alignment per
// term and cost several times more; they remain for precisions beyond 8 limbs.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/fixed_point.hpp>
#include <eulervop/certify/detail/magnitude_sum.hpp>
#include <eulervop/core/limb_arithmetic.hpp>

#include <arb.h>
#include <arb_mat.h>
#include <flint/fmpq.h>
#include <flint/fmpz.h>

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

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
  void enclose_on_grid();
  struct component_bound;
  template <std::size_t L>
  void apply_on_limbs(arb_mat_t out);
  template <std::size_t L>
  void coefficient_on_limbs(arb_ptr c, std::size_t k, bool short_folds, slong e);
  template <std::size_t L>
  void magnitude_sum(std::size_t first, slong exponent, mag_t out);
  template <std::size_t L>
  void load_folds(std::size_t i, slong& exponent, mag_t plus_abs, mag_t minus_abs);

  slong prec_;
  std::size_t N_, n1_, D_, half_, even_, odd_;
  arb_mat_t values_;
  // M's rows k = 0, 2, ... and k = 1, 3, ...; columns j < (N + 2) / 2: enclosed once, and shared
  // by the copies (one per check: two thousand numbers each, a third of a check's memory).
  struct matrices {
    arb_mat_t even, odd;
    matrices(slong even_rows, slong odd_rows, slong columns) {
      arb_mat_init(even, even_rows, columns);
      arb_mat_init(odd, odd_rows, columns);
    }
    ~matrices() {
      arb_mat_clear(even);
      arb_mat_clear(odd);
    }
    matrices(const matrices&) = delete;
    matrices& operator=(const matrices&) = delete;
  };
  std::shared_ptr<const matrices> M_;
  arb_mat_t plus_, minus_;        // folded values
  arb_mat_t c_even_, c_odd_;
  // M on the grid 2^-G, G = 64 limbs - 2: row k, column j as |q| (limbs' limbs) and a sign mask;
  // per row k, dM_k >= |M_kj - q_kj 2^-G| (the entries' radii and a step) and Mmax_k >= |q_kj 2^-G|.
  // Constant, so the copies (one per check) share it. limbs = 0: beyond 8 limbs, Arb's products.
  struct grid_matrix {
    std::size_t limbs = 0;
    std::vector<mp_limb_t> q, neg;
    std::vector<mag_value> dM, Mmax;
    std::vector<double> dM_up, Mmax_up;  // the same bounds as doubles (exact), where moderate()
    bool doubles = true;
  };
  std::shared_ptr<const grid_matrix> grid_;
  // Scratch: one component's folded values on their grid (plus, then minus), a sum, an integer.
  std::vector<mp_limb_t> folds_, fold_neg_, acc_;
  fmpz_t z_;
};

inline void ball_node_transform::allocate() {
  const auto rows = [](std::size_t n) { return static_cast<slong>(n); };
  arb_mat_init(values_, rows(n1_), rows(D_));
  arb_mat_init(plus_, rows(half_), rows(D_));
  arb_mat_init(minus_, rows(half_), rows(D_));
  arb_mat_init(c_even_, rows(even_), rows(D_));
  arb_mat_init(c_odd_, rows(odd_), rows(D_));
}

inline ball_node_transform::ball_node_transform(slong prec, std::size_t degree, std::size_t components)
    : prec_(prec), N_(degree), n1_(degree + 1), D_(components), half_((degree + 2) / 2), even_((degree + 2) / 2),
      odd_((degree + 1) / 2) {
  fmpz_init(z_);
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
  const auto M = std::make_shared<matrices>(static_cast<slong>(even_), static_cast<slong>(odd_), static_cast<slong>(half_));
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
      arb_set(arb_mat_entry(k % 2 ? M->odd : M->even, static_cast<slong>(k / 2), static_cast<slong>(j)), w);
    }
  arb_clear(w);
  _arb_vec_clear(cosines, static_cast<slong>(2 * N_));
  M_ = M;
  enclose_on_grid();
}

// grid_ from M_'s even and odd rows (rows k in order).
inline void ball_node_transform::enclose_on_grid() {
  auto g = std::make_shared<grid_matrix>();
  const std::size_t L = (static_cast<std::size_t>(prec_) + 2 + 63) / 64;
  if (L <= 8) {
    g->limbs = L;
    const slong G = 64 * static_cast<slong>(L) - 2;
    g->q.assign(n1_ * half_ * L, 0);
    g->neg.assign(n1_ * half_, 0);
    g->dM.resize(n1_);
    g->Mmax.resize(n1_);
    mag_value t;
    for (std::size_t k = 0; k < n1_; ++k)
      for (std::size_t j = 0; j < half_; ++j) {
        arb_srcptr m = arb_mat_entry(k % 2 ? M_->odd : M_->even, static_cast<slong>(k / 2), static_cast<slong>(j));
        arf_get_fmpz_fixed_si(z_, arb_midref(m), -G);  // |mid - q 2^-G| < 2^-G; |q| <= |mid| 2^G <= 2^G
        g->neg[k * half_ + j] = fmpz_sgn(z_) < 0 ? ~mp_limb_t(0) : 0;
        fmpz_abs(z_, z_);
        fmpz_get_ui_array(&g->q[(k * half_ + j) * L], static_cast<slong>(L), z_);
        mag_set_ui_2exp_si(t.m, 1, -G);
        mag_add(t.m, t.m, arb_radref(m));
        mag_max(g->dM[k].m, g->dM[k].m, t.m);
        arf_get_mag(t.m, arb_midref(m));
        mag_add_ui_2exp_si(t.m, t.m, 1, -G);  // whichever way the move went
        mag_max(g->Mmax[k].m, g->Mmax[k].m, t.m);
      }
    for (std::size_t k = 0; k < n1_; ++k) {
      double d = 0, m = 0;
      g->doubles = g->doubles && magnitude::bound(g->dM[k].m, d) && magnitude::bound(g->Mmax[k].m, m) &&
                   magnitude::moderate(d) && magnitude::moderate(m);
      g->dM_up.push_back(d);
      g->Mmax_up.push_back(m);
    }
    folds_.assign(2 * half_ * L, 0);
    fold_neg_.assign(2 * half_, 0);
    acc_.assign(2 * L + 2, 0);
  }
  grid_ = std::move(g);
}

inline ball_node_transform::~ball_node_transform() {
  fmpz_clear(z_);
  arb_mat_clear(values_);
  arb_mat_clear(plus_);
  arb_mat_clear(minus_);
  arb_mat_clear(c_even_);
  arb_mat_clear(c_odd_);
}

inline ball_node_transform::ball_node_transform(const ball_node_transform& o)
    : prec_(o.prec_), N_(o.N_), n1_(o.n1_), D_(o.D_), half_(o.half_), even_(o.even_), odd_(o.odd_),
      M_(o.M_), grid_(o.grid_), folds_(o.folds_), fold_neg_(o.fold_neg_), acc_(o.acc_) {
  fmpz_init(z_);
  allocate();
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

// Component i's values on the grid 2^exponent (G bits below the largest) and folded into folds_
// (sums at j, differences at half_ + j; the middle value, N even, alone in both), each within two
// steps of the exact fold; the sums of their magnitudes into plus_abs and minus_abs (rounded up).
template <std::size_t L>
void ball_node_transform::load_folds(std::size_t i, slong& exponent, mag_t plus_abs, mag_t minus_abs) {
  const slong G = 64 * static_cast<slong>(L) - 2;
  slong top = WORD_MIN;
  for (std::size_t j = 0; j < n1_; ++j) {
    const arf_struct* v = arb_midref(arb_mat_entry(values_, static_cast<slong>(j), static_cast<slong>(i)));
    if (!arf_is_zero(v)) top = std::max(top, arf_abs_bound_lt_2exp_si(v));
  }
  exponent = (top == WORD_MIN ? 0 : top) - G;  // |v| 2^-exponent < 2^G
  mp_limb_t a[L], b[L], a_neg = 0, b_neg = 0;
  const auto load = [&](std::size_t j, mp_limb_t* out, mp_limb_t& negative) {
    arb_srcptr v = arb_mat_entry(values_, static_cast<slong>(j), static_cast<slong>(i));
    unsigned sign = 0;
    if (fixed_limbs(out, L, sign, arb_midref(v), exponent) >= 0) {
      negative = sign ? ~mp_limb_t(0) : 0;
      return;
    }
    arf_get_fmpz_fixed_si(z_, arb_midref(v), exponent);
    negative = fmpz_sgn(z_) < 0 ? ~mp_limb_t(0) : 0;
    fmpz_abs(z_, z_);
    fmpz_get_ui_array(out, static_cast<slong>(L), z_);
  };
  for (std::size_t j = 0; j < half_; ++j) {
    mp_limb_t* plus = &folds_[j * L];
    mp_limb_t* minus = &folds_[(half_ + j) * L];
    load(j, a, a_neg);
    if (2 * j == N_) {  // the middle node, its own mirror
      for (std::size_t l = 0; l < L; ++l) plus[l] = minus[l] = a[l];
      fold_neg_[j] = fold_neg_[half_ + j] = a_neg;
      continue;
    }
    load(N_ - j, b, b_neg);  // each below 2^G: the sums fit L limbs
    limbs::signed_sum(a, a_neg, b, b_neg, false, L, plus, fold_neg_[j]);
    limbs::signed_sum(a, a_neg, b, b_neg, true, L, minus, fold_neg_[half_ + j]);
  }
  magnitude_sum<L>(0, exponent, plus_abs);
  magnitude_sum<L>(half_, exponent, minus_abs);
}

// sum_j |folds_ j| for j = first .. first + half_ - 1, times 2^exponent, rounded up.
template <std::size_t L>
void ball_node_transform::magnitude_sum(std::size_t first, slong exponent, mag_t out) {
  mp_limb_t* sum = acc_.data();
  for (std::size_t l = 0; l <= L; ++l) sum[l] = 0;
  for (std::size_t f = first; f < first + half_; ++f)
    sum[L] += mpn_add_n(sum, sum, &folds_[f * L], static_cast<mp_size_t>(L));
  mp_size_t size = static_cast<mp_size_t>(L + 1);
  while (size > 0 && sum[size - 1] == 0) --size;
  arf_t s;
  arf_init(s);
  if (size > 0) arf_set_mpn(s, sum, size, 0);
  arf_get_mag(out, s);
  mag_mul_2exp_si(out, out, exponent);
  arf_clear(s);
}

// The parts of a component's bound that do not depend on k (apply_on_limbs()): the folds'
// magnitudes F^ (sums, differences), 2 n steps and the values' radii, as mags and, where each is
// moderate (magnitude_sum.hpp), as doubles, in which at() then bounds in a few roundings up what
// Arb's magnitudes take seven calls for.
struct ball_node_transform::component_bound {
  mag_value F[2], steps, radii;
  double Fd[2] = {0, 0}, stepsd = 0, radiid = 0;
  bool doubles = false;

  void to_doubles(bool grid_doubles) {
    using namespace magnitude;
    doubles = grid_doubles && bound(F[0].m, Fd[0]) && bound(F[1].m, Fd[1]) && bound(steps.m, stepsd) &&
              bound(radii.m, radiid) && moderate(Fd[0]) && moderate(Fd[1]) && moderate(stepsd) && moderate(radiid);
  }
  // E >= dM_k (F^ + 2 n step) + Mmax_k 2 n step + (Mmax_k + dM_k) sum_j rad v_j.
  void at(mag_t E, const grid_matrix& g, std::size_t k) const {
    if (doubles) {
      using namespace magnitude;
      const double dM = g.dM_up[k], Mmax = g.Mmax_up[k];
      mag_set_d(E, add_up(add_up(mul_up(dM, add_up(Fd[k % 2], stepsd)), mul_up(Mmax, stepsd)),
                          mul_up(add_up(Mmax, dM), radiid)));
      return;
    }
    mag_value t;
    mag_add(E, F[k % 2].m, steps.m);
    mag_mul(E, E, g.dM[k].m);
    mag_addmul(E, g.Mmax[k].m, steps.m);
    mag_add(t.m, g.Mmax[k].m, g.dM[k].m);
    mag_addmul(E, t.m, radii.m);
  }
};

// c = 2^(e - G) sum_j q_kj f^_j, exactly (rounded to the working precision below), from the folds
// of k's parity; where their lowest limbs are all zero (`short_folds`) without those limbs'
// products, which gives the same sum.
template <std::size_t L>
void ball_node_transform::coefficient_on_limbs(arb_ptr c, std::size_t k, bool short_folds, slong e) {
  constexpr std::size_t W = 2 * L + 1;
  const grid_matrix& g = *grid_;
  const std::size_t folded = (k % 2) ? half_ : 0;  // differences or sums
  limbs::column_sum<L> sum;
  if constexpr (L > 1) {
    if (short_folds)
      for (std::size_t j = 0; j < half_; ++j)
        sum.template add_product<L - 1, 1>(&g.q[(k * half_ + j) * L], &folds_[(folded + j) * L + 1],
                                            (g.neg[k * half_ + j] ^ fold_neg_[folded + j]) & 1);
  }
  if (L == 1 || !short_folds)
    for (std::size_t j = 0; j < half_; ++j)
      sum.add_product(&g.q[(k * half_ + j) * L], &folds_[(folded + j) * L],
                      (g.neg[k * half_ + j] ^ fold_neg_[folded + j]) & 1);
  mp_limb_t* acc = acc_.data();
  sum.to_limbs(acc, W);
  const bool negative = acc[W - 1] >> 63;
  if (negative) mpn_neg(acc, acc, static_cast<mp_size_t>(W));
  mp_size_t size = static_cast<mp_size_t>(W);
  while (size > 0 && acc[size - 1] == 0) --size;
  mag_zero(arb_radref(c));
  if (size == 0) {
    arf_zero(arb_midref(c));
    return;
  }
  arf_set_mpn(arb_midref(c), acc, size, negative);
  arf_mul_2exp_si(arb_midref(c), arb_midref(c), e - (64 * static_cast<slong>(L) - 2));
}

// The coefficients on L limbs. With f_j the exact folded values (sums for even k, differences for
// odd k) and f^_j those on the grid (|f_j - f^_j| < 2 steps), F^ = sum_j |f^_j| and n = half_:
//   |c_k - 2^-G sum_j q_kj f^_j| <= sum_j |M_kj - q_kj 2^-G| |f_j| + |q_kj 2^-G| |f_j - f^_j|
//                                <= dM_k (F^ + 2 n step) + Mmax_k 2 n step;
// values with radii (the midpoints are folded) add (Mmax_k + dM_k) sum_j rad v_j, and the exact
// sum's rounding to the working precision is Arb's (arb_set_round).
template <std::size_t L>
void ball_node_transform::apply_on_limbs(arb_mat_t out) {
  component_bound bound;
  mag_value E;
  for (std::size_t i = 0; i < D_; ++i) {
    slong e = 0;
    load_folds<L>(i, e, bound.F[0].m, bound.F[1].m);
    // Where every fold's lowest limb is zero, it is left out of the products (the sum is the same):
    // in quad (L = 3, G = 190) values within 2^-13 of their component's largest are multiples of
    // 2^64 on the grid, which is nearly every segment.
    bool short_folds[2] = {true, true};
    for (std::size_t f = 0; f < 2 * half_; ++f)
      if (folds_[f * L] != 0) short_folds[f < half_ ? 0 : 1] = false;
    mag_set_ui_2exp_si(bound.steps.m, 2 * half_, e);  // 2 n steps
    mag_zero(bound.radii.m);
    for (std::size_t j = 0; j < n1_; ++j)
      mag_add(bound.radii.m, bound.radii.m, arb_radref(arb_mat_entry(values_, static_cast<slong>(j), static_cast<slong>(i))));
    bound.to_doubles(grid_->doubles);
    for (std::size_t k = 0; k < n1_; ++k) {
      bound.at(E.m, *grid_, k);
      arb_ptr c = arb_mat_entry(out, static_cast<slong>(k), static_cast<slong>(i));
      coefficient_on_limbs<L>(c, k, short_folds[k % 2], e);
      arb_set_round(c, c, prec_);
      arb_add_error_mag(c, E.m);
    }
  }
}

inline void ball_node_transform::apply(arb_mat_t out) {
  if (grid_->limbs > 0 &&
      limbs::with_limb_count(grid_->limbs, [&](auto L) { apply_on_limbs<decltype(L)::value>(out); }))
    return;
  fold();
  arb_mat_mul(c_even_, M_->even, plus_, prec_);
  if (odd_ > 0) arb_mat_mul(c_odd_, M_->odd, minus_, prec_);
  // Swapped, not copied: the products overwrite c_even_ and c_odd_ on the next call, and the
  // numbers' storage (at the working precision, on the heap) goes round instead of being copied.
  for (std::size_t k = 0; k < n1_; ++k)
    for (std::size_t i = 0; i < D_; ++i)
      arb_swap(arb_mat_entry(out, static_cast<slong>(k), static_cast<slong>(i)),
               arb_mat_entry(k % 2 ? c_odd_ : c_even_, static_cast<slong>(k / 2), static_cast<slong>(i)));
}

}  // namespace eulervop::detail

// A Chebyshev model on s in [-1, 1]: a polynomial with ball coefficients and a remainder bound,
//   f(s) in sum_k c_k T_k(s) + [-rem, rem]   for every s in [-1, 1],
// where each c_k is some point of its ball (Brisebarre and Joldes, "Chebyshev interpolation
// polynomial-based tools for rigorous computing", ISSAC 2010; Joldes' thesis, ENS Lyon 2011).
// The general path of --certify (docs/certified.md, "The general path") computes a segment's
// polynomial, the field along it, its residual and its Jacobian as such models.
//
// The remainder is kept apart from the coefficients' radii because the two mean different
// things: a radius is an uncertainty about one coefficient, while the remainder is any function
// bounded by rem. Products and sums treat both by the triangle inequality; the integral cannot
// move a remainder into a coefficient (int_{-1}^s of a function bounded by rem is bounded by
// (s + 1) rem, not by the integral of a T_k), so it doubles it instead. A model whose remainder
// is zero is exactly a polynomial with enclosed coefficients.
//
// Products use T_m T_n = (T_{m+n} + T_{|m-n|}) / 2: 2 c_k = sum_{m+n=k} a_m b_n + sum_{|m-n|=k}
// a_m b_n, the second sum a convolution of a with b reversed, so one product is two exact integer
// convolutions on binary grids (grid_product(), kronecker_product.hpp) with one error bound.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/magnitude_sum.hpp>
#include <eulervop/certify/detail/chunked_product.hpp>
#include <eulervop/certify/detail/fixed_point.hpp>
#include <eulervop/certify/detail/kronecker_product.hpp>

#include <arb.h>
#include <arb_poly.h>
#include <flint/fmpz_poly.h>

#include <algorithm>
#include <utility>

namespace eulervop::detail {

class chebyshev_model {
 public:
  chebyshev_model() { mag_init(rem_); }
  explicit chebyshev_model(slong length) : chebyshev_model() { resize(length); }
  chebyshev_model(const chebyshev_model& o) : chebyshev_model() { *this = o; }
  chebyshev_model(chebyshev_model&& o) noexcept : chebyshev_model() { swap(o); }
  chebyshev_model& operator=(const chebyshev_model& o) {
    if (this == &o) return *this;
    reserve_length(o.len_);
    _arb_vec_set(c_, o.c_, o.len_);
    mag_set(rem_, o.rem_);
    return *this;
  }
  chebyshev_model& operator=(chebyshev_model&& o) noexcept {
    swap(o);
    return *this;
  }
  ~chebyshev_model() {
    if (c_) _arb_vec_clear(c_, alloc_);
    mag_clear(rem_);
  }
  void swap(chebyshev_model& o) noexcept {
    std::swap(c_, o.c_);
    std::swap(len_, o.len_);
    std::swap(alloc_, o.alloc_);
    mag_swap(rem_, o.rem_);
  }

  slong length() const { return len_; }
  arb_ptr coeffs() { return c_; }
  arb_srcptr coeffs() const { return c_; }
  arb_ptr coeff(slong k) { return c_ + k; }
  arb_srcptr coeff(slong k) const { return c_ + k; }
  mag_ptr remainder() { return rem_; }
  mag_srcptr remainder() const { return rem_; }

  // The length becomes n; new coefficients are zero. The remainder is kept.
  void resize(slong n) {
    const slong old = len_;
    reserve_length(n);
    for (slong k = old; k < n; ++k) arb_zero(c_ + k);
  }
  // The length becomes n, the new coefficients unspecified: for a caller that sets every one.
  // Unlike resize(), it leaves the coefficients' storage alone (zeroing an Arb number frees its
  // limbs, which the caller's next set would allocate again).
  void reserve_length(slong n) {
    if (n > alloc_) {
      const slong grown = std::max<slong>(n, 2 * alloc_);
      arb_ptr c = _arb_vec_init(grown);
      if (c_) {
        _arb_vec_swap(c, c_, len_);
        _arb_vec_clear(c_, alloc_);
      }
      c_ = c;
      alloc_ = grown;
    }
    len_ = n;
  }
  void set_zero() {
    len_ = 0;
    mag_zero(rem_);
  }
  void set_constant(const ball& x) {
    resize(1);
    arb_set(c_, x.get());
    mag_zero(rem_);
  }
  // True when the model is the zero function (no coefficient, no remainder).
  bool is_zero() const { return len_ == 0 && mag_is_zero(rem_); }

 private:
  arb_ptr c_ = nullptr;
  slong len_ = 0, alloc_ = 0;
  mag_t rem_;
};

// sum_k |c_k| (an upper bound; coefficients k >= first only).
inline void coefficient_magnitude(mag_t out, const chebyshev_model& a, slong first = 0) {
  magnitude_sum(out, a.coeffs() + first, std::max<slong>(a.length() - first, 0));
}

// An upper bound of sup |f| on [-1, 1]: sum |c_k| + rem.
inline void sup_bound(mag_t out, const chebyshev_model& a) {
  coefficient_magnitude(out, a);
  mag_add(out, out, a.remainder());
}

// A ball that holds f(s) for every s in [-1, 1]: c_0 widened by the rest.
inline void range_of(ball& out, const chebyshev_model& a) {
  mag_t rest;
  mag_init(rest);
  coefficient_magnitude(rest, a, 1);
  mag_add(rest, rest, a.remainder());
  if (a.length() > 0)
    arb_set(out.get(), a.coeff(0));
  else
    arb_zero(out.get());
  arb_add_error_mag(out.get(), rest);
  mag_clear(rest);
}

// acc += b.
inline void add_to(chebyshev_model& acc, const chebyshev_model& b, slong prec) {
  if (b.length() > acc.length()) acc.resize(b.length());
  for (slong k = 0; k < b.length(); ++k) arb_add(acc.coeff(k), acc.coeff(k), b.coeff(k), prec);
  mag_add(acc.remainder(), acc.remainder(), b.remainder());
}

// acc -= b.
inline void subtract_from(chebyshev_model& acc, const chebyshev_model& b, slong prec) {
  if (b.length() > acc.length()) acc.resize(b.length());
  for (slong k = 0; k < b.length(); ++k) arb_sub(acc.coeff(k), acc.coeff(k), b.coeff(k), prec);
  mag_add(acc.remainder(), acc.remainder(), b.remainder());
}

inline void negate(chebyshev_model& a) {
  for (slong k = 0; k < a.length(); ++k) arb_neg(a.coeff(k), a.coeff(k));
}

// a *= x (a number); exactly where x is a signed power of two (the fields' 1/2, -1 and units).
inline void scale(chebyshev_model& a, const ball& x, slong prec) {
  const arf_struct* mid = arb_midref(x.get());
  if (arb_is_exact(x.get()) && !arf_is_zero(mid) && arf_is_finite(mid) && arf_bits(mid) == 1) {
    const slong e = arf_abs_bound_lt_2exp_si(mid) - 1;  // |x| = 2^e
    for (slong k = 0; k < a.length(); ++k) {
      arb_mul_2exp_si(a.coeff(k), a.coeff(k), e);
      if (arf_sgn(mid) < 0) arb_neg(a.coeff(k), a.coeff(k));
    }
    mag_mul_2exp_si(a.remainder(), a.remainder(), e);
    return;
  }
  for (slong k = 0; k < a.length(); ++k) arb_mul(a.coeff(k), a.coeff(k), x.get(), prec);
  mag_t m;
  mag_init(m);
  arb_get_mag(m, x.get());
  mag_mul(a.remainder(), a.remainder(), m);
  mag_clear(m);
}

// x = n 2^e exactly.
inline void set_fmpz_2exp(arf_t x, const fmpz_t n, slong e) {
  arf_set_fmpz(x, n);
  arf_mul_2exp_si(x, x, e);
}

// A polynomial with integer coefficients, freed with its owner (scratch kept per thread).
struct integer_poly {
  integer_poly() { fmpz_poly_init(p); }
  ~integer_poly() { fmpz_poly_clear(p); }
  integer_poly(integer_poly&& o) noexcept {
    fmpz_poly_init(p);
    fmpz_poly_swap(p, o.p);
  }
  integer_poly& operator=(integer_poly&& o) noexcept {
    fmpz_poly_swap(p, o.p);
    return *this;
  }
  integer_poly(const integer_poly&) = delete;
  integer_poly& operator=(const integer_poly&) = delete;
  fmpz_poly_t p;
};

// A model's coefficients on the binary grid 2^e: the integers n_k = trunc(mid(c_k) 2^-e), and in
// `moved` a bound of the distances to the grid plus the radii, sum_k rad c_k + (the number of
// inexact n_k) 2^e (truncation moves each by less than 2^e), which bounds |f - 2^e sum n_k T_k|
// beyond the model's own remainder (|T_k| <= 1).
inline void to_grid(fmpz_poly_t n, mag_t moved, const chebyshev_model& a, slong e) {
  fmpz_poly_fit_length(n, a.length());
  ulong inexact = 0;
  for (slong k = 0; k < a.length(); ++k)
    if (fixed_fmpz(n->coeffs + k, arb_midref(a.coeff(k)), e)) ++inexact;
  radius_sum(moved, a.coeffs(), a.length());
  if (inexact > 0) {
    mag_t step;
    mag_init(step);
    mag_set_ui_2exp_si(step, inexact, e);
    mag_add(moved, moved, step);
    mag_clear(step);
  }
  _fmpz_poly_set_length(n, a.length());
  _fmpz_poly_normalise(n);
}

// The exponent t with every midpoint of a below 2^t in magnitude (WORD_MIN where all are zero).
inline slong midpoint_top(const chebyshev_model& a) {
  slong top = WORD_MIN;
  for (slong k = 0; k < a.length(); ++k)
    if (!arf_is_zero(arb_midref(a.coeff(k)))) top = std::max(top, arf_abs_bound_lt_2exp_si(arb_midref(a.coeff(k))));
  return top;
}

// The exponent of the grid with `bits` bits below the largest midpoint of a (0 for zero).
inline slong grid_exponent(const chebyshev_model& a, slong bits) {
  const slong top = midpoint_top(a);
  return top == WORD_MIN ? 0 : top - bits;
}

// sum_k |n_k| 2^e, rounded up.
inline void grid_magnitude(mag_t out, const fmpz_poly_t n, slong e) { magnitude_sum(out, n->coeffs, n->length, e); }

// 2 c = A * B + (the sums over |i - j| = k), exactly in integers: c on the grid 2^(ea + eb - 1), by
// FLINT's polynomial products: the fallback of grid_product() and the reference of its test.
inline void grid_product_flint(fmpz_poly_t c, const fmpz_poly_t A, const fmpz_poly_t B) {
  const slong la = A->length, lb = B->length;
  if (la == 0 || lb == 0) {
    fmpz_poly_zero(c);
    return;
  }
  thread_local integer_poly scratch_diff, scratch_rev;
  fmpz_poly_struct* diff = scratch_diff.p;
  fmpz_poly_struct* rev = scratch_rev.p;
  fmpz_poly_mul(c, A, B);
  fmpz_poly_reverse(rev, B, lb);
  fmpz_poly_mul(diff, A, rev);  // diff[l] = sum over i - j = l - (lb - 1) of A_i B_j
  const slong n = la + lb - 1;
  fmpz_poly_fit_length(c, n);
  for (slong k = c->length; k < n; ++k) fmpz_zero(c->coeffs + k);
  _fmpz_poly_set_length(c, n);
  for (slong k = 0; k < n; ++k) {
    const slong up = lb - 1 + k, down = lb - 1 - k;
    if (k < la && up < diff->length) fmpz_add(c->coeffs + k, c->coeffs + k, diff->coeffs + up);
    if (k > 0 && down >= 0 && down < diff->length) fmpz_add(c->coeffs + k, c->coeffs + k, diff->coeffs + down);
  }
  _fmpz_poly_normalise(c);
}

// 2 c = A * B + (the sums over |i - j| = k), exactly in integers (c distinct from A and B): the
// same integers as grid_product_flint(): on 52-bit pieces (chunked_grid_product()) for short
// factors whose coefficients fall off, else by kronecker_grid_product() where it takes the factors.
// With `allowance` (in units of the integers' products), the pieces' kernel may leave out
// products that sum to at most that and add their bound to `dropped` (chunked::leave_out()).
inline void grid_product(fmpz_poly_t c, const fmpz_poly_t A, const fmpz_poly_t B,
                         const mag_struct* allowance = nullptr, mag_struct* dropped = nullptr) {
  if (A->length == 0 || B->length == 0) {
    fmpz_poly_zero(c);
    return;
  }
  if (!chunked_grid_product(c, A, B, allowance, dropped) && !kronecker_grid_product(c, A, B))
    grid_product_flint(c, A, B);
}

// The model of 2^e sum n_k T_k (exact coefficients) with remainder `rem`.
inline void from_grid(chebyshev_model& out, const fmpz_poly_t n, slong e, const mag_t rem) {
  out.reserve_length(n->length);
  for (slong k = 0; k < n->length; ++k) {
    set_fmpz_2exp(arb_midref(out.coeff(k)), n->coeffs + k, e);
    mag_zero(arb_radref(out.coeff(k)));
  }
  mag_set(out.remainder(), rem);
}

// A factor of a product on its grid (`bits` bits below its largest coefficient): the integers n_k
// and the exponent e (to_grid), in `moved` the distance to the grid with the radii and the
// model's remainder, in `magnitude` sum |n_k| 2^e. A model that is a factor of several products
// (a state component, a body rate) is moved once (series_algebra keeps it with the model).
struct grid_factor {
  grid_factor() {
    mag_init(moved);
    mag_init(magnitude);
  }
  ~grid_factor() {
    mag_clear(moved);
    mag_clear(magnitude);
  }
  grid_factor(const grid_factor&) = delete;
  grid_factor& operator=(const grid_factor&) = delete;

  void set(const chebyshev_model& a, slong grid_bits) {
    bits = grid_bits;
    e = grid_exponent(a, grid_bits);
    to_grid(n.p, moved, a, e);
    mag_add(moved, moved, a.remainder());
    grid_magnitude(magnitude, n.p, e);
  }

  integer_poly n;
  slong e = 0, bits = 0;
  mag_t moved, magnitude;
};

// A model that multiply() moves to a grid: neither zero nor a constant (one coefficient, no
// remainder), which it multiplies otherwise.
inline bool takes_grid(const chebyshev_model& a) {
  return !a.is_zero() && !(a.length() == 1 && mag_is_zero(a.remainder()));
}

// out = a b of two factors on their grids (A and B may be one): the remainder
// |(p + e)(q + d) - p q| <= sup|p| |d| + |e| (sup|q| + |d|), and p q in integers (grid_product()),
// but for products of the integers' lowest pieces that sum to at most 2^-12 of that remainder
// (whose bound joins it). Those of the two lowest pieces' positions qualify: on the shipped
// scenes they sum to 2^-39 of the remainder or less, and are a fifth of the pieces' products.
inline void multiply_grids(chebyshev_model& out, const grid_factor& A, const grid_factor& B) {
  thread_local integer_poly scratch_c;
  fmpz_poly_struct* C = scratch_c.p;
  mag_value t, allowance, dropped;
  mag_add(t.m, B.magnitude, B.moved);
  mag_mul(t.m, t.m, A.moved);
  mag_addmul(t.m, A.magnitude, B.moved);
  mag_mul_2exp_si(allowance.m, t.m, -12 - (A.e + B.e));
  grid_product(C, A.n.p, B.n.p, allowance.m, dropped.m);
  mag_mul_2exp_si(dropped.m, dropped.m, A.e + B.e);
  mag_add(t.m, t.m, dropped.m);
  from_grid(out, C, A.e + B.e - 1, t.m);
}

// out = a x for a constant x (b's one coefficient), in balls at bits + 64.
inline void multiply_constant(chebyshev_model& out, const chebyshev_model& a, arb_srcptr c, slong bits) {
  out.reserve_length(a.length());
  const arf_struct* x = arb_midref(c);
  if (arb_is_exact(c) && !arf_is_zero(x) && arf_is_finite(x) && arf_bits(x) == 1) {
    // A signed power of two (a variable's derivative, 1): the rounding alone.
    const slong e = arf_abs_bound_lt_2exp_si(x) - 1;
    for (slong k = 0; k < a.length(); ++k) {
      arb_set_round(out.coeff(k), a.coeff(k), bits + 64);
      arb_mul_2exp_si(out.coeff(k), out.coeff(k), e);
      if (arf_sgn(x) < 0) arb_neg(out.coeff(k), out.coeff(k));
    }
    mag_mul_2exp_si(out.remainder(), a.remainder(), e);
    return;
  }
  for (slong k = 0; k < a.length(); ++k) arb_mul(out.coeff(k), a.coeff(k), c, bits + 64);
  mag_t m;
  mag_init(m);
  arb_get_mag(m, c);
  mag_mul(out.remainder(), a.remainder(), m);
  mag_clear(m);
}

// out = a b (out distinct from a and b), `bits` bits below each factor's largest coefficient:
// each factor is moved to its grid (grid_factor), then multiply_grids(). A constant factor is a
// scaling (multiply_constant()).
inline void multiply(chebyshev_model& out, const chebyshev_model& a, const chebyshev_model& b, slong bits) {
  if (a.is_zero() || b.is_zero()) {
    out.set_zero();
    return;
  }
  if (b.length() == 1 && mag_is_zero(b.remainder())) {
    multiply_constant(out, a, b.coeff(0), bits);
    return;
  }
  if (a.length() == 1 && mag_is_zero(a.remainder())) {
    multiply_constant(out, b, a.coeff(0), bits);
    return;
  }
  thread_local grid_factor scratch_a, scratch_b;
  scratch_a.set(a, bits);
  scratch_b.set(b, bits);
  multiply_grids(out, scratch_a, scratch_b);
}

// T_0(s), ..., T_{n-1}(s) at a point s in [-1, 1] (a ball, intersected with [-1, 1] first), from
// the three-term recurrence, each intersected with [-1, 1] (where the exact value lies) once its
// ball reaches beyond: the recurrence's widths grow like 2.4^k, but they multiply coefficients
// that decay faster (Clenshaw's algorithm would instead multiply the coefficients' own widths).
class chebyshev_values {
 public:
  chebyshev_values() = default;  // no values, for assign()
  chebyshev_values(slong n, const ball& s, slong prec) { assign(n, s, prec); }
  ~chebyshev_values() {
    if (T_) _arb_vec_clear(T_, capacity_);
  }
  chebyshev_values(const chebyshev_values&) = delete;
  chebyshev_values& operator=(const chebyshev_values&) = delete;

  // The values at s, in the storage kept (grown where n is longer): tables kept from row to row
  // take no allocation, where a new one took one per value at the working precision.
  void assign(slong n, const ball& s, slong prec) { assign_from(n, s, nullptr, prec); }
  // The same at fewer bits from a table at s of more: its values rounded to prec (each an
  // enclosure still, and tighter than the recurrence run at prec), the recurrence only beyond it.
  void assign_rounded(slong n, const ball& s, const chebyshev_values& finer, slong prec) {
    assign_from(n, s, &finer, prec);
  }

  slong length() const { return n_; }
  arb_srcptr get() const { return T_; }

 private:
  void assign_from(slong n, const ball& s, const chebyshev_values* finer, slong prec) {
    if (n > capacity_) {
      if (T_) _arb_vec_clear(T_, capacity_);
      T_ = _arb_vec_init(n);
      capacity_ = n;
    }
    n_ = n;
    ball unit, x;
    arb_zero_pm_one(unit.get());
    if (!arb_intersection(x.get(), s.get(), unit.get(), prec)) arb_set(x.get(), unit.get());
    const slong given = finer ? std::min(n, finer->n_) : 0;
    for (slong k = 0; k < given; ++k) arb_set_round(T_ + k, finer->T_ + k, prec);
    for (slong k = given; k < n; ++k) {
      if (k == 0) {
        arb_one(T_);
      } else if (k == 1) {
        arb_set(T_ + 1, x.get());
      } else {
        arb_mul(T_ + k, T_ + k - 1, x.get(), prec);
        arb_mul_2exp_si(T_ + k, T_ + k, 1);
        arb_sub(T_ + k, T_ + k, T_ + k - 2, prec);
        if (!inside_unit(T_ + k) && !arb_contains(unit.get(), T_ + k))
          arb_intersection(T_ + k, T_ + k, unit.get(), prec);
      }
    }
  }
  // A sufficient test of x in [-1, 1]: |mid| + rad <= 1 rounded up. Where it fails, arb_contains
  // decides exactly; where it holds, arb_contains would too, so the values are the same, at a
  // small part of arb_contains' cost (its exact endpoint arithmetic was most of the recurrence's).
  static bool inside_unit(arb_srcptr x) {
    mag_t m;
    mag_init(m);
    arf_get_mag(m, arb_midref(x));
    mag_add(m, m, arb_radref(x));
    const bool in = mag_cmp_2exp_si(m, 0) <= 0;
    mag_clear(m);
    return in;
  }

  slong n_ = 0, capacity_ = 0;
  arb_ptr T_ = nullptr;
};

// f(s) enclosed from its first `length` coefficients, the rest bounded by `tail` (>= the sum of
// their magnitudes, as length_above gives); the remainder included.
inline void evaluate_head(ball& out, const chebyshev_model& a, slong length, const mag_t tail,
                          const chebyshev_values& T, slong prec) {
  arb_dot(out.get(), nullptr, 0, a.coeffs(), 1, T.get(), 1, length, prec);
  arb_add_error_mag(out.get(), a.remainder());
  arb_add_error_mag(out.get(), tail);
}

// f(s) enclosed from the values T_k(s) (at least a's length of them); the remainder included.
inline void evaluate(ball& out, const chebyshev_model& a, const chebyshev_values& T, slong prec) {
  const mag_value no_tail;
  evaluate_head(out, a, a.length(), no_tail.m, T, prec);
}

// f(s) enclosed, s in [-1, 1] (a ball); the remainder included.
inline void evaluate(ball& out, const chebyshev_model& a, const ball& s, slong prec) {
  const chebyshev_values T(std::max<slong>(a.length(), 1), s, prec);
  evaluate(out, a, T, prec);
}

// The coefficients at `prec` bits (their rounding goes into their radii).
inline void round_coefficients(chebyshev_model& a, slong prec) {
  for (slong k = 0; k < a.length(); ++k) arb_set_round(a.coeff(k), a.coeff(k), prec);
}

// Drops the coefficients from `length` on into the remainder (|T_k| <= 1).
inline void truncate(chebyshev_model& a, slong length) {
  if (length >= a.length()) return;
  mag_t tail;
  mag_init(tail);
  coefficient_magnitude(tail, a, length);
  mag_add(a.remainder(), a.remainder(), tail);
  mag_clear(tail);
  a.resize(length);
}

// How many leading coefficients to keep so that the trailing ones' magnitudes sum to at most
// `level` (at least one kept); that sum into `tail`. The sum runs in doubles rounded up
// (magnitude_sum.hpp), against `level` as a double (exact: a mag has 30 bits); out of the doubles'
// range, in Arb's mag arithmetic.
inline slong length_above(const chebyshev_model& a, const mag_t level, mag_t tail) {
  double cap = 0;
  bool fast = magnitude::bound(level, cap);
  magnitude::upper_sum sum;
  slong keep = a.length();
  while (fast && keep > 1) {
    magnitude::upper_sum next = sum;
    fast = magnitude::add_ball(next, a.coeff(keep - 1));
    if (!fast || next.s > cap) break;
    sum = next;
    --keep;
  }
  if (fast) {
    mag_set_d(tail, sum.s);
    return keep;
  }
  mag_t t;
  mag_init(t);
  mag_zero(tail);
  keep = a.length();
  while (keep > 1) {
    arb_get_mag(t, a.coeff(keep - 1));
    mag_add(t, tail, t);
    if (mag_cmp(t, level) > 0) break;
    mag_swap(tail, t);
    --keep;
  }
  mag_clear(t);
  return keep;
}

// Drops the trailing coefficients whose magnitudes sum to at most `level` into the remainder.
inline void truncate_below(chebyshev_model& a, const mag_t level) {
  mag_t tail;
  mag_init(tail);
  const slong keep = length_above(a, level, tail);
  if (keep < a.length()) {
    mag_add(a.remainder(), a.remainder(), tail);
    a.resize(keep);
  }
  mag_clear(tail);
}

}  // namespace eulervop::detail

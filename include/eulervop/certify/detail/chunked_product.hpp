// The exact Chebyshev product of two integer polynomials (grid_product() in chebyshev_model.hpp)
// term by term on 52-bit pieces, for the short factors of decaying coefficients that a segment's
// models are. Each coefficient is cut into signed pieces of 52 bits (A_i = sum_c a_ic 2^(52 c),
// every a_ic of A_i's sign), and for each pair of piece positions (c, e)
//   conv_{c+e}[i + j] += a_ic b_je,   corr_{c+e}[i - j] += a_ic b_je,
// in 128-bit integers: a piece product is below 2^104 in magnitude and a sum has at most
// max_length max_pieces of them, so nothing overflows and no carry is propagated until the end,
// where 2 c_k = conv[k] + corr[k] + corr[-k] (the sums over i + j = k and |i - j| = k) is put
// together from its columns as one integer.
//
// Why beside the Kronecker kernel (kronecker_product.hpp): a Kronecker slot is as wide as the
// largest coefficient's products, while a segment's coefficients fall off, on the paper scene
// from 145 bits at k = 0 to about 30 at its degree 41: most of them are one or two pieces. There
// the pieces' products cost 0.66 of the Kronecker kernel's (42 coefficients on a grid 145 bits
// below the largest, decaying by 113 bits; docs/certified.md, "Where rounding goes"). Where the
// coefficients do not fall off, or the factors are long, the Kronecker kernel's subquadratic
// integer products win, and grid_product() takes it (worth()).
#pragma once

#include <eulervop/certify/detail/kronecker_product.hpp>

#include <eulervop/certify/ball.hpp>

#include <arb.h>
#include <flint/fmpz.h>
#include <flint/fmpz_poly.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace eulervop::detail {

namespace chunked {

constexpr unsigned piece_bits = 52;
constexpr unsigned max_pieces = 4;      // coefficients of at most 208 bits
constexpr slong max_length = 96;        // beyond, the Kronecker kernel (measured: 0.99 at 128)
// A column's sum has at most max_length max_pieces terms (below 2^113), 2 c_k three such sums, and
// the columns reach 2^(52 (2 max_pieces - 2)): 2 c_k is below 2^431, eight limbs with the sign.
constexpr mp_size_t sum_limbs = 8;
using wide = __int128;

// A factor's pieces: piece c of coefficient i at d[c n + i], and count[c] = 1 + the last i whose
// piece c is nonzero (0 if none).
struct pieces {
  std::vector<std::int64_t> d;
  slong n = 0, count[max_pieces] = {};
  unsigned positions = 0;  // 1 + the highest nonzero piece position
  slong total = 0;         // sum of count[c]: the work of a product is total(A) total(B)
  // sum_i |piece c of A_i|: below max_length 2^52 < 2^59, exact.
  std::uint64_t size[max_pieces] = {};

  // False (and the factor unusable) where a coefficient needs more than max_pieces pieces.
  bool set(const fmpz* a, slong len) {
    n = len;
    d.assign(static_cast<std::size_t>(len) * max_pieces, 0);
    positions = 0;
    total = 0;
    for (slong& c : count) c = 0;
    for (std::uint64_t& m : size) m = 0;
    for (slong i = 0; i < len; ++i) {
      mp_limb_t small;
      const kronecker::limbs_of v(a + i, small);
      if (v.n == 0) continue;
      const auto bits = static_cast<ulong>(v.n) * kronecker::limb_bits - static_cast<ulong>(__builtin_clzll(v.d[v.n - 1]));
      const auto used = static_cast<unsigned>((bits + piece_bits - 1) / piece_bits);
      if (used > max_pieces) return false;
      for (unsigned c = 0; c < used; ++c) {
        const ulong bit = c * piece_bits;
        const auto w = static_cast<mp_size_t>(bit / kronecker::limb_bits);
        const unsigned r = bit % kronecker::limb_bits;
        std::uint64_t x = v.d[w] >> r;
        if (r + piece_bits > kronecker::limb_bits && w + 1 < v.n) x |= v.d[w + 1] << (kronecker::limb_bits - r);
        x &= (std::uint64_t{1} << piece_bits) - 1;
        if (x == 0) continue;
        d[c * static_cast<std::size_t>(len) + static_cast<std::size_t>(i)] =
            v.negative ? -static_cast<std::int64_t>(x) : static_cast<std::int64_t>(x);
        count[c] = i + 1;
        size[c] += x;
        positions = std::max(positions, c + 1);
      }
    }
    for (slong c : count) total += c;
    return true;
  }
  const std::int64_t* piece(unsigned c) const { return d.data() + c * static_cast<std::size_t>(n); }
};

// The two's complement of sum_col v[col] 2^(52 col) on out[0, sum_limbs): the columns' low 52 bits
// in turn, each column's rest carried into the next.
inline void put_together(mp_limb_t* out, const wide* v, unsigned columns) {
  for (mp_size_t l = 0; l < sum_limbs; ++l) out[l] = 0;
  wide carry = 0;
  const auto put = [&](std::uint64_t field, ulong bit, unsigned width) {  // field < 2^width, at bit
    const auto w = static_cast<mp_size_t>(bit / kronecker::limb_bits);
    const unsigned r = bit % kronecker::limb_bits;
    out[w] |= field << r;
    if (r + width > kronecker::limb_bits) out[w + 1] |= field >> (kronecker::limb_bits - r);
  };
  for (unsigned col = 0; col < columns; ++col) {
    const wide t = v[col] + carry;
    put(static_cast<std::uint64_t>(t) & ((std::uint64_t{1} << piece_bits) - 1), col * piece_bits, piece_bits);
    carry = t >> piece_bits;  // arithmetic: t = carry 2^52 + its low bits
  }
  // The rest (below 2^(128 - 52) in magnitude) in two's complement up to the last limb.
  const ulong bit = columns * piece_bits;
  const auto w = static_cast<mp_size_t>(bit / kronecker::limb_bits);
  const unsigned r = bit % kronecker::limb_bits;
  const auto lo = static_cast<std::uint64_t>(carry), hi = static_cast<std::uint64_t>(static_cast<unsigned __int128>(carry) >> 64);
  const std::uint64_t fill = carry < 0 ? ~std::uint64_t{0} : 0;
  out[w] |= lo << r;
  for (mp_size_t l = w + 1; l < sum_limbs; ++l) {
    const mp_size_t s = l - w;  // words of carry 2^r above limb w
    const std::uint64_t low_part = s == 1 ? lo : s == 2 ? hi : fill, high_part = s == 1 ? hi : fill;
    out[l] = r == 0 ? (s == 1 ? hi : fill) : (high_part << r) | (low_part >> (kronecker::limb_bits - r));
  }
}

// Whether the pieces' products cost less than the Kronecker kernel's for these factors, by a
// model of both fitted to their times (lengths 20 to 160, 64 to 250 bits, with and without decay):
// a pair of pieces costs about 24 times a bit of a Kronecker pair of coefficients. It takes the
// paper scene's and spacecraft-attitude's factors (42 coefficients from 145 bits down, 84 to 95
// pieces: 0.66 of the Kronecker kernel's time), and leaves to the Kronecker kernel factors that do
// not fall off (42 of 145 bits: 1.09) and long ones.
inline bool worth(const pieces& a, const pieces& b, ulong bits_a, ulong bits_b) {
  const auto pairs = static_cast<double>(a.n) * static_cast<double>(b.n);
  return 24.0 * static_cast<double>(a.total) * static_cast<double>(b.total) <=
         pairs * static_cast<double>(bits_a + bits_b) / 2;
}

// Which pairs of piece positions a product may leave out: those whose products sum to at most
// `allowance` / 16 (16 pairs at most, so all of them to at most `allowance`), in units of the
// factors' integers' products. Their sum's bound sum_i |a_ip| sum_j |b_jq| 2^(52 (p + q)) is
// added to `dropped`: each left-out product changes 2 c_k (once in conv, once in corr), so the
// product's coefficients c_k move by at most that sum in all.
struct left_out {
  bool pair[max_pieces][max_pieces] = {};
};
inline void leave_out(left_out& out, const pieces& pa, const pieces& pb, const mag_t allowance, mag_t dropped) {
  mag_value bound, share;
  mag_mul_2exp_si(share.m, allowance, -4);
  for (unsigned p = 0; p < pa.positions; ++p)
    for (unsigned q = 0; q < pb.positions; ++q) {
      const unsigned __int128 m = static_cast<unsigned __int128>(pa.size[p]) * pb.size[q];  // < 2^118
      const auto hi = static_cast<ulong>(m >> 60), lo = static_cast<ulong>(m & ((ulong{1} << 60) - 1));
      // m <= (hi + 1) 2^60 where lo > 0; hi < 2^58.
      mag_set_ui_2exp_si(bound.m, hi + (lo != 0 ? 1 : 0), 60 + static_cast<slong>(piece_bits * (p + q)));
      if (m == 0 || mag_cmp(bound.m, share.m) > 0) continue;
      out.pair[p][q] = true;
      mag_add(dropped, dropped, bound.m);
    }
}

// conv and corr (columns side by side per slot, corr at index i - j + lb - 1) += the pieces'
// products, but for the pairs of positions left out.
inline void accumulate(wide* conv, wide* corr, const pieces& pa, const pieces& pb, unsigned columns,
                       const left_out& skip) {
  for (unsigned p = 0; p < pa.positions; ++p)
    for (unsigned q = 0; q < pb.positions; ++q) {
      if (skip.pair[p][q]) continue;
      const std::int64_t *a = pa.piece(p), *b = pb.piece(q);
      const slong na = pa.count[p], nb = pb.count[q];
      wide* up = conv + (p + q);
      wide* down = corr + (p + q) + (pb.n - 1) * columns;  // at index i - j
      for (slong i = 0; i < na; ++i) {
        const std::int64_t x = a[i];
        if (x == 0) continue;
        wide *u = up + i * columns, *w = down + i * columns;
        for (slong j = 0; j < nb; ++j) {
          const wide product = static_cast<wide>(x) * b[j];
          u[j * columns] += product;
          w[-j * static_cast<slong>(columns)] += product;
        }
      }
    }
}

// The product as grid_product() defines it; false, c untouched, where a factor is longer than
// max_length or a coefficient wider than max_pieces pieces, or (only_where_worth) where the
// Kronecker kernel would cost less. Exact, unless `allowance` is given: then the pairs of piece
// positions whose products sum to at most `allowance` are left out and their bound is added to
// `dropped` (both in units of the integers' products; leave_out()).
inline bool product(fmpz_poly_t c, const fmpz_poly_t A, const fmpz_poly_t B, bool only_where_worth,
                    const mag_struct* allowance = nullptr, mag_struct* dropped = nullptr) {
  const slong la = A->length, lb = B->length;
  if (la > max_length || lb > max_length) return false;
  thread_local pieces tl_a, tl_b;
  thread_local std::vector<wide> tl_conv, tl_corr;
  pieces &pa = tl_a, &pb = tl_b;  // thread_local once: in a loaded module each use is a call
  std::vector<wide>&conv_v = tl_conv, &corr_v = tl_corr;
  if (!pa.set(A->coeffs, la) || !pb.set(B->coeffs, lb)) return false;
  if (only_where_worth && !worth(pa, pb, static_cast<ulong>(FLINT_ABS(_fmpz_vec_max_bits(A->coeffs, la))),
                                 static_cast<ulong>(FLINT_ABS(_fmpz_vec_max_bits(B->coeffs, lb)))))
    return false;
  const slong slots = la + lb - 1;
  const unsigned columns = pa.positions + pb.positions - 1;
  conv_v.assign(static_cast<std::size_t>(columns * slots), 0);
  corr_v.assign(static_cast<std::size_t>(columns * slots), 0);
  wide *const conv = conv_v.data(), *const corr = corr_v.data();
  left_out skip;
  if (allowance != nullptr) leave_out(skip, pa, pb, allowance, dropped);
  accumulate(conv, corr, pa, pb, columns, skip);
  fmpz_poly_fit_length(c, slots);
  mp_limb_t sum[sum_limbs], scratch[sum_limbs];
  wide v[2 * max_pieces - 1];
  for (slong k = 0; k < slots; ++k) {  // 2 c_k = conv[k] + corr[k] + corr[-k]
    const wide* up = conv + k * columns;
    for (unsigned col = 0; col < columns; ++col) v[col] = up[col];
    if (k < la)
      for (unsigned col = 0; col < columns; ++col) v[col] += corr[(lb - 1 + k) * columns + col];
    if (k > 0 && k < lb)
      for (unsigned col = 0; col < columns; ++col) v[col] += corr[(lb - 1 - k) * columns + col];
    put_together(sum, v, columns);
    const mp_limb_t* terms[1] = {sum};
    kronecker::set_sum(c->coeffs + k, terms, 1, sum_limbs, scratch);
  }
  _fmpz_poly_set_length(c, slots);
  _fmpz_poly_normalise(c);
  return true;
}

}  // namespace chunked

// 2 c_k = sum_{i+j=k} A_i B_j + sum_{|i-j|=k} A_i B_j exactly, as grid_product() (c distinct from A
// and B, both nonzero and normalised); false, c untouched, where the factors are beyond the
// pieces' limits or the Kronecker kernel would cost less (chunked::worth()).
inline bool chunked_grid_product(fmpz_poly_t c, const fmpz_poly_t A, const fmpz_poly_t B,
                                 const mag_struct* allowance = nullptr, mag_struct* dropped = nullptr) {
  return chunked::product(c, A, B, true, allowance, dropped);
}

}  // namespace eulervop::detail

// The exact Chebyshev product of two integer polynomials (grid_product() in chebyshev_model.hpp)
// by Kronecker substitution on GMP's limbs (Harvey, "Faster polynomial multiplication via
// multipoint Kronecker substitution", J. Symbolic Comput. 44, 2009: KS1 and KS2). With slots of
// b bits, X = A(2^b) = sum_i A_i 2^(i b) and Y = B(2^b) give X Y = C(2^b), C = A B, and the
// packing of B reversed gives the sums over i - j = k. A slot of b bits would have to hold a whole
// C_k; evaluated at 2^b and at -2^b, C(2^b) + C(-2^b) = 2 sum_k C_2k 2^(2 k b) and
// C(2^b) - C(-2^b) = 2^(b + 1) sum_k C_(2k+1) 2^(2 k b), so slots of 2 b bits suffice: b is half
// a C_k, and each convolution is two integer products of half the length (GMP's mpn_mul,
// subquadratic: 2 products of 98 limbs cost 0.68 of one of 196, the paper scene's size).
//
// FLINT's fmpz_poly_mul does KS1, around it packs through its own bit packer, allocates its limbs
// with calloc and unpacks every coefficient into a freshly reallocated GMP integer; here the
// packings, the products' limbs and their signed slots stay in scratch kept per thread, and the
// three sums of 2 c_k are formed on the slots' limbs before one write per coefficient. The
// integers are the same (the product is exact); only the way to them differs.
//
// Signs: each factor is packed as its positive and its negative terms apart, X = P - N, and the
// products are read in two's complement, each slot signed, a negative slot carrying one into the
// next. With w = bits(A) + bits(B) + ceil(log2(min(la, lb))) + 1, every sum of products has
// |C_k| < min(la, lb) 2^(bits(A) + bits(B)) <= 2^(w - 1), and b = max(ceil(w / 2), bits(A), bits(B)).
#pragma once

#include <eulervop/certify/detail/fixed_point.hpp>

#include <flint/fmpz.h>
#include <flint/fmpz_poly.h>
#include <flint/fmpz_vec.h>
#include <gmp.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

namespace eulervop::detail::kronecker {

constexpr ulong limb_bits = FLINT_BITS;

// The largest packed factor taken, in limbs (the scratch, kept per thread, grows to at most about
// 17 times this: 2.2 MB); FLINT takes longer factors, where its Schoenhage-Strassen products may
// win anyway.
constexpr mp_size_t max_limbs = 1 << 14;

// The magnitude's limbs and the sign of an fmpz (its small value in `small` when it has no mpz).
struct limbs_of {
  limbs_of(const fmpz* x, mp_limb_t& small) {
    if (!COEFF_IS_MPZ(*x)) {
      small = *x < 0 ? -static_cast<mp_limb_t>(*x) : static_cast<mp_limb_t>(*x);
      d = &small;
      n = *x == 0 ? 0 : 1;
      negative = *x < 0;
    } else {
      const __mpz_struct* z = COEFF_TO_PTR(*x);
      d = z->_mp_d;
      n = std::abs(z->_mp_size);
      negative = z->_mp_size < 0;
    }
  }
  const mp_limb_t* d;
  mp_size_t n;
  bool negative;
};

// x[...] |= d (n limbs) shifted left by `bit` bits.
inline void or_shifted(mp_limb_t* x, const mp_limb_t* d, mp_size_t n, ulong bit) {
  mp_limb_t* p = x + bit / limb_bits;
  const unsigned r = bit % limb_bits;
  if (r == 0) {
    for (mp_size_t j = 0; j < n; ++j) p[j] |= d[j];
    return;
  }
  for (mp_size_t j = 0; j < n; ++j) {
    p[j] |= d[j] << r;
    p[j + 1] |= d[j] >> (limb_bits - r);
  }
}

// x = |sum_i a_i (+-2^w)^i| on n limbs (the point -2^w when `minus`), a taken in reverse order
// when `reverse`, every |a_i| < 2^w; neg is scratch of n limbs. Returns the sign (+1 or -1: the
// last term outweighs the others, |a_{len-1}| 2^((len-1) w) > sum_{i<len-1} (2^w - 1) 2^(i w)).
// *used becomes the length without high zero limbs.
inline int pack(mp_limb_t* x, mp_limb_t* neg, mp_size_t n, mp_size_t* used, const fmpz* a, slong len,
                ulong w, bool reverse, bool minus) {
  std::fill(x, x + n, mp_limb_t{0});
  std::fill(neg, neg + n, mp_limb_t{0});
  bool any_negative = false;
  for (slong i = 0; i < len; ++i) {
    mp_limb_t small;
    const limbs_of v(a + (reverse ? len - 1 - i : i), small);
    if (v.n == 0) continue;
    const bool negative = v.negative != (minus && i % 2 == 1);
    any_negative = any_negative || negative;
    or_shifted(negative ? neg : x, v.d, v.n, static_cast<ulong>(i) * w);
  }
  int sign = 1;
  if (any_negative) {
    if (mpn_cmp(x, neg, n) >= 0) {
      mpn_sub_n(x, x, neg, n);
    } else {
      mpn_sub_n(x, neg, x, n);
      sign = -1;
    }
  }
  mp_size_t m = n;
  while (m > 0 && x[m - 1] == 0) --m;
  *used = m;
  return sign;
}

// The signed slots of z = sum_k C_k 2^(k w), |C_k| < 2^(w - 1), each in two's complement on L
// limbs (64 L >= w + 2), slot k at out + k stride: z's low w bits are C_0 mod 2^w, and a negative
// C_0 carries one into the next slot. z is held in two's complement on enough limbs to cover every
// slot.
inline void unpack(mp_limb_t* out, mp_size_t stride, const mp_limb_t* z, slong slots, ulong w, mp_size_t L) {
  const mp_size_t m = static_cast<mp_size_t>((w + limb_bits - 1) / limb_bits);  // the field's limbs
  const unsigned top = w % limb_bits;
  const mp_limb_t mask = top == 0 ? ~mp_limb_t{0} : (mp_limb_t{1} << top) - 1;  // of limb m - 1
  const unsigned sign = (w - 1) % limb_bits;                                    // bit w - 1, in limb m - 1
  mp_limb_t carry = 0;
  for (slong k = 0; k < slots; ++k) {
    mp_limb_t* t = out + k * stride;
    const ulong o = static_cast<ulong>(k) * w;
    const mp_limb_t* p = z + o / limb_bits;
    const unsigned r = o % limb_bits;
    if (r == 0)
      std::copy(p, p + m, t);
    else
      for (mp_size_t j = 0; j < m; ++j) t[j] = (p[j] >> r) | (p[j + 1] << (limb_bits - r));
    t[m - 1] &= mask;
    mp_size_t j = 0;  // v = field + carry; v = 2^w only from a field of ones, and then C = 0
    if (carry != 0)
      while (j < m && ++t[j] == 0) ++j;
    if (carry != 0 && (j == m || (top != 0 && t[m - 1] > mask))) {
      std::fill(t, t + L, mp_limb_t{0});
      continue;  // the carry stays one
    }
    carry = (t[m - 1] >> sign) & 1;  // v >= 2^(w - 1): C = v - 2^w, v's bits with ones above
    if (carry != 0) t[m - 1] |= ~mask;
    std::fill(t + m, t + L, carry != 0 ? ~mp_limb_t{0} : 0);
  }
}

// |x y| into z (nx + ny limbs), then z in two's complement of sign(x) sign(y) on nz >= nx + ny
// limbs. x and y as pack() left them.
inline void signed_product(mp_limb_t* z, mp_size_t nz, const mp_limb_t* x, mp_size_t nx, int sx, const mp_limb_t* y,
                           mp_size_t ny, int sy) {
  if (nx < ny) {
    std::swap(x, y);
    std::swap(nx, ny);
  }
  if (x == y || (nx == ny && mpn_cmp(x, y, nx) == 0))
    mpn_sqr(z, x, nx);
  else
    mpn_mul(z, x, nx, y, ny);
  std::fill(z + nx + ny, z + nz, mp_limb_t{0});
  if (sx * sy < 0) mpn_neg(z, z, nz);
}

// z >>= s on nz limbs in two's complement (the sign kept).
inline void shift_right(mp_limb_t* z, mp_size_t nz, ulong s) {
  const mp_limb_t fill = (z[nz - 1] >> (limb_bits - 1)) != 0 ? ~mp_limb_t{0} : 0;
  const auto q = static_cast<mp_size_t>(s / limb_bits);
  const unsigned r = s % limb_bits;
  if (q > 0) {
    std::copy(z + q, z + nz, z);
    std::fill(z + nz - q, z + nz, fill);
  }
  if (r != 0) {
    mpn_rshift(z, z, nz, r);
    z[nz - 1] |= fill << (limb_bits - r);
  }
}

// The slots C_k of Z(+2^b) and Z(-2^b) (zp, zm, two's complement on nz limbs; zp is overwritten),
// Z = sum_k C_k x^k, |C_k| < 2^(2 b - 1): (zp + zm) / 2 = sum_k C_{2k} 2^(2 k b) and
// (zp - zm) / 2^(b + 1) = sum_k C_{2k+1} 2^(2 k b) (Harvey, section 3, "KS2").
inline void unpack_two_point(mp_limb_t* out, mp_limb_t* zp, mp_limb_t* zm, mp_size_t nz, slong slots, ulong b,
                             mp_size_t L) {
  mpn_sub_n(zm, zp, zm, nz);  // zp - zm
  mpn_add_n(zp, zp, zp, nz);
  mpn_sub_n(zp, zp, zm, nz);  // zp + zm = 2 zp - (zp - zm)
  shift_right(zp, nz, 1);
  shift_right(zm, nz, b + 1);
  unpack(out, 2 * L, zp, (slots + 1) / 2, 2 * b, L);
  unpack(out + L, 2 * L, zm, slots / 2, 2 * b, L);
}

// c = the sum of L-limb two's complement numbers (from `count` of them, at s[0..count)), as an fmpz.
inline void set_sum(fmpz* c, const mp_limb_t* const* s, int count, mp_size_t L, mp_limb_t* t) {
  std::copy(s[0], s[0] + L, t);
  for (int i = 1; i < count; ++i) mpn_add_n(t, t, s[i], L);
  const bool negative = (t[L - 1] >> (limb_bits - 1)) != 0;
  if (negative) mpn_neg(t, t, L);
  set_signed_limbs(c, t, L, negative);
}

}  // namespace eulervop::detail::kronecker

namespace eulervop::detail {

// 2 c_k = sum_{i+j=k} A_i B_j + sum_{|i-j|=k} A_i B_j exactly, as grid_product() (c distinct from A
// and B, both nonzero and normalised); false, c untouched, where a packed factor would exceed
// kronecker::max_limbs.
inline bool kronecker_grid_product(fmpz_poly_t c, const fmpz_poly_t A, const fmpz_poly_t B) {
  using namespace kronecker;
  const slong la = A->length, lb = B->length, slots = la + lb - 1;
  const auto ba = static_cast<ulong>(FLINT_ABS(_fmpz_vec_max_bits(A->coeffs, la)));
  const auto bb = static_cast<ulong>(FLINT_ABS(_fmpz_vec_max_bits(B->coeffs, lb)));
  // Every slot's sum below 2^(2 b - 1); every coefficient below 2^b (so that pack() holds).
  const ulong w = ba + bb + static_cast<ulong>(FLINT_CLOG2(std::min(la, lb))) + 1;
  const ulong b = std::max({(w + 1) / 2, ba, bb});
  const auto limbs = [&](slong len) { return static_cast<mp_size_t>(static_cast<ulong>(len) * b / limb_bits + 2); };
  const mp_size_t nx = limbs(la), ny = limbs(lb), nz = nx + ny + 1;  // z: every slot, and a sign bit
  const mp_size_t L = static_cast<mp_size_t>((2 * b + 2 + limb_bits - 1) / limb_bits);
  if (nx > max_limbs || ny > max_limbs) return false;
  thread_local std::vector<mp_limb_t> scratch;
  scratch.resize(static_cast<std::size_t>(2 * nx + 2 * ny + std::max(nx, ny) + 2 * nz + (2 * slots + 1) * L));
  mp_limb_t *xp = scratch.data(), *xm = xp + nx, *yp = xm + nx, *ym = yp + ny, *neg = ym + ny;
  mp_limb_t *zp = neg + std::max(nx, ny), *zm = zp + nz, *s1 = zm + nz, *s2 = s1 + slots * L, *t = s2 + slots * L;
  mp_size_t uxp, uxm, uyp, uym;
  const int sxp = pack(xp, neg, nx, &uxp, A->coeffs, la, b, false, false);
  const int sxm = pack(xm, neg, nx, &uxm, A->coeffs, la, b, false, true);
  for (int reverse = 0; reverse < 2; ++reverse) {  // slot k: the sum over i + j = k; then over i - j = k - (lb - 1)
    const int syp = pack(yp, neg, ny, &uyp, B->coeffs, lb, b, reverse, false);
    const int sym = pack(ym, neg, ny, &uym, B->coeffs, lb, b, reverse, true);
    signed_product(zp, nz, xp, uxp, sxp, yp, uyp, syp);
    signed_product(zm, nz, xm, uxm, sxm, ym, uym, sym);
    unpack_two_point(reverse ? s2 : s1, zp, zm, nz, slots, b, L);
  }
  fmpz_poly_fit_length(c, slots);
  for (slong k = 0; k < slots; ++k) {
    const mp_limb_t* terms[3] = {s1 + k * L};
    int count = 1;
    if (k < la) terms[count++] = s2 + (lb - 1 + k) * L;
    if (k > 0 && k < lb) terms[count++] = s2 + (lb - 1 - k) * L;
    set_sum(c->coeffs + k, terms, count, L, t);
  }
  _fmpz_poly_set_length(c, slots);
  _fmpz_poly_normalise(c);
  return true;
}

}  // namespace eulervop::detail

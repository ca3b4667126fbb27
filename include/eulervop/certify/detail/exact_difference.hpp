// Fixed-size unsigned integers of four 64-bit limbs, for the residuals of the linear flow
// (integer_sum_residual.hpp): the product M d of the half-length's top 128 bits and a 128-bit
// sum, its scaling by a power of two rounded down, and sums of products of a 128-bit and a 64-bit
// integer, all exact; then a magnitude as Arb's mag, rounded up. In unsigned __int128 arithmetic:
// at these sizes GMP's calls cost more than the arithmetic.
#pragma once

#include <mag.h>

#include <bit>
#include <cstdint>

namespace eulervop::detail {

using wide_uint = unsigned __int128;

// An unsigned 256-bit integer, least significant limb first.
struct limbs256 {
  std::uint64_t w[4] = {0, 0, 0, 0};
};

// a b exactly (schoolbook on 64-bit halves; every partial sum below is < 2^128).
inline limbs256 multiply(wide_uint a, wide_uint b) {
  const auto lo = [](wide_uint x) { return static_cast<wide_uint>(static_cast<std::uint64_t>(x)); };
  const wide_uint a0 = lo(a), a1 = a >> 64, b0 = lo(b), b1 = b >> 64;
  const wide_uint p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
  const wide_uint mid = (p00 >> 64) + lo(p01) + lo(p10);                     // < 3 2^64
  const wide_uint high = (mid >> 64) + (p01 >> 64) + (p10 >> 64) + lo(p11);  // < 4 2^64
  return {{static_cast<std::uint64_t>(p00), static_cast<std::uint64_t>(mid), static_cast<std::uint64_t>(high),
           static_cast<std::uint64_t>((p11 >> 64) + (high >> 64))}};
}

// acc += a b and acc += a, exactly (the caller keeps acc below 2^256).
inline void add_product(limbs256& acc, wide_uint a, std::uint64_t b) {
  const wide_uint p0 = static_cast<wide_uint>(static_cast<std::uint64_t>(a)) * b, p1 = (a >> 64) * b;
  wide_uint t = static_cast<wide_uint>(acc.w[0]) + static_cast<std::uint64_t>(p0);
  acc.w[0] = static_cast<std::uint64_t>(t);
  t = (t >> 64) + acc.w[1] + (p0 >> 64) + static_cast<std::uint64_t>(p1);
  acc.w[1] = static_cast<std::uint64_t>(t);
  t = (t >> 64) + acc.w[2] + (p1 >> 64);
  acc.w[2] = static_cast<std::uint64_t>(t);
  acc.w[3] += static_cast<std::uint64_t>(t >> 64);
}
inline void add(limbs256& acc, wide_uint a) {
  wide_uint t = static_cast<wide_uint>(acc.w[0]) + static_cast<std::uint64_t>(a);
  acc.w[0] = static_cast<std::uint64_t>(t);
  t = (t >> 64) + acc.w[1] + (a >> 64);
  acc.w[1] = static_cast<std::uint64_t>(t);
  t = (t >> 64) + acc.w[2];
  acc.w[2] = static_cast<std::uint64_t>(t);
  acc.w[3] += static_cast<std::uint64_t>(t >> 64);
}

inline void add(limbs256& acc, const limbs256& x) {
  wide_uint t = 0;
  for (int i = 0; i < 4; ++i) {
    t += static_cast<wide_uint>(acc.w[i]) + x.w[i];
    acc.w[i] = static_cast<std::uint64_t>(t);
    t >>= 64;
  }
}

inline unsigned bit_length(const limbs256& x) {
  for (int i = 3; i >= 0; --i)
    if (x.w[i]) return 64 * static_cast<unsigned>(i) + static_cast<unsigned>(std::bit_width(x.w[i]));
  return 0;
}

// out = floor(x 2^-t) when it is below 2^bits (bits <= 128); false otherwise.
inline bool scaled_floor(wide_uint& out, const limbs256& x, long t, unsigned bits) {
  const unsigned n = bit_length(x);
  if (n == 0) {
    out = 0;
    return true;
  }
  if (t < 0) {
    if (n + static_cast<unsigned long>(-t) > bits) return false;
    out = ((static_cast<wide_uint>(x.w[1]) << 64) | x.w[0]) << -t;
    return true;
  }
  if (static_cast<unsigned long>(t) >= n) {
    out = 0;
    return true;
  }
  if (n - static_cast<unsigned long>(t) > bits) return false;
  const unsigned q = static_cast<unsigned>(t) / 64, b = static_cast<unsigned>(t) % 64;
  const auto limb = [&](unsigned i) -> wide_uint { return i < 4 ? x.w[i] : 0; };
  const wide_uint low = limb(q) | (limb(q + 1) << 64), top = limb(q + 2);
  out = b == 0 ? low : (low >> b) | (top << (128 - b));
  return true;
}

inline bool less(const limbs256& a, const limbs256& b) {
  for (int i = 3; i >= 0; --i)
    if (a.w[i] != b.w[i]) return a.w[i] < b.w[i];
  return false;
}

// a - b for a >= b.
inline limbs256 subtract(const limbs256& a, const limbs256& b) {
  limbs256 r;
  std::uint64_t borrow = 0;
  for (int i = 0; i < 4; ++i) {
    const wide_uint t = static_cast<wide_uint>(a.w[i]) - b.w[i] - borrow;
    r.w[i] = static_cast<std::uint64_t>(t);
    borrow = static_cast<std::uint64_t>(t >> 64) & 1;
  }
  return r;
}

// out >= x 2^e: x's top 62 bits plus one unit of the last (x < (floor(x / 2^s) + 1) 2^s), then
// Arb's rounding up.
inline void mag_set_limbs_2exp(mag_t out, const limbs256& x, slong e) {
  const unsigned n = bit_length(x);
  if (n <= 64) {
    mag_set_ui_2exp_si(out, x.w[0], e);
    return;
  }
  const unsigned s = n - 62, q = s / 64, b = s % 64;
  std::uint64_t top = x.w[q] >> b;
  if (b != 0 && q < 3) top |= x.w[q + 1] << (64 - b);
  mag_set_ui_2exp_si(out, (top & ((std::uint64_t{1} << 62) - 1)) + 1, e + static_cast<slong>(s));
}

}  // namespace eulervop::detail

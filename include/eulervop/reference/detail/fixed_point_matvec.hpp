// y = A x for quad (IEEE binary128) and MPFR matrices and vectors, in integer arithmetic.
//
// The reference integrator's residual in the wide type is a dense matrix-vector product, and it
// dominated the run time: soft-float quad costs about 20 ns per multiply or add (libgcc's
// __multf3 and __addtf3), and an MPFR fused multiply-add rounds, normalizes and manages
// temporaries on every term. Here each row of A and the vector x are scaled by powers of two
// into integers (A once, x per call, each by its own largest entry), the products are exact
// integer products and the sums exact integer sums: a fixed-point dot product in the manner of
// Kulisch's long accumulator, rounded to the wide type once at the end.
#pragma once

#include <eulervop/core/limb_arithmetic.hpp>
#include <eulervop/core/scalar.hpp>

#include <boost/multiprecision/gmp.hpp>

#include <gmp.h>
#include <mpfr.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

namespace eulervop::detail {

template <scalar T>
class fixed_point_matrix;

// Quad: the entries become signed 128-bit integers with 116 significant bits, split into 64-bit
// halves whose products are exact. Row r of A and x enter rounded to nearest, with absolute
// errors of at most 2^-117 max_k |A_rk| and 2^-117 max|x| (none for entries within 3 binades of
// those largest), the dropped low half of each product is below 2^-168 max_k |A_rk| max|x|, and
// the exact integer sum is rounded to quad once (twice, by at most an ulp each, where the result
// is not a normal number). So
//   |y_r - (A x)_r| <= 2^-116 n max_k |A_rk| max|x| + 2 ulp(y_r),
// the same order as n products and n sums in quad arithmetic, at a small fraction of the cost.
// The vector enters and the result leaves through their bit patterns (scaled_integer, rounded):
// integer shifts instead of soft-float conversions.
template <>
class fixed_point_matrix<quad> {
 public:
  // Bits of the integer images of A and x: products stay below 2^232 and the middle partial sums
  // below 2^127 for up to max_columns columns.
  static constexpr int fraction_bits = 116;
  static constexpr std::size_t max_columns = 1000;

  fixed_point_matrix() = default;
  // A row-major rows x cols matrix.
  fixed_point_matrix(const std::vector<quad>& a, std::size_t rows, std::size_t cols)
      : rows_(rows), cols_(cols), hi_(a.size()), lo_(a.size()), xh_(cols), xl_(cols) {
    if (cols > max_columns || a.size() != rows * cols)
      throw std::invalid_argument("fixed_point_matrix: at most 1000 columns, rows x cols entries");
    // Each row by its own largest entry: rows of the Picard matrix near the segment's start are
    // small (integrals over short intervals) and keep their relative accuracy.
    a_shift_.resize(rows);
    // The largest entry and the integers from the bit patterns, as for x in multiply(): the
    // same integers as nearest_integer(a 2^shift), without soft-float operations (a third of the
    // matrices' start-up in quad).
    for (std::size_t r = 0; r < rows; ++r) {
      unsigned __int128 max_bits = 0;
      for (std::size_t k = 0; k < cols; ++k) max_bits = std::max(max_bits, magnitude_bits(a[r * cols + k]));
      if (max_bits >= infinity_bits) throw std::invalid_argument("fixed_point_matrix: an entry is not finite");
      a_shift_[r] = max_bits > 0 ? shift_for(from_bits(max_bits)) : 0;
      for (std::size_t k = 0; k < cols; ++k)
        split(scaled_integer(a[r * cols + k], a_shift_[r]), hi_[r * cols + k], lo_[r * cols + k]);
    }
  }

  std::size_t rows() const { return rows_; }
  std::size_t cols() const { return cols_; }

  // y[r] = sum_k A[r][k] x[k] for rows [first_row, rows). Not const: x is split into scratch
  // storage (one object per thread).
  void multiply(const quad* x, quad* y, std::size_t first_row = 0) {
    // max |x_k| from the bit patterns: without the sign bit, binary128 magnitudes order as
    // unsigned integers (infinities and NaNs above every finite value), and integer comparisons
    // cost nothing beside soft-float ones.
    unsigned __int128 max_bits = 0;
    for (std::size_t k = 0; k < cols_; ++k) max_bits = std::max(max_bits, magnitude_bits(x[k]));
    if (max_bits == 0) {
      for (std::size_t r = first_row; r < rows_; ++r) y[r] = 0;
      return;
    }
    if (max_bits >= infinity_bits) {  // no fixed-point image: the product is not finite either
      for (std::size_t r = first_row; r < rows_; ++r) y[r] = std::numeric_limits<quad>::quiet_NaN();
      return;
    }
    __float128 xmax_value;
    std::memcpy(&xmax_value, &max_bits, sizeof xmax_value);
    const quad xmax(xmax_value);
    const int x_shift = shift_for(xmax);
    for (std::size_t k = 0; k < cols_; ++k) split(scaled_integer(x[k], x_shift), xh_[k], xl_[k]);
    for (std::size_t r = first_row; r < rows_; ++r) {
      // y = (H 2^128 + M 2^64) 2^-(a_shift + x_shift), with H and M exact integer sums.
      const std::int64_t* ah = &hi_[r * cols_];
      const std::uint64_t* al = &lo_[r * cols_];
      product_sum sum;
      for (std::size_t k = 0; k < cols_; ++k) sum.add(ah[k], al[k], xh_[k], xl_[k]);
      // Carry the middle sum's high half into H: y = (H 2^64 + m_low) 2^(64 - a_shift - x_shift).
      const __int128 M = sum.middle(), H = sum.H + (M >> 64);
      y[r] = rounded(H, static_cast<std::uint64_t>(M), 64 - a_shift_[r] - x_shift);
    }
  }

  // sum_k a[k] b[k b_stride] for two vectors that change with every call (b null: the plain sum
  // of a): both enter as integer images at their own scale, as x does in multiply(), and the
  // exact sum is rounded once, with the bound of multiply() for max|a| max|b| (of the sum of a:
  // 2^-117 n max|a| + 2 ulp).
  static quad dot(const quad* a, const quad* b, std::size_t b_stride, std::size_t n) {
    unsigned __int128 a_bits = 0, b_bits = 0;
    for (std::size_t k = 0; k < n; ++k) {
      a_bits = std::max(a_bits, magnitude_bits(a[k]));
      if (b) b_bits = std::max(b_bits, magnitude_bits(b[k * b_stride]));
    }
    if (a_bits == 0 || (b && b_bits == 0)) return 0;
    if (a_bits >= infinity_bits || b_bits >= infinity_bits) return std::numeric_limits<quad>::quiet_NaN();
    const int a_shift = shift_for(from_bits(a_bits));
    if (!b) {
      __int128 sum = 0;
      for (std::size_t k = 0; k < n; ++k) sum += scaled_integer(a[k], a_shift);
      return rounded(sum >> 64, static_cast<std::uint64_t>(sum), -a_shift);
    }
    const int b_shift = shift_for(from_bits(b_bits));
    product_sum sum;
    for (std::size_t k = 0; k < n; ++k) {
      std::int64_t ah, bh;
      std::uint64_t al, bl;
      split(scaled_integer(a[k], a_shift), ah, al);
      split(scaled_integer(b[k * b_stride], b_shift), bh, bl);
      sum.add(ah, al, bh, bl);
    }
    const __int128 M = sum.middle(), H = sum.H + (M >> 64);
    return rounded(H, static_cast<std::uint64_t>(M), 64 - a_shift - b_shift);
  }

  // sums[0] = dot(a, nullptr, 0, n) and sums[1 + i] = dot(a, b + i, b_stride, n) for i < count:
  // the same integers, so the same results, with a's integer images formed once instead of
  // count + 1 times (evaluate_segment's barycentric formula takes a denominator and D numerators
  // from the same weights at every sample).
  static void dots(const quad* a, const quad* b, std::size_t b_stride, std::size_t count, std::size_t n,
                   quad* sums) {
    unsigned __int128 a_bits = 0;
    for (std::size_t k = 0; k < n; ++k) a_bits = std::max(a_bits, magnitude_bits(a[k]));
    const bool a_finite = a_bits < infinity_bits;
    const int a_shift = a_bits > 0 && a_finite ? shift_for(from_bits(a_bits)) : 0;
    std::vector<__int128> images(a_bits > 0 && a_finite ? n : 0);
    __int128 sum = 0;
    for (std::size_t k = 0; k < images.size(); ++k) sum += images[k] = scaled_integer(a[k], a_shift);
    sums[0] = a_bits == 0 ? quad(0)
              : !a_finite ? std::numeric_limits<quad>::quiet_NaN()
                          : rounded(sum >> 64, static_cast<std::uint64_t>(sum), -a_shift);
    for (std::size_t i = 0; i < count; ++i) {
      const quad* bi = b + i;
      unsigned __int128 b_bits = 0;
      for (std::size_t k = 0; k < n; ++k) b_bits = std::max(b_bits, magnitude_bits(bi[k * b_stride]));
      if (a_bits == 0 || b_bits == 0) {
        sums[1 + i] = 0;
        continue;
      }
      if (!a_finite || b_bits >= infinity_bits) {
        sums[1 + i] = std::numeric_limits<quad>::quiet_NaN();
        continue;
      }
      const int b_shift = shift_for(from_bits(b_bits));
      product_sum ps;
      for (std::size_t k = 0; k < n; ++k) {
        std::int64_t ah, bh;
        std::uint64_t al, bl;
        split(images[k], ah, al);
        split(scaled_integer(bi[k * b_stride], b_shift), bh, bl);
        ps.add(ah, al, bh, bl);
      }
      const __int128 M = ps.middle(), H = ps.H + (M >> 64);
      sums[1 + i] = rounded(H, static_cast<std::uint64_t>(M), 64 - a_shift - b_shift);
    }
  }

  // v 2^shift rounded to the nearest integer, halves towards zero (as nearest_integer), from v's
  // bit pattern: a normal binary128 number is (2^112 + m) 2^(e - 16495), so this is an integer
  // shift and a comparison of the bits shifted out, with no soft-float operation (six of them
  // per entry through nearest_integer). Requires |v| 2^shift < 2^126; zero and subnormal v take
  // the soft-float way.
  static __int128 scaled_integer(const quad& v, int shift) {
    unsigned __int128 bits;
    std::memcpy(&bits, &v.backend().value(), sizeof bits);
    const int biased = static_cast<int>(bits >> 112) & 0x7fff;
    if (biased == 0) return nearest_integer(v * power_of_two(shift));
    const unsigned __int128 one = 1;
    const unsigned __int128 significand = (bits & ((one << 112) - 1)) | (one << 112);
    const int k = biased - 16495 + shift;  // v 2^shift = significand 2^k
    unsigned __int128 n = 0;
    if (k >= 0) {
      n = significand << k;
    } else if (k > -114) {  // below that, |v| 2^shift < 1/2
      n = significand >> -k;
      const unsigned __int128 rest = significand & ((one << -k) - 1), half = one << (-k - 1);
      if (rest > half) ++n;
    }
    return (bits >> 127) ? -static_cast<__int128>(n) : static_cast<__int128>(n);
  }

  // (H 2^64 + low) 2^e rounded to binary128 once (to nearest, ties to even), by assembling its
  // bit pattern from the integer's leading 113 bits; the soft-float way (two conversions, two
  // products and a sum, rounding twice) where the result would not be a normal number.
  static quad rounded(__int128 H, std::uint64_t low, int e) {
    const bool negative = H < 0;
    auto hi = static_cast<unsigned __int128>(H);
    if (negative) {  // the magnitude of the 192-bit two's complement integer
      low = ~low + 1;
      hi = ~hi + (low == 0 ? 1 : 0);
    }
    if (hi == 0) {
      const quad v = quad(static_cast<__float128>(low)) * power_of_two(e);  // exact: 64 bits
      return negative ? quad(-v) : v;
    }
    const auto top = static_cast<std::uint64_t>(hi >> 64);
    const int lz = top ? __builtin_clzll(top) : 64 + __builtin_clzll(static_cast<std::uint64_t>(hi));
    // Shifted so that the leading one is bit 127 of n_hi; n_lo holds what follows.
    unsigned __int128 n_hi = hi;
    std::uint64_t n_lo = low;
    if (lz > 0 && lz < 64) {
      n_hi = (hi << lz) | (low >> (64 - lz));
      n_lo = low << lz;
    } else if (lz >= 64) {
      n_hi = (hi << lz) | (static_cast<unsigned __int128>(low) << (lz - 64));
      n_lo = 0;
    }
    unsigned __int128 significand = n_hi >> 15;  // 113 bits
    const auto rest = static_cast<unsigned>(n_hi & 0x7fff);
    if (rest > 0x4000 || (rest == 0x4000 && (n_lo != 0 || (significand & 1)))) ++significand;
    int exponent = 191 - lz + e;  // of the leading bit
    if (significand >> 113) {
      significand >>= 1;
      ++exponent;
    }
    const int biased = exponent + 16383;
    if (biased < 1 || biased > 32766) {
      const quad v = quad(static_cast<__float128>(static_cast<__int128>(hi >> 1))) * power_of_two(e + 65) +
                     quad(static_cast<__float128>(((hi & 1) << 64) | low)) * power_of_two(e);
      return negative ? quad(-v) : v;
    }
    const unsigned __int128 one = 1;
    const unsigned __int128 out = (static_cast<unsigned __int128>(negative) << 127) |
                                  (static_cast<unsigned __int128>(biased) << 112) | (significand & ((one << 112) - 1));
    __float128 f;
    std::memcpy(&f, &out, sizeof f);
    return quad(f);
  }

 private:
  static constexpr unsigned __int128 infinity_bits = static_cast<unsigned __int128>(0x7fff) << 112;
  // H 2^128 + M 2^64 = sum of (ah 2^64 + al)(bh 2^64 + bl), the low half of each al bl dropped
  // (below 2^64 in these units). A signed half times an unsigned one, ah bl, is the product of
  // their 64-bit patterns less 2^64 bl when ah < 0: one unsigned multiply and a masked sum (C)
  // instead of the two multiplies of a 128-bit signed product. The same integers, so the same
  // results; M is formed once as U - 2^64 C modulo 2^128, exact since |M| < 2^127.
  struct product_sum {
    __int128 H = 0;
    unsigned __int128 U = 0, C = 0;
    [[gnu::always_inline]] void add(std::int64_t ah, std::uint64_t al, std::int64_t bh, std::uint64_t bl) {
      using u128 = unsigned __int128;
      H += static_cast<__int128>(ah) * bh;
      U += static_cast<u128>(static_cast<std::uint64_t>(ah)) * bl;
      U += static_cast<u128>(static_cast<std::uint64_t>(bh)) * al;
      U += (static_cast<u128>(al) * bl) >> 64;
      C += static_cast<std::uint64_t>(ah >> 63) & bl;
      C += static_cast<std::uint64_t>(bh >> 63) & al;
    }
    __int128 middle() const { return static_cast<__int128>(U - (C << 64)); }
  };
  static quad from_bits(unsigned __int128 bits) {
    __float128 f;
    std::memcpy(&f, &bits, sizeof f);
    return quad(f);
  }
  static unsigned __int128 magnitude_bits(const quad& v) {
    unsigned __int128 bits;
    std::memcpy(&bits, &v.backend().value(), sizeof bits);
    return bits & ~(static_cast<unsigned __int128>(1) << 127);
  }
  // 2^e, exact: for a normal result straight from its IEEE binary128 bit pattern (biased exponent
  // e + 16383 in bits 112-126), else by ldexp. Two per row of every product: through ldexp, whose
  // classification of its argument costs soft-float comparisons unless the compiler happens to
  // inline it, they were 2% of a quad reference run.
  static quad power_of_two(int e) {
    if (e < -16382 || e > 16383) return ldexp(quad(1), e);
    const unsigned __int128 bits = static_cast<unsigned __int128>(e + 16383) << 112;
    __float128 f;
    std::memcpy(&f, &bits, sizeof f);
    return quad(f);
  }
  // The power of two that brings max (> 0) just below 2^fraction_bits.
  static int shift_for(const quad& max) {
    int e = 0;
    (void)frexp(max, &e);  // max = m 2^e, m in [0.5, 1)
    return fraction_bits - e;
  }
  // Rounded to nearest (truncation would bias every sum towards zero). The conversion truncates;
  // the remainder is exact in quad, so comparing it with one half rounds correctly.
  static __int128 nearest_integer(const quad& v) {
    const __float128 x = v.backend().value();
    __int128 n = static_cast<__int128>(x);
    const __float128 rest = x - static_cast<__float128>(n);
    if (rest > __float128(0.5)) ++n;
    else if (rest < __float128(-0.5)) --n;
    return n;
  }
  // v = hi 2^64 + lo with lo in [0, 2^64).
  static void split(__int128 v, std::int64_t& hi, std::uint64_t& lo) {
    hi = static_cast<std::int64_t>(v >> 64);
    lo = static_cast<std::uint64_t>(v);
  }

  std::size_t rows_ = 0, cols_ = 0;
  std::vector<int> a_shift_;  // per row
  std::vector<std::int64_t> hi_;
  std::vector<std::uint64_t> lo_;
  std::vector<std::int64_t> xh_;
  std::vector<std::uint64_t> xl_;
};

// MPFR at p bits: the entries become integers of L = ceil((p + 4) / 64) limbs (fraction bits
// 64 L), which hold every entry within 4 binades of its row's or the vector's largest exactly
// and smaller ones truncated below 2^-(p+4) of that largest. The products are summed exactly in
// a two's-complement accumulator (negated where their sign is), and the sum is rounded to p
// bits once (mpfr_set_z_2exp).
//
// Up to 8 limbs (p up to 508 bits) the limb loops are unrolled at compile time: a product of two
// entries is the sum of the limb products a_i b_j 2^(64 (i + j)), and those with i + j >= L - 2
// are added, for the whole row, into one 192-bit sum per column i + j and sign (positive and
// negative products apart), so that no carry runs across the columns for each entry; the columns
// are combined into the two's-complement sum once per row. The lower limb products, all below
// 2^(64 L) in the scaled units, are dropped:
// less than L 2^-(64 L + 62) max_k |A_rk| max|x| per column of A, far below the truncation of
// the inputs. Wider entries are multiplied exactly by mpn_mul_n. In both cases
//   |y_r - (A x)_r| <= 2^-(p+3) n max_k |A_rk| max|x| + ulp(y_r) / 2.
template <>
class fixed_point_matrix<mpfr_real> {
 public:
  // Sums of at most max_columns products keep 10 bits of headroom in the accumulator's top limb.
  static constexpr std::size_t max_columns = 1000;

  fixed_point_matrix() = default;
  // A row-major rows x cols matrix whose entries carry at most `bits` significant bits.
  fixed_point_matrix(const std::vector<mpfr_real>& a, std::size_t rows, std::size_t cols, unsigned bits)
      : rows_(rows), cols_(cols), limbs_((bits + 4 + 63) / 64), fraction_bits_(64 * static_cast<long>(limbs_)),
        a_(a.size() * limbs_), a_negative_(a.size()), a_shift_(rows), x_(cols * limbs_), x_negative_(cols),
        product_(2 * limbs_), sum_(2 * limbs_ + 1) {
    if (a.size() != rows * cols || cols > max_columns)
      throw std::invalid_argument("fixed_point_matrix: at most 1000 columns, rows x cols entries");
    for (std::size_t r = 0; r < rows; ++r) {
      const mpfr_real* row = &a[r * cols];
      a_shift_[r] = shift_for(row, cols);
      for (std::size_t k = 0; k < cols; ++k)
        to_fixed(row[k], a_shift_[r], &a_[(r * cols + k) * limbs_], a_negative_[r * cols + k]);
    }
  }

  std::size_t rows() const { return rows_; }
  std::size_t cols() const { return cols_; }

  // y[r] = sum_k A[r][k] x[k] for rows [first_row, rows), rounded to the precision of y[r]. Not
  // const: works in scratch storage (one object per thread).
  void multiply(const mpfr_real* x, mpfr_real* y, std::size_t first_row = 0) {
    const long x_shift = shift_for(x, cols_);
    for (std::size_t k = 0; k < cols_; ++k) to_fixed(x[k], x_shift, &x_[k * limbs_], x_negative_[k]);
    const auto unrolled = [&](auto L) { unrolled_rows<decltype(L)::value>(first_row, x_shift, y); };
    if (!limbs::with_limb_count(limbs_, unrolled)) wide_rows(first_row, x_shift, y);
  }

 private:
  template <std::size_t L>
  void unrolled_rows(std::size_t first_row, long x_shift, mpfr_real* y) {
    constexpr std::size_t lowest = L >= 2 ? L - 2 : 0;  // the lowest column summed
    constexpr std::size_t width = 2 * L - lowest;       // product limbs: columns lowest .. 2 L - 1
    for (std::size_t r = first_row; r < rows_; ++r) {
      limbs::column_sum<L, lowest> sum;
      for (std::size_t k = 0; k < cols_; ++k) {
        limbs::product_columns<L, lowest> p;
        limbs::columns_of<L, lowest>(&a_[(r * cols_ + k) * L], &x_[k * L], p);
        sum.add(p, a_negative_[r * cols_ + k] ^ x_negative_[k]);
      }
      sum.to_limbs(sum_.data(), width + 1);
      round_sum(width + 1, y[r], a_shift_[r] + x_shift - 64 * static_cast<long>(lowest));
    }
  }

  void wide_rows(std::size_t first_row, long x_shift, mpfr_real* y) {
    const auto n = static_cast<mp_size_t>(limbs_);
    for (std::size_t r = first_row; r < rows_; ++r) {
      std::fill(sum_.begin(), sum_.end(), 0);
      for (std::size_t k = 0; k < cols_; ++k) {
        mpn_mul_n(product_.data(), &a_[(r * cols_ + k) * limbs_], &x_[k * limbs_], n);
        const bool negative = a_negative_[r * cols_ + k] != x_negative_[k];
        const mp_limb_t carry = negative ? mpn_sub_n(sum_.data(), sum_.data(), product_.data(), 2 * n)
                                         : mpn_add_n(sum_.data(), sum_.data(), product_.data(), 2 * n);
        sum_[2 * limbs_] += negative ? mp_limb_t(0) - carry : carry;
      }
      round_sum(sum_.size(), y[r], a_shift_[r] + x_shift);
    }
  }

  // y = sum_ 2^-shift for the two's-complement integer in the first n limbs of sum_
  // (overwritten), rounded to nearest.
  void round_sum(std::size_t n, mpfr_real& y, long shift) {
    limbs::round_to(sum_.data(), n, y.backend().data(), shift);
  }

  // The power of two that brings the largest |v| of the span just below 2^fraction_bits (0 for
  // an all-zero span).
  long shift_for(const mpfr_real* v, std::size_t count) const {
    bool any = false;
    mpfr_exp_t e = 0;
    for (std::size_t k = 0; k < count; ++k) {
      mpfr_srcptr p = v[k].backend().data();
      if (mpfr_zero_p(p)) continue;
      e = any ? std::max(e, mpfr_get_exp(p)) : mpfr_get_exp(p);  // |v| < 2^exp
      any = true;
    }
    return any ? fraction_bits_ - static_cast<long>(e) : 0;
  }

  // v 2^shift as a sign and `limbs_` limbs of magnitude: exact when v's last bit is at or above
  // 2^-shift, truncated otherwise.
  void to_fixed(const mpfr_real& v, long shift, mp_limb_t* out, unsigned char& negative) {
    std::fill(out, out + limbs_, 0);
    negative = 0;
    mpfr_srcptr p = v.backend().data();
    if (mpfr_zero_p(p)) return;
    mpz_ptr z = scratch_.backend().data();
    const long s = static_cast<long>(mpfr_get_z_2exp(z, p)) + shift;  // v = z 2^e exactly
    if (s >= 0)
      mpz_mul_2exp(z, z, static_cast<mp_bitcnt_t>(s));
    else
      mpz_tdiv_q_2exp(z, z, static_cast<mp_bitcnt_t>(-s));
    negative = mpz_sgn(z) < 0;
    const std::size_t size = mpz_size(z);  // <= limbs_, as |v| 2^shift < 2^fraction_bits
    for (std::size_t i = 0; i < size; ++i) out[i] = mpz_getlimbn(z, static_cast<mp_size_t>(i));
  }

  std::size_t rows_ = 0, cols_ = 0, limbs_ = 0;
  long fraction_bits_ = 0;
  std::vector<mp_limb_t> a_;  // magnitudes, limbs_ per entry, row-major
  std::vector<unsigned char> a_negative_;
  std::vector<long> a_shift_;  // per row
  std::vector<mp_limb_t> x_;
  std::vector<unsigned char> x_negative_;
  std::vector<mp_limb_t> product_, sum_;  // scratch: a product, and the sum of a row
  boost::multiprecision::mpz_int scratch_;
};

}  // namespace eulervop::detail

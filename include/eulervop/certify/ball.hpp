// A ball of Arb (Johansson 2017, "Arb: efficient arbitrary-precision midpoint-radius interval
// arithmetic", IEEE Trans. Computers 66): a midpoint and a radius, each operation rounding its
// result outward into the radius. The general path of --certify (docs/certified.md, "The general
// path") computes every number of its proof as one, so that no rounding needs an analysis of its
// own. This header holds the owner type and the exact entries of the program's numbers.
#pragma once

#include <eulervop/core/scalar.hpp>

#include <arb.h>
#include <flint/fmpz.h>
#include <mpfr.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace eulervop {

class ball {
 public:
  ball() { arb_init(x_); }
  explicit ball(long value) {
    arb_init(x_);
    arb_set_si(x_, value);
  }
  ball(const ball& o) {
    arb_init(x_);
    arb_set(x_, o.x_);
  }
  ball(ball&& o) noexcept {
    arb_init(x_);
    arb_swap(x_, o.x_);
  }
  ball& operator=(const ball& o) {
    arb_set(x_, o.x_);
    return *this;
  }
  ball& operator=(ball&& o) noexcept {
    arb_swap(x_, o.x_);
    return *this;
  }
  ~ball() { arb_clear(x_); }

  arb_ptr get() { return x_; }
  arb_srcptr get() const { return x_; }

 private:
  arb_t x_;
};
// A vector of balls is an array of arb_struct, which Arb's vector functions (arb_dot) take.
static_assert(sizeof(ball) == sizeof(arb_struct) && std::is_standard_layout_v<ball>);

// An upper bound as Arb's mag (a magnitude rounded up by every operation), freed with its owner.
struct mag_value {
  mag_value() { mag_init(m); }
  mag_value(const mag_value& o) {
    mag_init(m);
    mag_set(m, o.m);
  }
  mag_value& operator=(const mag_value& o) {
    mag_set(m, o.m);
    return *this;
  }
  ~mag_value() { mag_clear(m); }
  mag_t m;
};

namespace detail {

// A binary128 number exactly, from its fields (IEEE 754-2008, 3.4): the 113-bit integer as two
// words, and the exponent.
inline void set_exact_binary128(ball& out, __float128 x) {
  static_assert(std::endian::native == std::endian::little, "binary128 fields read as little-endian words");
  std::uint64_t w[2];
  std::memcpy(w, &x, sizeof w);
  const unsigned biased = static_cast<unsigned>(w[1] >> 48) & 0x7fffu;
  if (biased == 0x7fffu) {  // infinite or NaN: the indeterminate ball, which fails every test
    arb_indeterminate(out.get());
    return;
  }
  std::uint64_t high = w[1] & ((std::uint64_t{1} << 48) - 1);
  long exponent = 1 - 16383 - 112;
  if (biased != 0) {
    high |= std::uint64_t{1} << 48;
    exponent = static_cast<long>(biased) - 16383 - 112;
  }
  arf_t low;
  arf_init(low);
  arf_set_ui_2exp_si(arb_midref(out.get()), high, exponent + 64);
  arf_set_ui_2exp_si(low, w[0], exponent);
  arf_add(arb_midref(out.get()), arb_midref(out.get()), low, ARF_PREC_EXACT, ARF_RND_DOWN);
  arf_clear(low);
  if (w[1] >> 63) arf_neg(arb_midref(out.get()), arb_midref(out.get()));
  mag_zero(arb_radref(out.get()));
}

}  // namespace detail

// The exact value of a scalar as a point ball (any precision: Arb's midpoints are exact).
template <scalar T>
void set_exact(ball& out, const T& x) {
  if constexpr (std::is_same_v<T, double>) {
    arb_set_d(out.get(), x);
  } else if constexpr (std::is_same_v<T, mpfr_real>) {
    arf_set_mpfr(arb_midref(out.get()), x.backend().data());
    mag_zero(arb_radref(out.get()));
  } else {
    detail::set_exact_binary128(out, x.backend().value());
  }
}

namespace detail {

// A plain decimal ("-1.25e-3": a sign, digits with at most one point, an exponent) as Arb's parser
// reads it (arb/set_str.c): the digits without their trailing zeros (all but a lone digit) as an
// integer n, and the exponent e adjusted for the digits after the point, so the text is n 10^e.
struct plain_decimal {
  bool negative = false;
  unsigned __int128 n = 0;
  long exponent = 0;
};

// False where the text is not of that form or has more than 38 digits.
inline bool parse_plain_decimal(plain_decimal& out, const std::string& text) {
  std::size_t i = 0;
  out.negative = !text.empty() && text[0] == '-';
  if (!text.empty() && (text[0] == '-' || text[0] == '+')) ++i;
  out.n = 0;
  int digits = 0, after_point = 0, zeros = 0;  // zeros: the trailing zeros so far
  bool point = false;
  for (; i < text.size() && text[i] != 'e' && text[i] != 'E'; ++i) {
    const char c = text[i];
    if (c == '.' && !point) {
      point = true;
      continue;
    }
    if (c < '0' || c > '9' || ++digits > 38) return false;
    after_point += point;
    zeros = c == '0' ? zeros + 1 : 0;
    out.n = 10 * out.n + static_cast<unsigned>(c - '0');
  }
  if (digits == 0) return false;
  out.exponent = 0;
  if (i < text.size()) {  // the exponent: [+-]digits, at most 6 of them
    std::size_t j = i + 1;
    const bool minus = j < text.size() && text[j] == '-';
    if (j < text.size() && (text[j] == '-' || text[j] == '+')) ++j;
    if (j == text.size() || text.size() - j > 6) return false;
    for (; j < text.size(); ++j) {
      if (text[j] < '0' || text[j] > '9') return false;
      out.exponent = 10 * out.exponent + (text[j] - '0');
    }
    if (minus) out.exponent = -out.exponent;
  }
  zeros = std::min(zeros, digits - 1);
  for (int k = 0; k < zeros; ++k) out.n /= 10;
  out.exponent -= after_point - zeros;
  return true;
}

// 10^k as Arb's parser makes it at prec (arb_pow_fmpz_binexp at prec + 4).
inline void set_power_of_ten(ball& out, std::size_t k, slong prec) {
  fmpz_t e;
  fmpz_init_set_ui(e, k);
  arb_set_ui(out.get(), 10);
  arb_pow_fmpz_binexp(out.get(), out.get(), e, prec + 4);
  fmpz_clear(e);
}

// The same, kept per thread for k up to 1000 (a printed number's exponent; beyond, made anew, in
// `spare`): a certified row reads three or more printed decimals, and their powers were most of
// arb_set_str's time.
inline const ball& power_of_ten(std::size_t k, slong prec, ball& spare) {
  thread_local std::vector<ball> powers;  // zero where not made yet
  thread_local slong powers_prec = -1;
  if (k > 1000) {
    set_power_of_ten(spare, k, prec);
    return spare;
  }
  if (powers_prec != prec) {
    powers.clear();
    powers_prec = prec;
  }
  if (powers.size() <= k) powers.resize(k + 1);
  ball& t = powers[k];
  if (arb_is_zero(t.get())) set_power_of_ten(t, k, prec);
  return t;
}

// The ball arb_set_str makes of a plain decimal, by its own steps: n rounded to prec if e = 0,
// else n times or divided by 10^|e| at prec, negated for a minus sign. False (out untouched)
// where the text is not plain; arb_set_str then reads it.
inline bool plain_decimal_ball(ball& out, const std::string& text, slong prec) {
  plain_decimal d;
  if (!parse_plain_decimal(d, text)) return false;
  if (d.n == 0) {
    arb_zero(out.get());
    return true;
  }
  fmpz_t m;
  fmpz_init(m);
  fmpz_set_ui(m, static_cast<ulong>(d.n >> 64));
  fmpz_mul_2exp(m, m, 64);
  fmpz_add_ui(m, m, static_cast<ulong>(d.n));
  if (d.exponent == 0) {
    arb_set_round_fmpz(out.get(), m, prec);
  } else {
    ball spare;
    const ball& t = power_of_ten(static_cast<std::size_t>(d.exponent < 0 ? -d.exponent : d.exponent), prec, spare);
    arb_set_fmpz(out.get(), m);
    if (d.exponent > 0)
      arb_mul(out.get(), out.get(), t.get(), prec);
    else
      arb_div(out.get(), out.get(), t.get(), prec);
  }
  fmpz_clear(m);
  if (d.negative) arb_neg(out.get(), out.get());
  return true;
}

}  // namespace detail

// A ball that holds the real number a decimal text denotes ("0.1" is one tenth): the ball of
// arb_set_str, bit for bit.
inline ball decimal_ball(const std::string& text, slong prec) {
  ball out;
  if (detail::plain_decimal_ball(out, text, prec)) return out;
  if (arb_set_str(out.get(), text.c_str(), prec) != 0)
    throw std::invalid_argument("decimal_ball: not a decimal number: " + text);
  return out;
}

// An upper bound of |x| as a double (+inf when x is not finite).
inline double magnitude_up(const ball& x) {
  arf_t u;
  arf_init(u);
  arb_get_abs_ubound_arf(u, x.get(), 53);
  const double d = arf_get_d(u, ARF_RND_UP);
  arf_clear(u);
  return d;
}

// [0, an upper bound of |x|]: the magnitude as a ball, for sums of bounds.
inline void set_magnitude(ball& out, const ball& x) {
  mag_t m;
  mag_init(m);
  arb_get_mag(m, x.get());
  arf_set_mag(arb_midref(out.get()), m);
  mag_zero(arb_radref(out.get()));
  mag_clear(m);
}

// x = [0, sup |x|] as the ball whose upper end bounds |x| from above (midpoint and radius both
// half of it, rounded up): what a bound's interval [0, b] is in midpoint-radius form.
inline void to_zero_hull(ball& x) {
  mag_t zero, m;
  mag_init(zero);
  mag_init(m);
  arb_get_mag(m, x.get());
  arb_set_interval_mag(x.get(), zero, m, MAG_BITS);
  mag_clear(m);
  mag_clear(zero);
}

}  // namespace eulervop

// quad_text (core/scalar.hpp): a binary128 number's decimal digits by exact integer arithmetic.
#pragma once

#include <boost/multiprecision/float128.hpp>

#include <gmp.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

namespace eulervop::detail {

// GMP integers reused by a thread, with the powers of ten most conversions need: a conversion
// allocates nothing once they have grown.
struct quad_text_scratch {
  static constexpr unsigned kept_powers = 160;
  mpz_t a, b, q, r;
  mpz_t powers[kept_powers];  // 10^k
  quad_text_scratch() {
    mpz_inits(a, b, q, r, nullptr);
    for (unsigned k = 0; k < kept_powers; ++k) {
      mpz_init(powers[k]);
      mpz_ui_pow_ui(powers[k], 10, k);
    }
  }
  ~quad_text_scratch() {
    mpz_clears(a, b, q, r, nullptr);
    for (auto& p : powers) mpz_clear(p);
  }
  quad_text_scratch(const quad_text_scratch&) = delete;
  quad_text_scratch& operator=(const quad_text_scratch&) = delete;
  // 10^k, kept or made in r.
  mpz_srcptr power_of_ten(unsigned long k) {
    if (k < kept_powers) return powers[k];
    mpz_ui_pow_ui(r, 10, k);
    return r;
  }
};

// q = round(m 2^e 10^k), ties to even, into s.q.
inline void scaled_rounded(quad_text_scratch& s, unsigned __int128 m, long e, long k) {
  const std::uint64_t limbs[2] = {static_cast<std::uint64_t>(m), static_cast<std::uint64_t>(m >> 64)};
  mpz_import(s.a, 2, -1, sizeof(std::uint64_t), 0, 0, limbs);
  mpz_set_ui(s.b, 1);
  if (e >= 0) mpz_mul_2exp(s.a, s.a, static_cast<mp_bitcnt_t>(e));
  else mpz_mul_2exp(s.b, s.b, static_cast<mp_bitcnt_t>(-e));
  mpz_srcptr ten = s.power_of_ten(static_cast<unsigned long>(k >= 0 ? k : -k));
  if (k >= 0) mpz_mul(s.a, s.a, ten);
  else mpz_mul(s.b, s.b, ten);
  mpz_fdiv_qr(s.q, s.r, s.a, s.b);
  mpz_mul_2exp(s.r, s.r, 1);
  const int c = mpz_cmp(s.r, s.b);
  if (c > 0 || (c == 0 && mpz_odd_p(s.q))) mpz_add_ui(s.q, s.q, 1);
}

inline std::string quad_text_exact(const boost::multiprecision::float128& x, unsigned digits) {
  const __float128 v = x.backend().value();
  unsigned __int128 bits;
  std::memcpy(&bits, &v, sizeof bits);
  const bool negative = bits >> 127;
  const int biased = static_cast<int>(bits >> 112) & 0x7fff;
  const unsigned __int128 fraction = bits & ((static_cast<unsigned __int128>(1) << 112) - 1);
  // Infinities, NaN and zeros (and digits beyond any use), as printf writes them.
  if (biased == 0x7fff || (biased == 0 && fraction == 0) || digits > 120)
    return x.str(static_cast<std::streamsize>(digits), std::ios_base::scientific);
  const unsigned __int128 m = biased ? fraction | (static_cast<unsigned __int128>(1) << 112) : fraction;
  const long e = (biased ? biased : 1) - 16383L - 112;
  const auto high = static_cast<std::uint64_t>(m >> 64);
  const int length = high ? 128 - __builtin_clzll(high) : 64 - __builtin_clzll(static_cast<std::uint64_t>(m));
  // |x| is in [2^(e + length - 1), 2^(e + length)): its decimal exponent is this, or one less.
  long E = static_cast<long>(std::floor(static_cast<double>(e + length - 1) * 0.30102999566398120));
  thread_local quad_text_scratch s;
  for (;;) {  // D = round(|x| 10^(digits - E)) must have digits + 1 digits
    scaled_rounded(s, m, e, static_cast<long>(digits) - E);
    if (mpz_cmp(s.q, s.power_of_ten(digits + 1)) >= 0) { ++E; continue; }
    if (mpz_cmp(s.q, s.power_of_ten(digits)) < 0) { --E; continue; }
    break;
  }
  char mantissa[128];
  mpz_get_str(mantissa, 10, s.q);
  std::string out = negative ? "-" : "";
  out += mantissa[0];
  if (digits) {
    out += '.';
    out.append(mantissa + 1, digits);
  }
  // The exponent as %e writes it: a sign and at least two digits.
  out += E < 0 ? "e-" : "e+";
  const std::string exponent = std::to_string(E < 0 ? -E : E);
  if (exponent.size() < 2) out += '0';
  return out + exponent;
}

}  // namespace eulervop::detail

// Decimal text to quad and back. Reading: the fast path of core/scalar.hpp (one correctly rounded
// operation on exact operands) against libquadmath's strtoflt128 (through Boost's float128 string
// constructor), an independent correctly rounded conversion, on random decimals of every length
// and exponent the fast path takes, and on the texts it must hand over. Writing: quad_text (exact
// integer arithmetic) against libquadmath's quadmath_snprintf (through Boost's str()), byte for
// byte, on random bit patterns of every magnitude, subnormals included.
#include <eulervop/core/scalar.hpp>

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>

namespace {

using eulervop::quad;

bool same_bits(const quad& a, const quad& b) {
  return std::memcmp(&a.backend().value(), &b.backend().value(), sizeof(__float128)) == 0;
}

TEST(DecimalToQuad, FastPathEqualsStrtoflt128) {
  std::mt19937_64 random(20261128);
  int taken = 0;
  for (int n = 0; n < 200000; ++n) {
    const int digits = 1 + static_cast<int>(random() % 34);
    std::string text = random() % 2 ? "-" : "";
    const int point = static_cast<int>(random() % (digits + 1));
    for (int d = 0; d < digits; ++d) {
      if (d == point) text += '.';
      text += static_cast<char>('0' + random() % 10);
    }
    const int e = static_cast<int>(random() % 81) - 40;
    if (random() % 3) text += "e" + std::to_string(e);
    const auto fast = eulervop::quad_fast_path(text);
    if (!fast) continue;
    ++taken;
    ASSERT_TRUE(same_bits(*fast, quad(text))) << text;
  }
  EXPECT_GT(taken, 150000);  // most of them are in its range
}

TEST(DecimalToQuad, EveryDoubleTextRoundTrips) {
  // A double's shortest text (as a trajectory file holds it) read in quad is the double itself
  // only if the decimal is exactly the double; what matters is that it equals strtoflt128's value.
  std::mt19937_64 random(7);
  for (int n = 0; n < 100000; ++n) {
    double x;
    const std::uint64_t bits = random();
    std::memcpy(&x, &bits, sizeof x);
    if (!std::isfinite(x) || std::abs(x) > 1e30 || std::abs(x) < 1e-30) continue;
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
    const std::string text(buf, end);
    const auto fast = eulervop::from_text<quad>(text);
    ASSERT_TRUE(fast.has_value()) << text;
    ASSERT_TRUE(same_bits(*fast, quad(text))) << text;
  }
}

TEST(DecimalToQuad, OtherTextsTakeTheGeneralWay) {
  for (const char* text : {"1e-49", "1e49", "12345678901234567890123456789012345", "0x1p3", "inf", "nan", " 1", "1e"})
    EXPECT_FALSE(eulervop::quad_fast_path(text).has_value()) << text;
  // ...and still convert there when they are numbers.
  EXPECT_TRUE(same_bits(*eulervop::from_text<quad>("1e-49"), quad("1e-49")));
  EXPECT_TRUE(same_bits(*eulervop::from_text<quad>("12345678901234567890123456789012345"),
                        quad("12345678901234567890123456789012345")));
  EXPECT_FALSE(eulervop::from_text<quad>("1e").has_value());
  EXPECT_TRUE(same_bits(*eulervop::from_text<quad>("-0"), quad("-0")));
  EXPECT_TRUE(same_bits(*eulervop::from_text<quad>("0.000"), quad(0)));
}

TEST(QuadToDecimal, EqualsQuadmathSnprintf) {
  std::mt19937_64 random(11);
  for (int n = 0; n < 200000; ++n) {
    const unsigned __int128 bits = (static_cast<unsigned __int128>(random()) << 64) | random();
    __float128 v;
    std::memcpy(&v, &bits, sizeof v);
    const quad x(v);
    if (!isfinite(x)) continue;
    const unsigned digits = n % 10 == 0 ? 1 + static_cast<unsigned>(random() % 40) : 36;  // Boost reads 0 as 36
    ASSERT_EQ(eulervop::quad_text(x, digits), x.str(digits, std::ios_base::scientific)) << "digits " << digits;
  }
  // Values of the magnitudes a reference holds, and ties: 0.5 ulp of the last digit kept.
  for (const char* text : {"1", "0.1", "-2.5", "9.9999999999999999999999999999999999999", "1e-300", "123456789e20",
                           "0.00000000000000000000000000000000000015"}) {
    const quad x(text);
    for (unsigned digits : {1u, 3u, 35u, 36u})
      EXPECT_EQ(eulervop::quad_text(x, digits), x.str(digits, std::ios_base::scientific)) << text << " " << digits;
  }
  for (const quad& x : {quad(0), quad(-0.0), std::numeric_limits<quad>::infinity()})
    EXPECT_EQ(eulervop::to_text(x), x.str(36, std::ios_base::scientific));
}

}  // namespace

// decimal_ball (certify/ball.hpp) reads the plain decimals of the program's output itself, with
// the powers of ten kept per thread, and must give Arb's arb_set_str's ball bit for bit (the
// reference here: arb_set_str on the same text, which the radii were computed with before):
// random texts of the printed form (36 significant digits and a two- or three-digit exponent, as
// quad's and MPFR's cells are written), and the edge cases of Arb's parser (trailing zeros moved
// into the exponent, a lone zero, signs, no point, no exponent), at two precisions.
#include <eulervop/certify/ball.hpp>

#include <gtest/gtest.h>

#include <arb.h>

#include <random>
#include <stdexcept>
#include <string>

namespace {

// The midpoints and radii are equal exactly.
bool identical(const eulervop::ball& a, const eulervop::ball& b) {
  return arf_equal(arb_midref(a.get()), arb_midref(b.get())) && mag_equal(arb_radref(a.get()), arb_radref(b.get()));
}

eulervop::ball of_arb(const std::string& text, slong prec) {
  eulervop::ball out;
  if (arb_set_str(out.get(), text.c_str(), prec) != 0) throw std::invalid_argument(text);
  return out;
}

TEST(DecimalBall, IsArbsBallOfRandomPrintedDecimals) {
  std::mt19937_64 rng(20261129);
  for (const slong prec : {177, 320}) {
    for (int k = 0; k < 20000; ++k) {
      std::string t = rng() % 2 ? "-" : "";
      t += static_cast<char>('1' + rng() % 9);
      t += '.';
      const int digits = k % 5 == 0 ? static_cast<int>(rng() % 38) : 35;
      for (int d = 0; d < digits; ++d) t += static_cast<char>('0' + rng() % 10);
      if (k % 7 == 0) t += "000";  // trailing zeros
      const long e = static_cast<long>(rng() % 700) - 400;
      t += e < 0 ? "e-" : "e+";
      t += (std::abs(e) < 10 ? "0" : "") + std::to_string(std::abs(e));
      ASSERT_TRUE(identical(eulervop::decimal_ball(t, prec), of_arb(t, prec))) << t << " at " << prec;
    }
  }
}

TEST(DecimalBall, IsArbsBallAtTheParsersEdges) {
  for (const slong prec : {64, 177}) {
    for (const char* t : {"0", "-0", "0.0", "0.", ".5", "100", "1e3", "1E-3", "+2.5e+01", "-0.000125", "120.000e-2",
                          "10", "9.000000000000000000000000000000000000e-01", "5.0000000000000000000000000000000000e-01",
                          "1.000000000000000000000000000000000000e+00", "0.1", "12345678901234567890123456789012345678",
                          "123456789012345678901234567890123456789", "1.5e-999999", "2e1234567", " 1.5", "[1.5]",
                          "1.5 +/- 0.25", "inf", "-inf", "nan"}) {
      EXPECT_TRUE(identical(eulervop::decimal_ball(t, prec), of_arb(t, prec))) << t << " at " << prec;
    }
  }
}

TEST(DecimalBall, RefusesWhatArbRefuses) {
  for (const char* t : {"", "1.2.3", "e5", "1e", "1e+", "abc", "1,5"})
    EXPECT_THROW(eulervop::decimal_ball(t, 177), std::invalid_argument) << t;
}

}  // namespace

// The radius cells' text (compute/certified_reference.hpp, rounded_up_text): three significant
// digits of an upper bound, rounded up, exactly as MPFR's "%.2RUe" prints the same number (the
// reference here: mpfr_asprintf, which the text was made with before), over random 64-bit numbers
// from 2^-4000 to 2^300 (beyond a double's range both ways, as mpfr:1024 radii go) and the decimal
// boundaries where rounding up carries into the next digit or decade.
#include "compute/certified_reference.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace {

// m as "%.2RUe" prints it.
std::string printed(const mpfr_t m) {
  char* text = nullptr;
  mpfr_asprintf(&text, "%.2RUe", m);
  std::string out = text;
  mpfr_free_str(text);
  return out;
}

// A 64-bit MPFR number, cleared at the end of its scope.
struct number {
  number() { mpfr_init2(m, 64); }
  ~number() { mpfr_clear(m); }
  number(const number&) = delete;
  number& operator=(const number&) = delete;
  mpfr_t m;
};

TEST(RadiusText, MatchesMpfrsRoundedUpScientificTextOnRandomNumbers) {
  std::mt19937_64 rng(20261129);
  number x;
  for (int k = 0; k < 20000; ++k) {
    mpfr_set_ui_2exp(x.m, rng() | 1, static_cast<mpfr_exp_t>(rng() % 4300) - 4064, MPFR_RNDU);
    ASSERT_EQ(eulervop::app::rounded_up_text(x.m), printed(x.m)) << k;
  }
}

// 9.99e-33 and 1.00e-32 and their neighbours, 10^k exactly and just above, and the exponents
// that change width (e-09, e-10, e-99, e-100, e+00); zero and infinity.
TEST(RadiusText, MatchesAtTheDecimalBoundaries) {
  number x;
  for (const char* decimal : {"9.99e-33", "9.995e-33", "9.9951e-33", "1e-32", "1.001e-32", "1.0e-9", "9.999e-10",
                              "1e-99", "9.9999e-100", "1e-100", "1", "0.99999", "1.005", "123.4", "2.785e-32"}) {
    for (const mpfr_rnd_t rounding : {MPFR_RNDD, MPFR_RNDU}) {  // the 64-bit numbers each side of it
      mpfr_set_str(x.m, decimal, 10, rounding);
      EXPECT_EQ(eulervop::app::rounded_up_text(x.m), printed(x.m)) << decimal;
    }
  }
  mpfr_set_zero(x.m, 1);
  EXPECT_EQ(eulervop::app::rounded_up_text(x.m), printed(x.m));
  mpfr_set_inf(x.m, 1);
  EXPECT_EQ(eulervop::app::rounded_up_text(x.m), printed(x.m));
}

// upper_text is rounded_up_text of the ball's 64-bit upper bound: a ball's radius counts, and its
// sign does not.
TEST(RadiusText, OfABallIsItsUpperBoundsText) {
  eulervop::ball x;
  arb_set_str(x.get(), "-2.775e-32", 200);
  EXPECT_EQ(eulervop::app::upper_text(x), "2.78e-32");
  mag_set_d(arb_radref(x.get()), 1e-34);
  EXPECT_EQ(eulervop::app::upper_text(x), "2.79e-32");  // 2.775e-32 + 1e-34 rounds up to 2.79e-32
}

}  // namespace

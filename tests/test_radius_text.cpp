// The radius cells' text (compute/certified_reference.hpp, rounded_up_text): three significant
// digits of an upper bound, rounded up, exactly as MPFR's "%.2RUe" prints the same number (the
// reference here: mpfr_asprintf, which the text was made with before), over random 64-bit numbers
// from 2^-4000 to 2^300 (beyond a double's range both ways, as mpfr:1024 radii go) and the decimal
// boundaries where rounding up carries into the next digit or decade.
#include "compute/certified_reference.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

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

// The largest of a column's texts, against the order of their values in MPFR (the reference:
// each text read at 200 bits, whose value is then exact): random texts of rounded_up_text
// mixed with zero, infinity and texts of other forms, which take MPFR's way.
TEST(RadiusText, LargestIsTheLargestValue) {
  std::mt19937_64 rng(20261129);
  number x;
  std::vector<std::string> texts = {"0.00e+00", "inf", "1e-30", "9.999e-31", "5.00e-31"};
  for (int k = 0; k < 3000; ++k) {
    mpfr_set_ui_2exp(x.m, rng() | 1, static_cast<mpfr_exp_t>(rng() % 700) - 600, MPFR_RNDU);
    texts.push_back(eulervop::app::rounded_up_text(x.m));
  }
  for (int run = 0; run < 40; ++run) {
    std::shuffle(texts.begin() + (run % 2 == 0 ? 1 : 0), texts.end() - (run % 3 == 0 ? 1 : 0), rng);
    const std::size_t count = 2 + rng() % 200;
    eulervop::app::largest_radius_text largest;
    std::string max;
    mpfr_t best, v;
    mpfr_init2(best, 200);
    mpfr_init2(v, 200);
    std::string expected;
    for (std::size_t i = 0; i < count; ++i) {
      largest.raise(max, texts[i]);
      mpfr_set_str(v, texts[i].c_str(), 10, MPFR_RNDN);
      if (expected.empty() || mpfr_greater_p(v, best)) {
        expected = texts[i];
        mpfr_set(best, v, MPFR_RNDN);
      }
    }
    mpfr_clear(best);
    mpfr_clear(v);
    ASSERT_EQ(max, expected) << run;
  }
}

TEST(RadiusText, RegularKeyOrdersAsTheValue) {
  using key = eulervop::app::largest_radius_text;
  EXPECT_LT(*key::regular_key("9.99e-33"), *key::regular_key("1.00e-32"));
  EXPECT_LT(*key::regular_key("1.00e-32"), *key::regular_key("1.01e-32"));
  EXPECT_LT(*key::regular_key("9.99e-100"), *key::regular_key("1.00e-99"));
  EXPECT_LT(*key::regular_key("9.99e+00"), *key::regular_key("1.00e+01"));
  EXPECT_FALSE(key::regular_key("0.00e+00"));  // zero is not regular: MPFR compares it
  EXPECT_FALSE(key::regular_key("inf"));
  EXPECT_FALSE(key::regular_key("1e-30"));
}

}  // namespace

// The radius cells' text (compute/certified_reference.hpp, upper_text): three significant digits
// of an upper bound, rounded up, exactly as MPFR's "%.2RUe" prints the same bound (the reference
// here: mpfr_asprintf, which the text was made with before), over random bounds from 2^-4000 to
// 2^300 (beyond a double's range both ways, as mpfr:1024 radii go) and the decimal boundaries
// where rounding up carries into the next digit or decade.
#include "compute/certified_reference.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace {

using eulervop::ball;

// The bound as "%.2RUe" prints it, from the same 64-bit upper bound upper_text takes.
std::string printed(const ball& x) {
  arf_t u;
  arf_init(u);
  arb_get_abs_ubound_arf(u, x.get(), 64);
  mpfr_t m;
  mpfr_init2(m, 64);
  arf_get_mpfr(m, u, MPFR_RNDU);
  char* text = nullptr;
  mpfr_asprintf(&text, "%.2RUe", m);
  std::string out = text;
  mpfr_free_str(text);
  mpfr_clear(m);
  arf_clear(u);
  return out;
}

TEST(RadiusText, MatchesMpfrsRoundedUpScientificTextOnRandomBounds) {
  std::mt19937_64 rng(20261129);
  for (int k = 0; k < 20000; ++k) {
    ball x;
    arf_set_ui_2exp_si(arb_midref(x.get()), rng() | 1, static_cast<slong>(rng() % 4300) - 4064);
    if (k % 3 == 0) mag_set_ui_2exp_si(arb_radref(x.get()), rng() % 1000, static_cast<slong>(rng() % 4300) - 4074);
    if (k % 2 == 0) arb_neg(x.get(), x.get());
    ASSERT_EQ(eulervop::app::upper_text(x), printed(x)) << k;
  }
}

// 9.99e-33 and 1.00e-32 and their neighbours, 10^k exactly and just above, and the exponents
// that change width (e-09, e-10, e-99, e-100, e+00).
TEST(RadiusText, MatchesAtTheDecimalBoundaries) {
  for (const char* decimal : {"9.99e-33", "9.995e-33", "9.9951e-33", "1e-32", "1.001e-32", "1.0e-9", "9.999e-10",
                              "1e-99", "9.9999e-100", "1e-100", "1", "0.99999", "1.005", "123.4", "2.785e-32"}) {
    ball x;
    arb_set_str(x.get(), decimal, 200);
    EXPECT_EQ(eulervop::app::upper_text(x), printed(x)) << decimal;
    arb_mul_2exp_si(x.get(), x.get(), 0);
    mag_set_ui_2exp_si(arb_radref(x.get()), 1, -300);
    EXPECT_EQ(eulervop::app::upper_text(x), printed(x)) << decimal << " with a radius";
  }
  for (const ball& x : {ball(), ball(1)}) EXPECT_EQ(eulervop::app::upper_text(x), printed(x));
  ball infinite;
  arb_indeterminate(infinite.get());
  EXPECT_EQ(eulervop::app::upper_text(infinite), printed(infinite));
}

}  // namespace

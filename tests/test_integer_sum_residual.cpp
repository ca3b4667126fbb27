// The bound of a linear-flow residual from its exact integer sums
// (include/eulervop/certify/detail/integer_sum_residual.hpp, with exact_difference.hpp), tested
// as the other kernels of the general path are (test_chebyshev_model.cpp): against the exact
// residual computed independently from the same integers, in Arb at 3000 bits.
#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/integer_sum_residual.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace {

using eulervop::ball;
using eulervop::mag_value;

using eulervop::detail::wide_int;
constexpr slong truth_prec = 3000;

// b_k = hl 2^e d_k / (2k) (b[0] unused), c0 = delta + sum (-1)^(k+1) b_k, babs = sum |b_k|.
void integral(std::vector<ball>& b, ball& c0, ball& babs, const fmpz_poly_t S, slong n, const ball& hl, slong e,
              int identity) {
  fmpz_t d, next;
  fmpz_init(d);
  fmpz_init(next);
  b.assign(static_cast<std::size_t>(n + 1), ball());
  arb_set_si(c0.get(), identity);
  arb_zero(babs.get());
  ball t;
  for (slong k = 1; k <= n; ++k) {
    arb_ptr bk = b[static_cast<std::size_t>(k)].get();
    fmpz_poly_get_coeff_fmpz(d, S, k - 1);
    if (k == 1) fmpz_mul_2exp(d, d, 1);
    fmpz_poly_get_coeff_fmpz(next, S, k + 1);
    fmpz_sub(d, d, next);
    arb_mul_fmpz(bk, hl.get(), d, truth_prec);
    arb_mul_2exp_si(bk, bk, e);
    arb_div_ui(bk, bk, static_cast<ulong>(2 * k), truth_prec);
    (k % 2 ? arb_add : arb_sub)(c0.get(), c0.get(), bk, truth_prec);
    arb_abs(t.get(), bk);
    arb_add(babs.get(), babs.get(), t.get(), truth_prec);
  }
  fmpz_clear(d);
  fmpz_clear(next);
}

// sum_k |c_k| + 2 |hl| rem, c the residual's coefficients for Q = q 2^f.
void residual_sum(ball& sum, const std::vector<ball>& b, const ball& c0, const fmpz_poly_t q, slong f, const ball& hl,
                  const mag_t rem) {
  const auto n = static_cast<slong>(b.size()) - 1;
  ball t;
  arb_zero(sum.get());
  for (slong k = 0; k < std::max(q->length, n + 1); ++k) {
    arb_zero(t.get());
    if (k < q->length) arb_set_fmpz(t.get(), q->coeffs + k);
    arb_mul_2exp_si(t.get(), t.get(), f);
    if (k <= n) arb_sub(t.get(), (k == 0 ? c0 : b[static_cast<std::size_t>(k)]).get(), t.get(), truth_prec);
    arb_abs(t.get(), t.get());
    arb_add(sum.get(), sum.get(), t.get(), truth_prec);
  }
  arf_t r;
  arf_init(r);
  arf_set_mag(r, rem);
  arb_abs(t.get(), hl.get());
  arb_mul_arf(t.get(), t.get(), r, truth_prec);
  arb_mul_2exp_si(t.get(), t.get(), 1);
  arb_add(sum.get(), sum.get(), t.get(), truth_prec);
  arf_clear(r);
}

// n random sums of `bits` bits (both forms), and hl: an odd integer of hl_bits bits in [1/4, 1/2).
void random_inputs(std::vector<wide_int>& S, fmpz_poly_t Sp, ball& hl, slong n, unsigned bits, unsigned hl_bits,
                   bool negative, std::mt19937_64& rng) {
  S.resize(static_cast<std::size_t>(n));
  fmpz_poly_zero(Sp);
  fmpz_t z;
  fmpz_init(z);
  for (slong k = 0; k < n; ++k) {
    const unsigned __int128 v = ((static_cast<unsigned __int128>(rng()) << 64) | rng()) >> (128 - bits);
    const wide_int s = rng() % 2 ? static_cast<wide_int>(v) : -static_cast<wide_int>(v);
    S[static_cast<std::size_t>(k)] = s;
    const auto u = static_cast<unsigned __int128>(s);
    fmpz_set_signed_uiui(z, static_cast<ulong>(u >> 64), static_cast<ulong>(u));
    fmpz_poly_set_coeff_fmpz(Sp, k, z);
  }
  fmpz_zero(z);
  for (unsigned i = 0; i < hl_bits; ++i) {
    fmpz_mul_2exp(z, z, 1);
    fmpz_add_ui(z, z, rng() % 2);
  }
  fmpz_setbit(z, hl_bits - 1);
  fmpz_setbit(z, 0);
  if (negative) fmpz_neg(z, z);
  arb_set_fmpz(hl.get(), z);
  arb_mul_2exp_si(hl.get(), hl.get(), -static_cast<slong>(hl_bits) - 1);
  fmpz_clear(z);
}

// Q: the integral (b, c0) on the grid 2^f moved by up to 3 units (or 0 and those moves), and
// three coefficients more.
void subtracted(fmpz_poly_t q, const std::vector<ball>& b, const ball& c0, slong f, bool cancel, std::mt19937_64& rng) {
  const auto n = static_cast<slong>(b.size()) - 1;
  fmpz_t d, m;
  fmpz_init(d);
  fmpz_init(m);
  ball t;
  fmpz_poly_zero(q);
  for (slong k = 0; k < n + 4; ++k) {
    fmpz_set_si(d, static_cast<slong>(rng() % 7) - 3);
    if (cancel && k <= n) {
      arb_mul_2exp_si(t.get(), (k == 0 ? c0 : b[static_cast<std::size_t>(k)]).get(), -f);
      arf_get_fmpz(m, arb_midref(t.get()), ARF_RND_NEAR);
      fmpz_add(d, d, m);
    }
    fmpz_poly_set_coeff_fmpz(q, k, d);
  }
  fmpz_clear(d);
  fmpz_clear(m);
}


// A linear-flow residual's bound from its exact integer sums (integer_sum_residual.hpp), where Q
// cancels the integral to a few units of its grid (as Phi_num's and u_num's do) or is unrelated
// to it, for half-lengths of 1 to 200 bits (beyond 128 the rest enters as eps) and one with a
// radius, on grids where the exact path holds every term, and where a term leaves it for the path
// in balls (Q's coefficients beyond 62 bits, or too far from the integral's grid). Truth: the
// residual's coefficients from the same integers in Arb at 3000 bits (the division by 2k their
// only rounding), at both ends of the half-length's ball: the bound holds the sum of their
// magnitudes, and exceeds it by at most what the path in balls' 64-bit factors may add (2^-60 of
// sum |b_k|, b_k the integral's coefficients), the radius's part (2^3 of its relative size times
// sum |b_k|) and the magnitudes' 30-bit roundings (2^-20 of the sum).
TEST(IntegerSumResidual, BoundsTheSumOfTheExactCoefficientsTightly) {
  struct residual_case {
    unsigned hl_bits;
    bool negative;
    slong e, f;     // the sums' grid 2^e and Q's 2^f
    unsigned bits;  // the sums' coefficients' bits
    bool cancel;    // Q the integral to a few units of 2^f, else small integers
    slong radius;   // hl's radius 2^radius |hl|, or none at 0
  };
  std::mt19937_64 rng(51);
  for (const residual_case& c : std::vector<residual_case>{
           {113, false, -110, -48, 110, true, 0}, {113, false, -122, -60, 122, true, 0}, {60, true, -100, -40, 100, true, 0},
           {200, false, -110, -50, 110, true, 0}, {1, false, -110, -45, 110, true, 0}, {1, false, -40, -50, 40, true, 0},
           {113, false, -110, -20, 110, false, 0}, {113, false, -110, -48, 110, true, -40},
           {113, false, -110, -300, 110, true, 0}, {113, false, -110, 100, 110, false, 0}})
    for (int identity = 0; identity < 2; ++identity) {
      const slong n = 20 + static_cast<slong>(rng() % 40);
      std::vector<wide_int> S;
      eulervop::detail::integer_poly Sp, q;
      ball hl, c0, babs, ends[2], truth[2];
      random_inputs(S, Sp.p, hl, n, c.bits, c.hl_bits, c.negative, rng);
      std::vector<ball> b;
      integral(b, c0, babs, Sp.p, n, hl, c.e, identity);
      subtracted(q.p, b, c0, c.f, c.cancel, rng);
      if (c.radius != 0) arb_add_error_2exp_si(hl.get(), arf_abs_bound_lt_2exp_si(arb_midref(hl.get())) + c.radius);
      mag_value rem;
      mag_set_ui_2exp_si(rem.m, 1, -300);
      for (int end = 0; end < 2; ++end) {  // the truth at both ends of hl's ball
        (end ? arb_get_ubound_arf : arb_get_lbound_arf)(arb_midref(ends[end].get()), hl.get(), ARF_PREC_EXACT);
        integral(b, c0, babs, Sp.p, n, ends[end], c.e, identity);
        residual_sum(truth[end], b, c0, q.p, c.f, ends[end], rem.m);
      }
      eulervop::detail::integral_residual ir;
      ir.set_factors(n + 1, hl, c.e, 64);
      for (int path = 0; path < 2; ++path) {
        mag_value out;
        if (path == 0)
          ir.sup(out.m, eulervop::detail::wide_sums{&S}, rem.m, q.p, c.f, identity);
        else
          ir.sup(out.m, eulervop::detail::flint_sums{Sp.p}, rem.m, q.p, c.f, identity);
        ball bound, slack;
        arf_set_mag(arb_midref(bound.get()), out.m);
        const std::string where = "hl bits " + std::to_string(c.hl_bits) + " f " + std::to_string(c.f) + " path " +
                                  std::to_string(path) + " bound " + std::to_string(mag_get_d(out.m));
        EXPECT_TRUE(arb_le(truth[0].get(), bound.get()) && arb_le(truth[1].get(), bound.get())) << where;
        arb_max(slack.get(), truth[0].get(), truth[1].get(), truth_prec);
        arb_mul_2exp_si(bound.get(), slack.get(), -20);
        arb_add(slack.get(), slack.get(), bound.get(), truth_prec);
        arb_mul_2exp_si(bound.get(), babs.get(), c.radius != 0 ? c.radius + 3 : -60);
        arb_add(slack.get(), slack.get(), bound.get(), truth_prec);
        arf_set_mag(arb_midref(bound.get()), out.m);
        EXPECT_TRUE(arb_le(bound.get(), slack.get())) << where;
      }
    }
}

}  // namespace

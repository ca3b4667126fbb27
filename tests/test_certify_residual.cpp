// The fast certificate's residual (certify/detail/picard_residual.hpp) and a row's value of the
// segment polynomial (certify/row_enclosure.hpp, polynomial_at), both computed on exact integers
// and rounded MPFR numbers with derived bounds of their roundings, against the same quantities in
// interval arithmetic at 600 bits, computed from their definitions (an independent computation at
// a higher precision):
//   q_k = (2/N) sum_j'' v_j T_k(s_j) (halved at k = 0 and N), P = X0 + q,
//   f_i = a_i P_j P_k + G_i with T_m T_n = (T_{m+n} + T_{|m-n|}) / 2,
//   r = v_0 - q + hl int_{-1}^s f, its constant term from the integral's own (not from r(-1) = 0,
//   which the code under test uses).
// Each claimed bound must hold against the 600-bit enclosures; on a segment whose residual is
// large (a node moved by 1e-22), the bounds must also be close to it, so a bound that grew by
// orders of magnitude would fail.
#include <eulervop/certify/certifier.hpp>
#include <eulervop/certify/row_enclosure.hpp>
#include <eulervop/reference/integrate.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

using eulervop::chebyshev_segment;
using eulervop::exact_problem;
using eulervop::interval;
using eulervop::quad;
using eulervop::detail::real;

constexpr mpfr_prec_t working_bits = 113 + 64;
constexpr mpfr_prec_t oracle_bits = 600;

// Segments of a quad reference of Eq. 5 with torque G (quad) from Omega(0), to tau_end.
std::vector<chebyshev_segment<quad>> segments_of(const std::array<quad, 3>& G, const std::array<quad, 3>& Omega0,
                                                 double tau_end) {
  eulervop::euler_problem<quad> run;
  run.torque.G = {G[0], G[1], G[2]};
  run.Omega0 = {Omega0[0], Omega0[1], Omega0[2]};
  std::vector<chebyshev_segment<quad>> out;
  eulervop::chebyshev_picard<eulervop::euler_problem<quad>> integrator(eulervop::picard_settings{});
  integrator.run_segments(run, quad(tau_end), [&](const chebyshev_segment<quad>& seg, const std::vector<quad>&) {
    out.push_back(seg);
  });
  return out;
}

// P's coefficients (3 x n1) at `bits` from the definition, enclosed.
std::vector<interval> coefficients_oracle(const chebyshev_segment<quad>& seg, mpfr_prec_t bits) {
  const std::size_t n1 = seg.values.size(), N = n1 - 1;
  interval pi = interval::zero(bits), angle = interval::zero(bits), term = interval::zero(bits);
  mpfi_const_pi(pi.get());
  std::vector<interval> p(3 * n1, interval::zero(bits));
  interval v = interval::zero(bits);
  for (int i = 0; i < 3; ++i)
    for (std::size_t k = 0; k < n1; ++k) {
      interval& c = p[i * n1 + k];
      for (std::size_t j = 0; j < n1; ++j) {
        eulervop::detail::set_exact(v, seg.values[j][i]);
        // T_k(s_j) = (-1)^k cos(k j pi / N)
        mpfi_mul_ui(angle.get(), pi.get(), static_cast<unsigned long>(k * j));
        mpfi_div_ui(angle.get(), angle.get(), static_cast<unsigned long>(N));
        mpfi_cos(term.get(), angle.get());
        if (k % 2) mpfi_neg(term.get(), term.get());
        mpfi_mul(term.get(), term.get(), v.get());
        if (j == 0 || j == N) mpfi_mul_2si(term.get(), term.get(), -1);
        mpfi_add(c.get(), c.get(), term.get());
      }
      mpfi_mul_ui(c.get(), c.get(), 2);
      mpfi_div_ui(c.get(), c.get(), static_cast<unsigned long>(N));
      if (k == 0 || k == N) mpfi_mul_2si(c.get(), c.get(), -1);
    }
  return p;  // q's coefficients; X0 is added by the callers
}

// r (3 x (2N + 2)) at `bits` from the definition.
std::vector<interval> residual_oracle(const chebyshev_segment<quad>& seg, const exact_problem& problem,
                                      mpfr_prec_t bits) {
  const std::array<int, 3> a = eulervop::unit_coefficients(problem);
  const std::size_t n1 = seg.values.size(), np = 2 * n1 - 1, nr = 2 * n1;
  const std::vector<interval> q = coefficients_oracle(seg, bits);
  std::vector<interval> p = q;
  interval t = interval::zero(bits), hl = interval::zero(bits);
  for (int i = 0; i < 3; ++i) {
    eulervop::detail::set_exact(t, seg.base[i]);
    mpfi_add(p[i * n1].get(), p[i * n1].get(), t.get());
    eulervop::detail::set_exact(t, seg.base_lo[i]);
    mpfi_add(p[i * n1].get(), p[i * n1].get(), t.get());
  }
  eulervop::detail::set_exact(hl, seg.half_length);
  std::vector<interval> r(3 * nr, interval::zero(bits));
  for (int i = 0; i < 3; ++i) {
    const auto [j, k] = exact_problem::quadratic_pair[i];
    std::vector<interval> f(np, interval::zero(bits));
    for (std::size_t m = 0; m < n1; ++m)
      for (std::size_t n = 0; n < n1; ++n) {
        mpfi_mul(t.get(), p[j * n1 + m].get(), p[k * n1 + n].get());
        mpfi_mul_2si(t.get(), t.get(), -1);
        mpfi_add(f[m + n].get(), f[m + n].get(), t.get());
        const std::size_t d = m > n ? m - n : n - m;
        mpfi_add(f[d].get(), f[d].get(), t.get());
      }
    for (interval& x : f) mpfi_mul_si(x.get(), x.get(), a[i]);
    mpfi_add(f[0].get(), f[0].get(), problem.torque.G[i].get());
    // b_1 = f_0 - f_2/2, b_k = (f_{k-1} - f_{k+1}) / (2k), b_0 = sum_{k>=1} (-1)^(k+1) b_k.
    std::vector<interval> b(nr, interval::zero(bits));
    for (std::size_t kk = 1; kk < nr; ++kk) {
      interval& bk = b[kk];
      mpfi_set(bk.get(), f[kk - 1].get());
      if (kk + 1 < np) {
        mpfi_set(t.get(), f[kk + 1].get());
        if (kk == 1) mpfi_mul_2si(t.get(), t.get(), -1);
        mpfi_sub(bk.get(), bk.get(), t.get());
      }
      if (kk > 1) mpfi_div_ui(bk.get(), bk.get(), static_cast<unsigned long>(2 * kk));
      if (kk % 2)
        mpfi_add(b[0].get(), b[0].get(), bk.get());
      else
        mpfi_sub(b[0].get(), b[0].get(), bk.get());
    }
    for (std::size_t kk = 0; kk < nr; ++kk) {
      interval& rk = r[i * nr + kk];
      mpfi_mul(rk.get(), b[kk].get(), hl.get());
      if (kk < n1) mpfi_sub(rk.get(), rk.get(), q[i * n1 + kk].get());
    }
    eulervop::detail::set_exact(t, seg.values[0][i]);  // v_0
    mpfi_add(r[i * nr].get(), r[i * nr].get(), t.get());
  }
  return r;
}

struct residual_check {
  double rrad_over_size;  // rrad / sum |rd_k|, per component (the largest)
  double rsup_over_size;  // the claimed sup |r| over the oracle's sum |r_k| (the largest)
};

// Checks the residual's claims for one segment against the oracle; returns their looseness.
residual_check check_residual(const chebyshev_segment<quad>& seg, const exact_problem& problem) {
  const std::size_t N = seg.values.size() - 1, nr = 2 * N + 2;
  eulervop::detail::segment_polynomial P(working_bits, N);
  eulervop::detail::node_transform transform(working_bits, N);
  P.place(seg);
  P.load(seg);
  P.enclose(transform);
  eulervop::detail::picard_residual R(working_bits, N, problem.torque.G, eulervop::unit_coefficients(problem));
  R.compute(P);
  const std::vector<interval> r = residual_oracle(seg, problem, oracle_bits);
  residual_check out{0, 0};
  real magnitude(oracle_bits), distance(oracle_bits), end(oracle_bits), x(oracle_bits);
  interval sum = interval::zero(oracle_bits);
  for (int i = 0; i < 3; ++i) {
    mpfr_set_ui(magnitude.get(), 0, MPFR_RNDU);
    mpfr_set_ui(distance.get(), 0, MPFR_RNDU);
    mpfi_set_ui(sum.get(), 0);
    double size = 0;
    for (std::size_t k = 0; k < nr; ++k) {
      const interval& rk = r[i * nr + k];
      mpfi_mag(x.get(), rk.get());
      mpfr_add(magnitude.get(), magnitude.get(), x.get(), MPFR_RNDU);
      mpfi_add(sum.get(), sum.get(), rk.get());
      // max over the oracle's interval of |x 2^s - rd_k|
      const double d = R.rd[i * nr + k];
      size += std::abs(d);
      mpfr_set_ui(x.get(), 0, MPFR_RNDU);
      for (const mpfr_srcptr e : {&rk.get()->left, &rk.get()->right}) {
        mpfr_mul_2si(end.get(), e, R.r_scale, MPFR_RNDN);  // exact
        mpfr_sub_d(end.get(), end.get(), d, MPFR_RNDA);
        mpfr_abs(end.get(), end.get(), MPFR_RNDU);
        mpfr_max(x.get(), x.get(), end.get(), MPFR_RNDU);
      }
      mpfr_add(distance.get(), distance.get(), x.get(), MPFR_RNDU);
    }
    EXPECT_GE(mpfr_cmp(&R.rsup[i].get()->right, magnitude.get()), 0) << "sup |r| of component " << i;
    EXPECT_GT(mpfi_is_inside(sum.get(), R.r1[i].get()), 0) << "r(1) of component " << i;
    EXPECT_LE(mpfr_cmp_d(distance.get(), R.rrad[i]), 0) << "the doubles of r, component " << i;
    out.rrad_over_size = std::max(out.rrad_over_size, R.rrad[i] / size);
    out.rsup_over_size =
        std::max(out.rsup_over_size, mpfr_get_d(&R.rsup[i].get()->right, MPFR_RNDU) / mpfr_get_d(magnitude.get(), MPFR_RNDD));
  }
  return out;
}

exact_problem paper_problem() {
  return eulervop::exact_problem_of({"1.0", "1.0", "1.0"}, {"0.5", "0", "1.0"}, working_bits);
}

TEST(CertifyResidual, BoundsHoldOnTheReferencesSegments) {
  const auto segments = segments_of({quad(1), quad(1), quad(1)}, {quad(0.5), quad(0), quad(1)}, 20);
  ASSERT_GT(segments.size(), 100u);
  const exact_problem problem = paper_problem();
  for (const std::size_t index : {std::size_t{0}, std::size_t{1}, segments.size() / 2, segments.size() - 1})
    check_residual(segments[index], problem);
}

// A decimal torque (G not a point at any precision) and another modulus.
TEST(CertifyResidual, BoundsHoldWithADecimalTorque) {
  const auto segments = segments_of({quad("0.1"), quad("-0.3"), quad("0.7")}, {quad("0.3"), quad(0), quad("0.7")}, 20);
  const exact_problem problem =
      eulervop::exact_problem_of({"0.1", "-0.3", "0.7"}, {"0.3", "0", "0.7"}, working_bits);
  for (const std::size_t index : {std::size_t{0}, segments.size() / 3, segments.size() - 1})
    check_residual(segments[index], problem);
}

// One node moved by 1e-22: the residual is then about 1e-22, far above every rounding, and the
// bounds must stay close to it (derived: the roundings at 177 bits are near 1e-50 of the state).
TEST(CertifyResidual, BoundsAreTightOnALargeResidual) {
  auto segments = segments_of({quad(1), quad(1), quad(1)}, {quad(0.5), quad(0), quad(1)}, 5);
  chebyshev_segment<quad> seg = segments[segments.size() / 2];
  seg.values[seg.values.size() / 3][1] += quad(1e-22);
  const residual_check c = check_residual(seg, paper_problem());
  EXPECT_LT(c.rrad_over_size, 1e-12);
  EXPECT_LT(c.rsup_over_size, 1 + 1e-9);
}

// polynomial_at against P(tau) at 600 bits from the oracle's coefficients: the enclosure holds
// the value, and its width stays far below the reference's own precision (1e-40 against 1e-34).
TEST(CertifyRowValue, EnclosesThePolynomialTightly) {
  const auto segments = segments_of({quad(1), quad(1), quad(1)}, {quad(0.5), quad(0), quad(1)}, 20);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> where(0, 1);
  for (const std::size_t index : {std::size_t{0}, segments.size() / 2, segments.size() - 1}) {
    const chebyshev_segment<quad>& seg = segments[index];
    const std::size_t N = seg.values.size() - 1, n1 = N + 1;
    eulervop::detail::segment_polynomial P(working_bits, N);
    eulervop::detail::node_transform transform(working_bits, N);
    P.place(seg);
    P.load(seg);
    P.enclose(transform);
    const std::vector<interval> q = coefficients_oracle(seg, oracle_bits);
    for (int trial = 0; trial < 20; ++trial) {
      const quad tau = seg.tau_begin + 2 * seg.half_length * quad(where(random));
      interval dt = interval::zero(working_bits);
      eulervop::detail::set_exact(dt, tau);
      mpfi_sub(dt.get(), dt.get(), P.a.get());
      std::vector<interval> value(3, interval::zero(working_bits));
      eulervop::detail::polynomial_at(P, dt, value);
      // The oracle: s = (tau - a) / hl - 1 and sum q_k T_k(s) + X0 at 600 bits.
      interval s = interval::zero(oracle_bits), a = interval::zero(oracle_bits), t = interval::zero(oracle_bits);
      eulervop::detail::set_exact(s, tau);
      eulervop::detail::set_exact(a, seg.tau_begin);
      mpfi_sub(s.get(), s.get(), a.get());
      eulervop::detail::set_exact(t, seg.half_length);
      mpfi_div(s.get(), s.get(), t.get());
      mpfi_sub_ui(s.get(), s.get(), 1);
      for (int i = 0; i < 3; ++i) {
        interval exact = interval::zero(oracle_bits), T0 = interval::zero(oracle_bits), T1 = s, T2 = s;
        mpfi_set_ui(T0.get(), 1);
        eulervop::detail::set_exact(exact, seg.base[i]);
        eulervop::detail::set_exact(t, seg.base_lo[i]);
        mpfi_add(exact.get(), exact.get(), t.get());
        for (std::size_t k = 0; k < n1; ++k) {
          const interval& Tk = k == 0 ? T0 : T1;
          mpfi_mul(t.get(), q[i * n1 + k].get(), Tk.get());
          mpfi_add(exact.get(), exact.get(), t.get());
          if (k >= 1) {  // T_{k+1} = 2 s T_k - T_{k-1}
            mpfi_mul(T2.get(), T1.get(), s.get());
            mpfi_mul_2si(T2.get(), T2.get(), 1);
            mpfi_sub(T2.get(), T2.get(), T0.get());
            std::swap(T0, T1);
            std::swap(T1, T2);
          }
        }
        EXPECT_GT(mpfi_is_inside(exact.get(), value[i].get()), 0) << "segment " << index << ", component " << i;
        real width(64);
        eulervop::detail::width_up(width, value[i]);
        EXPECT_LT(mpfr_get_d(width.get(), MPFR_RNDU), 1e-40) << "segment " << index << ", component " << i;
      }
    }
  }
}

}  // namespace

// The linear flow of the general path of --certify (include/eulervop/certify/detail/
// ball_linear_flow.hpp): the exact variational matrix and signed integral term lie within the
// proven distances of the double-precision ones. Truth: Taylor series at 400 bits (the Jacobian a
// polynomial, so the solutions are entire).
#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/ball_linear_flow.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/core/scalar.hpp>

#include <gtest/gtest.h>

#include "ball_test_support.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace {

using namespace eulervop::test::ball_support;

// The linear flow (ball_linear_flow.hpp) for a Jacobian J(s) of random polynomials: at points of
// the segment, the exact Phi (Phi' = hl J Phi, Phi(-1) = I) and u (u' = hl J (u + r), u(-1) = 0)
// lie within the proven distance of Phi_num and u_num, in the weighted norm:
//   |W (Phi - Phi_num) W^-1|_2 <= phi_residual (1 + dt exp(j dt) j) and the same for u, with
// dt = hl (s + 1) and j >= |W J W^-1|_2 (>= its logarithmic norm), here the Frobenius norm of
// the entries' sup bounds. The exact solutions: Taylor series in t = s + 1 at 400 bits, in steps
// of at most 1/8 (J and r re-expanded at each step's start; 60 terms leave less than 2^-200).
TEST(BallLinearFlow, PhiAndUHoldTheExactSolutions) {
  const eulervop::mpfr_precision_scope scope(400);
  struct flow_case {
    std::size_t D;
    double size, hl;  // J's entries up to `size`; half the segment's length
    int q_weight;     // the weight 2^-q_weight of components 3..6
    double r_size;    // the residual r's size (its grid against u's decides the 128-bit path)
  };
  using poly = std::vector<mpfr_real>;
  // T_k(t - 1) as polynomials in t, k < 40.
  std::vector<poly> T = {{mpfr_real(1)}, {mpfr_real(-1), mpfr_real(1)}};
  for (std::size_t k = 2; k < 40; ++k) {
    poly next(k + 1, mpfr_real(0));
    for (std::size_t i = 0; i < T[k - 1].size(); ++i) {
      next[i + 1] += 2 * T[k - 1][i];
      next[i] -= 2 * T[k - 1][i];
    }
    for (std::size_t i = 0; i < T[k - 2].size(); ++i) next[i] -= T[k - 2][i];
    T.push_back(next);
  }
  const auto monomial = [&](const chebyshev_model& c) {
    poly out(40, mpfr_real(0));
    for (slong k = 0; k < c.length(); ++k) {
      const mpfr_real ck = to_mpfr(arb_midref(c.coeff(k)));
      for (std::size_t i = 0; i < T[static_cast<std::size_t>(k)].size(); ++i) out[i] += ck * T[static_cast<std::size_t>(k)][i];
    }
    return out;
  };
  // p(t0 + x) as a polynomial in x (Horner's shifts).
  const auto shifted = [](poly p, const mpfr_real& t0) {
    for (std::size_t i = 0; i + 1 < p.size(); ++i)
      for (std::size_t j = p.size() - 1; j-- > i;) p[j] += t0 * p[j + 1];
    return p;
  };
  std::mt19937_64 rng(11);
  for (const flow_case& fc : {flow_case{3, 1.0, 0.8, 0, 1e-30}, flow_case{7, 0.6, 1.5, 3, 1e-33},
                              flow_case{7, 2e-3, 0.9, 0, 1e-20}, flow_case{3, 2.0, 1.2, 0, 1e-34}}) {
    const std::size_t D = fc.D, DD = D * D;
    std::vector<chebyshev_model> J(DD);
    for (std::size_t q = 0; q < DD; ++q) {
      if (rng() % 5 == 0) continue;  // a zero entry: the iteration skips what stays zero
      J[q] = random_model(rng, 14, 0.4, 0, 0);
      eulervop::detail::scale(J[q], decimal(fc.size), 300);
    }
    std::vector<chebyshev_model> r(D);
    for (std::size_t i = 0; i < D; ++i) {
      r[i] = random_model(rng, 40, 0.9, 0, 0);
      eulervop::detail::scale(r[i], decimal(fc.r_size), 300);
    }
    std::vector<double> weight(D, 1.0);
    for (std::size_t i = 3; i < D; ++i) weight[i] = std::ldexp(1.0, -fc.q_weight);
    const ball hl = decimal(fc.hl);
    // j: the Frobenius norm of W J W^-1 from the entries' sup bounds.
    mag_value jm, m;
    for (std::size_t i = 0; i < D; ++i)
      for (std::size_t k = 0; k < D; ++k) {
        eulervop::detail::sup_bound(m.m, J[i * D + k]);
        mag_mul_2exp_si(m.m, m.m, std::ilogb(weight[i]) - std::ilogb(weight[k]));
        mag_addmul(jm.m, m.m, m.m);
      }
    mag_sqrt(jm.m, jm.m);
    const double j = mag_get_d(jm.m);
    eulervop::detail::ball_linear_flow flow(D);
    flow.load_jacobian(J, weight);
    ASSERT_TRUE(flow.variational(hl, j * 2 * fc.hl));
    ASSERT_TRUE(flow.integral_term(r, hl));
    const double phi_res = mag_get_d(flow.phi_residual()), u_res = mag_get_d(flow.u_residual());
    // The bounds are of use: Phi to about six digits or more, u's far below r.
    EXPECT_LT(phi_res, 1e-6) << "D " << D;
    EXPECT_LT(u_res, 1e-4 * fc.r_size) << "D " << D;
    std::vector<poly> Jm(DD), rm(D);
    for (std::size_t q = 0; q < DD; ++q) Jm[q] = monomial(J[q]);
    for (std::size_t i = 0; i < D; ++i) rm[i] = monomial(r[i]);
    const mpfr_real h = to_mpfr(arb_midref(hl.get()));
    std::vector<mpfr_real> phi(DD, mpfr_real(0)), ue(D, mpfr_real(0));
    for (std::size_t i = 0; i < D; ++i) phi[i * D + i] = 1;
    mpfr_real t0 = 0;
    const std::size_t terms = 60;
    for (const double sd : {-0.5, 0.0, 0.37, 1.0}) {
      const mpfr_real target = mpfr_real(sd) + 1;
      while (t0 < target) {
        const mpfr_real step = min(target - t0, mpfr_real(0.125));
        std::vector<poly> Js(DD), rs(D);
        for (std::size_t q = 0; q < DD; ++q) Js[q] = shifted(Jm[q], t0);
        for (std::size_t i = 0; i < D; ++i) rs[i] = shifted(rm[i], t0);
        std::vector<std::vector<mpfr_real>> P(terms, std::vector<mpfr_real>(DD, mpfr_real(0))),
            U(terms, std::vector<mpfr_real>(D, mpfr_real(0)));
        P[0] = phi;
        U[0] = ue;
        for (std::size_t n = 0; n + 1 < terms; ++n)
          for (std::size_t i = 0; i < D; ++i) {
            for (std::size_t c = 0; c < D; ++c) {
              mpfr_real acc = 0;
              for (std::size_t a = 0; a <= n && a < 40; ++a)
                for (std::size_t k = 0; k < D; ++k) acc += Js[i * D + k][a] * P[n - a][k * D + c];
              P[n + 1][i * D + c] = h * acc / mpfr_real(n + 1);
            }
            mpfr_real acc = 0;
            for (std::size_t a = 0; a <= n && a < 40; ++a)
              for (std::size_t k = 0; k < D; ++k)
                acc += Js[i * D + k][a] * (U[n - a][k] + (n - a < 40 ? rs[k][n - a] : mpfr_real(0)));
            U[n + 1][i] = h * acc / mpfr_real(n + 1);
          }
        std::fill(phi.begin(), phi.end(), mpfr_real(0));
        std::fill(ue.begin(), ue.end(), mpfr_real(0));
        for (std::size_t n = terms; n-- > 0;) {
          for (std::size_t q = 0; q < DD; ++q) phi[q] = phi[q] * step + P[n][q];
          for (std::size_t i = 0; i < D; ++i) ue[i] = ue[i] * step + U[n][i];
        }
        t0 += step;
      }
      slong length = flow.phi_length();
      for (const eulervop::detail::chebyshev_model& m : flow.u()) length = std::max(length, m.length());
      const eulervop::detail::chebyshev_values Ts(length, point(mpfr_real(sd)), 400);
      std::vector<ball> Pn, un(D);
      flow.Phi_at(Ts, Pn, 400);
      for (std::size_t i = 0; i < D; ++i) eulervop::detail::evaluate(un[i], flow.u()[i], Ts, 400);
      const double dt = fc.hl * (sd + 1);
      const double factor = 1 + dt * std::exp(j * dt) * j;
      mpfr_real phi_err2 = 0, u_err2 = 0;
      for (std::size_t i = 0; i < D; ++i) {
        for (std::size_t k = 0; k < D; ++k) {
          const mpfr_real d = (phi[i * D + k] - to_mpfr(arb_midref(Pn[i * D + k].get()))) * weight[i] / weight[k];
          phi_err2 += d * d;
        }
        const mpfr_real d = (ue[i] - to_mpfr(arb_midref(un[i].get()))) * weight[i];
        u_err2 += d * d;
      }
      const double phi_err = static_cast<double>(sqrt(phi_err2)), u_err = static_cast<double>(sqrt(u_err2));
      EXPECT_LE(phi_err, phi_res * factor) << "D " << D << " s " << sd;
      EXPECT_LE(u_err, u_res * factor) << "D " << D << " s " << sd;
      // Not vacuous: Phi_num's distance is within a few orders of its residual (the factor is
      // this test's own, from a crude j).
      if (sd > -1) EXPECT_GT(phi_err, 1e-4 * phi_res) << "D " << D << " s " << sd;
    }
  }
}

}  // namespace

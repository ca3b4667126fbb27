// The Taylor-series peer of the benchmarks (benchmarks/taylor_peer.hpp): its compiled jets of
// formulas of time and its integration, so that the speed it is measured at is that of a correct
// integrator (docs/benchmarks.md). Speed itself is measured in bench_problems, not here.
#include "../benchmarks/taylor_peer.hpp"

#include <eulervop/core/scalar.hpp>
#include <eulervop/scene/expression_parser.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace {

using Q = eulervop::quad;
using M = eulervop::mpfr_real;
using eulervop::bench::time_tape;

eulervop::expression parse(const std::string& text) {
  return eulervop::scene::parse_expression(text, eulervop::scene::expression_variables{{"t", "", "", ""}});
}

struct formula_case {
  std::string text;
  std::function<M(const M&)> f;  // the same formula in MPFR
};

// The jet's polynomial at t0 + s against the formula evaluated directly in MPFR at 200 bits at
// t0 + s (an independent evaluation): with 31 coefficients and |s| = 1/32 the truncation is below
// 2^-150 for these formulas (radius of convergence >= 1 around t0), so the difference is the
// jet's rounding alone: bounded by 64 epsilon of quad relative to max(1, |f|).
TEST(TaylorPeerTape, JetsMatchTheFormulaAtNearbyTimes) {
  eulervop::mpfr_precision_scope scope(200);
  using std::cos;
  using std::exp;
  using std::log;
  using std::sin;
  using std::sqrt;
  const std::vector<formula_case> cases = {
      {"0.25*sin(t)^2", [](const M& t) { return M(M("0.25") * sin(t) * sin(t)); }},
      {"cos(t)^2 - sin(2*t + 1)", [](const M& t) { return M(cos(t) * cos(t) - sin(2 * t + 1)); }},
      {"sin(t*t) + cos(t^3)", [](const M& t) { return M(sin(t * t) + cos(t * t * t)); }},
      {"exp(t/3)/(1 + t^2)", [](const M& t) { return M(exp(t / 3) / (1 + t * t)); }},
      {"log(2 + t) * sqrt(1 + t^2)", [](const M& t) { return M(log(2 + t) * sqrt(1 + t * t)); }},
      {"1/t^2 - (t - 1)^4 + pi", [](const M& t) {
         return M(1 / (t * t) - (t - 1) * (t - 1) * (t - 1) * (t - 1) + boost::math::constants::pi<M>());
       }},
      {"-(0.5*t) * exp(sin(t))", [](const M& t) { return M(-(M("0.5") * t) * exp(sin(t))); }},
  };
  const std::size_t n = 31;
  const Q eps = std::numeric_limits<Q>::epsilon();
  for (const formula_case& c : cases) {
    time_tape<Q> tape(parse(c.text), n);
    for (const char* t0_text : {"0.75", "1.25", "2.5"}) {
      const Q t0(t0_text);
      const Q* jet = tape.at(t0);
      for (const char* s_text : {"-0.03125", "0.03125"}) {
        const Q s(s_text);
        Q v = jet[n - 1];
        for (std::size_t k = n - 1; k-- > 0;) v = v * s + jet[k];
        const M truth = c.f(M(t0_text) + M(s_text));
        const M scale = std::max(M(1), M(abs(truth)));
        const double err = static_cast<double>(M(abs(M(v) - truth) / scale));
        EXPECT_LE(err, 64 * static_cast<double>(eps)) << c.text << " at t0 = " << t0_text << ", s = " << s_text;
      }
    }
  }
}

TEST(TaylorPeerTape, DeclinesFormulasOfTheState) {
  const eulervop::expression e =
      eulervop::scene::parse_expression("y1 * t", eulervop::scene::expression_variables{{"t", "y1", "y2", "y3"}});
  EXPECT_THROW(time_tape<Q>(e, 5), std::invalid_argument);
}

// The torque-free body keeps the quadratics sum c_i y_i^2 with c orthogonal to a: for Eq. 1,
// d/dt sum c_i y_i^2 = 2 y1 y2 y3 sum c_i a_i. A wrong coefficient of the jets or a step beyond
// the polynomial's accuracy breaks them; a correct run holds them to its roundings, a few epsilon
// per step (about 1e-31 over the run at worst): the bound is 2^-100.
TEST(TaylorPeerIntegrate, TorqueFreeBodyKeepsItsQuadraticInvariants) {
  eulervop::bench::taylor_problem<Q> p;
  p.a = {Q(-2), Q("1.25"), Q("-0.5")};  // the SciML rigid body's coefficients
  p.y0 = {Q(1), Q(0), Q("0.9")};
  std::vector<Q> times;
  for (int i = 0; i <= 100; ++i) times.push_back(Q(i));
  std::vector<eulervop::vec3<Q>> ys(times.size());
  const auto st = eulervop::bench::taylor_integrate<Q>(p, std::numeric_limits<Q>::epsilon(), times,
                                                       [&](std::size_t i, const eulervop::vec3<Q>& y) { ys[i] = y; });
  EXPECT_EQ(st.order, 40u);  // ceil(-ln(epsilon) / 2 + 1) for epsilon = 2^-112
  EXPECT_GT(st.steps, 100u);
  // c orthogonal to a = (-2, 1.25, -0.5): (1.25, 2, 0) and (0.5, 0, -2).
  const std::array<std::array<Q, 3>, 2> cs = {{{Q("1.25"), Q(2), Q(0)}, {Q("0.5"), Q(0), Q(-2)}}};
  for (const auto& c : cs) {
    const auto invariant = [&](const eulervop::vec3<Q>& y) {
      return c[0] * y[0] * y[0] + c[1] * y[1] * y[1] + c[2] * y[2] * y[2];
    };
    const Q i0 = invariant(p.y0);
    for (const auto& y : ys)
      EXPECT_LE(static_cast<double>(abs(invariant(y) - i0)), 0x1p-100) << static_cast<double>(i0);
  }
}

}  // namespace

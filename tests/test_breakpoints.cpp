// Breakpoints of a piecewise torque in the reference integrator (docs/design.md, "Breakpoints"):
// every segment ends on a breakpoint, so no Chebyshev interpolant spans a change of formula.
//
// Truth: an axisymmetric body in the direct form, a = (-1, 1, 0) (I = (1, 1, 2)), so y3' = g3 and
// z = y1 + i y2 obeys z' = i y3 z: y3 and the phase Phi = int y3 dt integrate in closed form,
// evaluated in T. The torque is HNW's EULR forcing on the third axis, g3 = 0.25 sin^2 t on
// [3 pi, 4 pi] and 0 elsewhere: g3 and g3' vanish at both ends and g3'' jumps (by 0.5), so the
// solution has a jump in its third derivative there.
//   y3(t)  = y30 + 0.25 ((s - 3 pi) / 2 - sin(2 s) / 4),            s = clamp(t, 3 pi, 4 pi)
//   Phi(t) = y30 t + 0.25 ((s - 3 pi)^2 / 4 + (cos 2s - 1) / 8) + (t - 4 pi)^+ pi / 8
// Bound: as tests/test_torque_paths.cpp, 256 eps of the state's size 1 + |y|, the phase reaching
// about 25 rad over [0, 20]. Measured: see the test's printed figures.
// Without breakpoints (the same formulas behind a torque type that hides them) the segments
// that straddle 3 pi and 4 pi interpolate a function whose third derivative jumps: the tail
// estimate no longer decays geometrically, and the run either needs many more segments or
// misses the tolerance. The second test shows the difference, so a reference that stopped
// honouring breakpoints fails it.
#include <eulervop/model/expression_torque.hpp>
#include <eulervop/model/torque_law.hpp>
#include <eulervop/reference/integrate.hpp>
#include <eulervop/scene/expression_parser.hpp>

#include "type_test_names.hpp"

#include <gtest/gtest.h>

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;

std::shared_ptr<const eulervop::torque_law> eulr_forcing() {
  const eulervop::scene::expression_variables vars{{"t", "y1", "y2", "y3"}};
  auto law = std::make_shared<eulervop::torque_law>();
  law->name = "f";
  law->time_name = "t";
  law->base = {eulervop::constant_expression("0"), eulervop::constant_expression("0"),
               eulervop::constant_expression("0")};
  eulervop::torque_piece window;
  window.from = eulervop::scene::parse_expression("3*pi", vars);
  window.to = eulervop::scene::parse_expression("4*pi", vars);
  window.terms = {eulervop::constant_expression("0"), eulervop::constant_expression("0"),
                  eulervop::scene::parse_expression("0.25*sin(t)^2", vars)};
  law->pieces.push_back(window);
  return law;
}

// The same torque with its breakpoints hidden: evaluated by the time alone (right-continuous).
template <class T>
struct hidden_breakpoints {
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = false;
  eulervop::time_torque<T> g;
  vec3<T> value(const T& t, const vec3<T>& y) const { return g.value(t, y); }
};
template <class U, class T>
hidden_breakpoints<U> convert_torque(const hidden_breakpoints<T>& h) {
  return {convert_torque<U>(h.g)};
}

template <class T, class Torque>
eulervop::euler_problem<T, Torque> axisymmetric(const Torque& g, const vec3<T>& y0) {
  eulervop::euler_problem<T, Torque> p;
  p.form = eulervop::equation_form::direct;
  p.a = {T(-1), T(1), T(0)};
  p.torque = g;
  p.Omega0 = y0;
  p.tau0 = T(0);
  return p;
}

template <class T>
vec3<T> exact(const T& t, const vec3<T>& y0) {
  using std::cos;
  using std::sin;
  const T pi = boost::math::constants::pi<T>();
  const T a = 3 * pi, b = 4 * pi;
  const T s = t < a ? a : (t > b ? b : t);
  const T y3 = y0[2] + (s - a) / 8 - sin(2 * s) / 16;
  T phase = y0[2] * t + ((s - a) * (s - a) / 4 + (cos(2 * s) - 1) / 8) / 4;
  if (t > b) phase += (t - b) * pi / 8;
  const T c = cos(phase), si = sin(phase);
  return {y0[0] * c - y0[1] * si, y0[0] * si + y0[1] * c, y3};
}

template <class T>
class Breakpoints : public ::testing::Test {
 protected:
  std::optional<eulervop::mpfr_precision_scope> scope_ =
      std::is_same_v<T, mpfr_real> ? std::optional<eulervop::mpfr_precision_scope>(256) : std::nullopt;
};
using Types = ::testing::Types<quad, mpfr_real>;
TYPED_TEST_SUITE(Breakpoints, Types, scalar_test_names);

// Largest difference from the closed form at 401 times in [0, 20], in units of eps (1 + |y|).
template <class T, class Torque>
double error_in_eps(const Torque& g, eulervop::picard_stats& stats) {
  const vec3<T> y0 = {T(1), T(0), T(1)};
  const T t_end = T(20);
  const auto traj = eulervop::integrate_reference(axisymmetric<T>(g, y0), t_end, {}, {}, &stats);
  double worst = 0;
  for (int k = 0; k <= 400; ++k) {
    const T t = t_end * k / 400;
    const vec3<T> y = traj(t), e = exact(t, y0);
    using std::abs;
    for (int i = 0; i < 3; ++i)
      worst = std::max(worst, static_cast<double>(abs(y[i] - e[i]) / ((1 + abs(e[i])) * eulervop::epsilon<T>())));
  }
  return worst;
}

TYPED_TEST(Breakpoints, EulrForcingMatchesTheClosedForm) {
  using T = TypeParam;
  const eulervop::time_torque<T> g(eulr_forcing(), {});
  ASSERT_EQ(g.breakpoints().size(), 2u);
  eulervop::picard_stats stats;
  const double err = error_in_eps<T>(g, stats);
  std::cout << "[ breakpoints ] error " << err << " eps, " << stats.segments << " segments\n";
  EXPECT_LE(err, 256.0);
}

TYPED_TEST(Breakpoints, WithoutThemTheRunIsCostlierOrWorse) {
  using T = TypeParam;
  const eulervop::time_torque<T> g(eulr_forcing(), {});
  eulervop::picard_stats with, without;
  const double err_with = error_in_eps<T>(g, with);
  double err_without = 0;
  try {
    err_without = error_in_eps<T>(hidden_breakpoints<T>{g}, without);
  } catch (const eulervop::numerical_failure& e) {
    std::cout << "[ no breakpoints ] " << e.what() << "\n";
    return;  // the run could not even finish: the breakpoints are what made it work
  }
  std::cout << "[ no breakpoints ] error " << err_without << " eps, " << without.segments << " segments (with: "
            << err_with << " eps, " << with.segments << " segments, " << with.rejected << " rejected; without: "
            << without.rejected << " rejected)\n";
  // Honouring the breakpoints pays: at least 4x fewer rejected attempts or a 16x smaller error.
  EXPECT_TRUE(without.rejected >= 4 * std::max<std::size_t>(with.rejected, 1) || err_without >= 16 * err_with)
      << "with: " << with.rejected << " rejected, " << err_with << " eps; without: " << without.rejected << ", "
      << err_without;
}

}  // namespace

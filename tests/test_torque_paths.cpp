// The reference integrator on torques of time and of state (model/torque.hpp): the paths its
// torque traits select, checked against closed forms in quad and MPFR.
//
// Truth: bodies whose equations integrate in closed form (model/euler_problem.hpp, direct form
// with coefficients a):
//   - a sphere (a = 0): y' = g(t, y) alone;
//   - an axisymmetric body, I = (1, 1, 2): a = (-1, 1, 0), so y3' = g3 and z = y1 + i y2 obeys
//     z' = -i a1 y3 z + (g1 + i g2); z turns by the integral of y3.
// The torques are g = (0, 0, A sin^2 t) (of time: y3 = y30 + A (t/2 - sin 2t / 4)) and
// g = -D y (of the state: y3 = y30 e^{-D t}, z = z0 e^{-D t - i a1 Phi}, Phi = y30 (1 - e^{-D t}) / D),
// evaluated in T. Bound: the reference holds each segment's truncation below eps / 16 (relative)
// and its rounding near sqrt(N) eps, compensated across segments; the phase of the axisymmetric
// body reaches ~40 rad, and its error moves z by |z| times it. 256 eps of the state's size
// 1 + |y| leaves a margin of 20 over the largest measured (11.3 eps, MPFR, torque of time on the
// axisymmetric body; 0.5-1 eps elsewhere). A torque of time evaluated at the segment's start
// instead of the nodes' times errs by about 1e-3 here.
#include <eulervop/reference/integrate.hpp>

#include "test_torques.hpp"
#include "type_test_names.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;

// g = (0, 0, A sin^2 t): a torque of time alone.
template <class T>
struct sin2_torque {
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = false;
  T A;
  vec3<T> value(const T& t, const vec3<T>&) const {
    using std::sin;
    const T s = sin(t);
    return {T(0), T(0), A * s * s};
  }
};
template <class U, class T>
sin2_torque<U> convert_torque(const sin2_torque<T>& g) {
  return {static_cast<U>(g.A)};
}

using eulervop::test_torques::damping_torque;

template <class T>
class TorquePaths : public ::testing::Test {
 protected:
  // MPFR at 256 bits for the whole test; nothing for quad.
  std::optional<eulervop::mpfr_precision_scope> scope_ =
      std::is_same_v<T, mpfr_real> ? std::optional<eulervop::mpfr_precision_scope>(256) : std::nullopt;
};
using Types = ::testing::Types<quad, mpfr_real>;
TYPED_TEST_SUITE(TorquePaths, Types, scalar_test_names);

template <class T, class Torque>
eulervop::euler_problem<T, Torque> body(const vec3<T>& a, const Torque& g, const vec3<T>& y0) {
  eulervop::euler_problem<T, Torque> p;
  p.form = eulervop::equation_form::direct;
  p.a = a;
  p.torque = g;
  p.Omega0 = y0;
  p.tau0 = T(0);
  return p;
}

// The largest |y - exact(t)| over 41 times in [0, 20], relative to the state's size 1 + |y|.
template <class T, class Torque, class Exact>
T worst_error(const eulervop::euler_problem<T, Torque>& p, Exact&& exact) {
  using std::abs;
  const auto traj = eulervop::integrate_reference(p, T(20));
  T worst = 0;
  for (int i = 0; i <= 40; ++i) {
    const T t = T(i) / 2;
    const vec3<T> y = traj(t), e = exact(t);
    for (int c = 0; c < 3; ++c) worst = std::max<T>(worst, abs(y[c] - e[c]) / (1 + abs(e[c])));
  }
  return worst;
}

const char* const y0_text[3] = {"0.3", "-0.2", "0.9"};

template <class T>
vec3<T> y0() {
  return {T(y0_text[0]), T(y0_text[1]), T(y0_text[2])};
}

TYPED_TEST(TorquePaths, TorqueOfTimeOnASphere) {
  using T = TypeParam;
  const T A = T(1) / 4;
  const auto p = body<T>({T(0), T(0), T(0)}, sin2_torque<T>{A}, y0<T>());
  const T err = worst_error(p, [&](const T& t) {
    using std::sin;
    return vec3<T>{p.Omega0[0], p.Omega0[1], p.Omega0[2] + A * (t / 2 - sin(2 * t) / 4)};
  });
  EXPECT_LE(err, 256 * eulervop::epsilon<T>());
}

// z = z0 exp(-i a1 Phi), Phi = int_0^t y3 = y30 t + A (t^2 / 4 - (1 - cos 2t) / 8).
TYPED_TEST(TorquePaths, TorqueOfTimeOnAnAxisymmetricBody) {
  using T = TypeParam;
  const T A = T(1) / 4;
  const vec3<T> a = {T(-1), T(1), T(0)};
  const auto p = body<T>(a, sin2_torque<T>{A}, y0<T>());
  const T err = worst_error(p, [&](const T& t) {
    using std::cos;
    using std::sin;
    const T y30 = p.Omega0[2];
    const T Phi = y30 * t + A * (t * t / 4 - (1 - cos(2 * t)) / 8);
    const T angle = -a[0] * Phi;
    const T x = p.Omega0[0], y = p.Omega0[1];
    return vec3<T>{x * cos(angle) - y * sin(angle), x * sin(angle) + y * cos(angle),
                   y30 + A * (t / 2 - sin(2 * t) / 4)};
  });
  EXPECT_LE(err, 256 * eulervop::epsilon<T>());
}

// y3 = y30 e^{-Dt}; z = z0 exp(-Dt - i a1 Phi), Phi = y30 (1 - e^{-Dt}) / D.
TYPED_TEST(TorquePaths, TorqueOfStateOnAnAxisymmetricBody) {
  using T = TypeParam;
  const T D = T(1) / 10;
  const vec3<T> a = {T(-1), T(1), T(0)};
  const auto p = body<T>(a, damping_torque<T>{D}, y0<T>());
  const T err = worst_error(p, [&](const T& t) {
    using std::cos;
    using std::exp;
    using std::sin;
    const T decay = exp(-D * t), y30 = p.Omega0[2];
    const T angle = -a[0] * y30 * (1 - decay) / D;
    const T x = p.Omega0[0], y = p.Omega0[1];
    return vec3<T>{decay * (x * cos(angle) - y * sin(angle)), decay * (x * sin(angle) + y * cos(angle)),
                   y30 * decay};
  });
  EXPECT_LE(err, 256 * eulervop::epsilon<T>());
}

}  // namespace

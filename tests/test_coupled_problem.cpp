// The pieces of a torque of the attitude: formulas of q0..q3 and their partials
// (model/expression.hpp), the gravity gradient (model/gravity_gradient.hpp) and the Jacobian of
// the 7-state problem (model/coupled_problem.hpp), which the reference's correction linearizes.
//
// Truth:
//   - the formula's value and partials: the closed form, written out by hand in double;
//   - the gravity gradient: 3 n^2 r_b x (I r_b) with r_b = q* (x) (0, r) (x) q, the rotation by
//     the quaternion product of core/quaternion.hpp instead of the rotation matrix, in quad;
//   - the Jacobians: central differences in mpfr:256 with step 1e-40 (truncation ~1e-80,
//     rounding ~eps / step = 1e-37), on a scene whose moments are listed out of order (the
//     permutation and signs of the change of variables), with a PD law and the gravity gradient.
// Bounds: the formula's value and partials within 4 ulps (a few roundings each); the gravity
// gradient within 64 eps of |M| (both forms round about twenty times); the Jacobians within
// 1e-30 of the differences, relative to the largest entry of each row.
#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/model/coupled_problem.hpp>
#include <eulervop/model/gravity_gradient.hpp>
#include <eulervop/scene/expression_parser.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;
namespace sc = eulervop::scene;

TEST(AttitudeFormula, ValueAndPartialsByTheRatesAndQ) {
  const sc::expression_variables vars{{"t", "omega1", "omega2", "omega3", "q0", "q1", "q2", "q3"}};
  const eulervop::expression e = sc::parse_expression("q0*q1 + sin(q2)*omega1 - q3^2 + t", vars);
  EXPECT_TRUE(e.uses_attitude());
  EXPECT_TRUE(e.uses_state());
  const eulervop::compiled_expression<double> f(e);
  const double t = 0.25, w1 = 0.3, q0 = 0.7, q1 = 0.1, q2 = -0.2, q3 = 0.6;
  const eulervop::vec3<double> y = {w1, -0.4, 0.9};
  const std::array<double, 4> q = {q0, q1, q2, q3};
  const double closed = q0 * q1 + std::sin(q2) * w1 - q3 * q3 + t;
  const double ulp = std::numeric_limits<double>::epsilon();
  EXPECT_NEAR(f(t, y, q), closed, 4 * ulp);
  eulervop::compiled_expression<double>::partials d;
  const double v = f.value_and_gradient(t, y, q, d);
  EXPECT_EQ(v, f(t, y, q));  // the same operations in the same order
  const double expected[7] = {std::sin(q2), 0, 0, q1, q0, std::cos(q2) * w1, -2 * q3};
  for (int k = 0; k < 7; ++k) EXPECT_NEAR(d[k], expected[k], 4 * ulp) << "partial " << k;
  // Named without q: a logic error, never a silent zero.
  EXPECT_THROW(f(t, y), std::logic_error);
}

TEST(GravityGradient, EqualsTheTorqueOfTheRotatedPositionInQuad) {
  using eulervop::quaternion;
  const quad n("0.0011"), t(1234);
  const eulervop::vec3<quad> I = {quad(220), quad(100), quad(150)};
  const eulervop::gravity_gradient<quad> gg{n, I};
  const quaternion<quad> q = eulervop::normalized(quaternion<quad>{quad("0.7"), quad("0.1"), quad("-0.3"), quad("0.6")});
  using std::cos;
  using std::sin;
  // r_b = q* (x) (0, r) (x) q: the inertial r in the body's axes.
  const quaternion<quad> rb =
      eulervop::conjugate(q) * quaternion<quad>{quad(0), cos(n * t), sin(n * t), quad(0)} * q;
  const eulervop::vec3<quad> b = {rb.x, rb.y, rb.z};
  const eulervop::vec3<quad> Ib = {I[0] * b[0], I[1] * b[1], I[2] * b[2]};
  const quad k = 3 * n * n;
  const eulervop::vec3<quad> expected = {k * (b[1] * Ib[2] - b[2] * Ib[1]), k * (b[2] * Ib[0] - b[0] * Ib[2]),
                                         k * (b[0] * Ib[1] - b[1] * Ib[0])};
  const eulervop::vec3<quad> M = gg.value(t, {q.w, q.x, q.y, q.z});
  using std::abs;
  const quad size = abs(expected[0]) + abs(expected[1]) + abs(expected[2]);
  for (int i = 0; i < 3; ++i)
    EXPECT_LE(abs(M[i] - expected[i]), 64 * std::numeric_limits<quad>::epsilon() * size) << "component " << i;
}

// d f / d x of the 7-state problem against central differences of f, in mpfr:256.
TEST(CoupledProblem, JacobianMatchesCentralDifferences) {
  const eulervop::mpfr_precision_scope scope(256);
  const sc::scene s = sc::parse_scene(R"(name = "j"
[body]
inertia = [220, 100, 150]
[torque]
M = ["-2*q1 - 40*omega1 + 0.001*q0*q2", "-2*q2 - 40*omega2", "sin(q3) - 40*omega3*q0"]
[torque.gravity_gradient]
mean_motion = 0.0011
[initial]
omega = [0.0004, 0.0012, -0.0006]
q = [0.5, 0.5, 0.5, 0.5]
[span]
t_end = 10
samples = 2
)",
                                      "j");
  const eulervop::coupled_problem<mpfr_real> p = sc::to_coupled_problem<mpfr_real>(s);
  EXPECT_TRUE(p.normalized());  // distinct moments: Eqs. 2-4, with the axes permuted
  auto x = p.initial_state();
  x[3] = mpfr_real("0.6");  // away from the symmetric start
  x[6] = mpfr_real("0.3");
  const mpfr_real t("2.5"), h("1e-40");
  typename eulervop::coupled_problem<mpfr_real>::jacobian_type J;
  p.jacobian(t, x, J);
  for (std::size_t k = 0; k < 7; ++k) {
    auto up = x, down = x;
    up[k] += h;
    down[k] -= h;
    std::array<mpfr_real, 7> fu, fd;
    p.rhs(t, up, fu);
    p.rhs(t, down, fd);
    for (std::size_t i = 0; i < 7; ++i) {
      const mpfr_real numeric = (fu[i] - fd[i]) / (2 * h);
      mpfr_real row = 0;
      for (const mpfr_real& v : J[i]) row = std::max(row, mpfr_real(abs(v)));
      EXPECT_LE(static_cast<double>(abs(J[i][k] - numeric)), 1e-30 * static_cast<double>(row) + 1e-60)
          << "d f_" << i << " / d x_" << k << ": " << J[i][k] << " vs " << numeric;
    }
  }
}

}  // namespace

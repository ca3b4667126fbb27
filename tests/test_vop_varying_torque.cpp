// The VOP formulations under a torque of time or of time and state (vop/detail/vop_equations.hpp,
// runs/detail/vop_run_state.hpp, vop_fixed_run.hpp, vop_adaptive_run.hpp): Eqs. 13-16 evaluated
// with G(tau, Omega) at each stage, Omega by Eq. 12 from the stage's elements (docs/design.md,
// sections 1.3-1.4 and 4).
//
// Truth: for the right-hand sides, Eq. 5 itself (the chain rule: d/dtau Omega(elements) along the
// element equations must equal f(Omega) + G(tau, Omega)); for the runs, Eq. 5 with the same torque
// (the same type over quad, or the same formulas compiled in quad) integrated by the quad
// Chebyshev-Picard reference (integrate_reference<quad>), its dense output evaluated at the runs'
// sample times tau0 + n h (the doubles the runs use, exact in quad). Errors are Eq. 20
// (eq20_error, formed in quad).
// Precision: the reference holds its segments' truncation below quad's eps (~1e-34) and rounds
// near sqrt(N) eps; the chain rule's central difference (step 1e-9 dy) errs by ~1e-18 |Omega'''|
// (truncation) and ~1e-25 (rounding). Both are far below every bound here.
// Why the bounds hold: the chain-rule bound is that of tests/test_vop.cpp (any wrong term, e.g.
// G not evaluated at the stage's own Omega or not rotated into the frame, is an O(|G|) mismatch,
// ~1e-1 here). The run bounds are the measured errors with a margin of 8-100 (each test says what
// was measured); the ratios they assert (VOP below Euler at the same step, a run that honours the
// breakpoint far below one that steps across it) hold by factors of 100-10^4. A torque of time
// whose value is constant must reproduce the constant path bit for bit (same G in every stage,
// same arithmetic, same band thresholds).
// Euler's adaptive runs here set h_max: that formulation reads h_max = 0 as a zero step.
//
// This file: the right-hand sides, and a constant-valued torque of time against the constant
// path. The runs against the reference: test_vop_varying_runs.cpp, _crossing.cpp,
// _breakpoints.cpp and _adaptive_breakpoints.cpp.
// The torques and helpers are in vop_varying_torque_support.hpp.
#include "vop_varying_torque_support.hpp"

#include <gtest/gtest.h>

namespace {

using namespace vop_varying;

// ---- Right-hand sides ----

// Eqs. 13-16 (and the theta form) with G(tau, Omega) of the stage are the exact image of Eq. 5
// with the same torque, in the k < 1 and k > 1 frames and both signs (vop_frame::for_state), at
// times away from 0 so the torque's time dependence shows. Measured: <= 1.7e-16 in both regimes;
// the bounds are those of test_vop.cpp and test_vop_theta.cpp (the difference's truncation grows
// with dy[2] in the k > 1 frames), and a wrong G is an O(0.1) mismatch.
TEST(VopVaryingRhs, IsEulersEquationsInElements) {
  const mixed_torque<quad> g;
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> times(-20, 20);
  for (bool minor : {false, true}) {
    double worst_u = 0, worst_theta = 0;
    for (const auto& Om : random_states(60, minor)) {
      const auto frame = eulervop::vop_frame<quad>::for_state(Om);
      ASSERT_EQ(frame.minor_axis(), minor);
      const quad tau = quad(times(rng));
      vec3<quad> y = frame.elements_of(Om);
      y[2] += quad(37);  // the secular term E(u) - kc^2 u large
      eulervop::vop_system<quad, mixed_torque<quad>> sys(frame, g);
      worst_u = std::max(worst_u, chain_rule_mismatch(y, tau, sys, [&](const vec3<quad>& e) { return frame.Omega_of(e); }, g));
      // The stage's torque, in the frame, is G(tau, Omega) rotated (the run's band thresholds read it).
      const vec3<quad> G = frame.rotate(g.value(tau, frame.Omega_of(y)));
      for (int i = 0; i < 3; ++i) EXPECT_LE(static_cast<double>(fabs(sys.last_torque()[i] - G[i])), 1e-30);
      const vec3<quad> yt = frame.theta_elements_of(Om);
      eulervop::vop_theta_system<quad, mixed_torque<quad>> tsys(frame, g);
      worst_theta = std::max(worst_theta, chain_rule_mismatch(yt, tau, tsys, [&](const vec3<quad>& e) { return frame.Omega_of_theta(e); }, g));
    }
    std::printf("chain rule, varying torque, %s: vop %.2e, vop-theta %.2e\n", minor ? "k > 1" : "k < 1", worst_u,
                worst_theta);
    EXPECT_LE(worst_u, minor ? 1e-12 : 1e-15);
    EXPECT_LE(worst_theta, minor ? 1e-12 : 1e-15);
  }
}

// A torque of time whose value is constant takes the stage path but must give what the constant
// path gives: the same G in every stage, the same arithmetic, the same band thresholds, so the
// runs are bit-identical (here across the separatrix band of the crossing scene,
// docs/vop-strategies.md section 4, which exercises the band logic and a regime change).
template <class T>
struct constant_valued_time_torque {
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = false;
  vec3<T> G;
  vec3<T> value(const T&, const vec3<T>&) const { return G; }
};
template <class U, class T>
constant_valued_time_torque<U> convert_torque(const constant_valued_time_torque<T>& g) {
  return {{static_cast<U>(g.G[0]), static_cast<U>(g.G[1]), static_cast<U>(g.G[2])}};
}

TEST(VopVaryingTorque, ConstantValuedTorqueOfTimeMatchesTheConstantPath) {
  const vec3<double> G = {-0.05, 0, -0.05};
  eulervop::euler_problem<double> constant = problem<double>(eulervop::constant_torque<double>{G}, paper_Omega0);
  const auto timed = problem<double>(constant_valued_time_torque<double>{G}, paper_Omega0);
  const double h = paper_h();
  const eulervop::fixed_run_settings s{h, static_cast<std::size_t>(20 / h), 7};
  for (formulation f : {formulation::vop, formulation::vop_theta})
    for (auto m : {eulervop::rk::method::rk4, eulervop::rk::method::rk8}) {
      const auto a = eulervop::run_fixed(f, m, constant, s);
      const auto b = eulervop::run_fixed(f, m, timed, s);
      ASSERT_FALSE(a.diverged());
      ASSERT_FALSE(b.diverged());
      ASSERT_FALSE(a.separatrix_bands.empty());
      EXPECT_EQ(a.separatrix_bands, b.separatrix_bands);
      EXPECT_EQ(a.rhs_evals, b.rhs_evals);
      ASSERT_EQ(a.Omega.size(), b.Omega.size());
      for (std::size_t i = 0; i < a.Omega.size(); ++i)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(a.Omega[i][c], b.Omega[i][c]) << "sample " << i;
    }
  // Under error control too (the element error scale and the controller see the same numbers).
  eulervop::adaptive_run_settings as;
  as.atol = as.rtol = 1e-10;
  as.tau_end = 20;
  as.h_max = 1;
  for (formulation f : {formulation::vop, formulation::vop_theta}) {
    const auto a = eulervop::run_adaptive(f, eulervop::rk::method::dp45, constant, as);
    const auto b = eulervop::run_adaptive(f, eulervop::rk::method::dp45, timed, as);
    EXPECT_EQ(a.steps, b.steps);
    ASSERT_EQ(a.Omega.size(), b.Omega.size());
    for (std::size_t i = 0; i < a.Omega.size(); ++i)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(a.Omega[i][c], b.Omega[i][c]) << "sample " << i;
  }
}


}  // namespace

// The published rigid-body test problems shipped in data/scenes/problems/, each against an
// independent truth that shares no code with the Chebyshev-Picard integrator, the change of
// variables (Eqs. 2-4, physical_scaling) or eulervop's elliptic functions.
//
// Truth, computed in MPFR at 100 decimal digits (about 333 bits), in each problem's own variables:
//   - enright-pryce-b5 (coefficient form, a = (1, -1, -0.51), y0 = (0, 1, 1)): the exact solution
//     y = (sn, cn, dn)(t | m = 0.51) (Enright and Pryce, ACM TOMS 13 (1987), problem B5), with
//     Boost.Math's jacobi_elliptic (modulus k = sqrt(m)) and dn = sqrt(1 - m sn^2), since Boost's
//     dn is a ratio that is 0/0 at odd multiples of K.
//   - hlw-free-rigid-body (physical, I = (2, 1, 2/3), m0 = (cos 1.1, 0, sin 1.1)): the angular
//     momentum m = I omega of m1' = m2 m3 / 2, m2' = -m3 m1, m3' = m1 m2 / 2 is
//       m(t) = (c cn(L t), -sqrt(2) c sn(L t), s dn(L t) | m = cot^2 1.1), c = cos 1.1, s = sin 1.1,
//     L = s / sqrt(2) (differentiate: m1' = -c L sn dn = m2 m3 / 2, m2' = -sqrt(2) c L cn dn
//     = -m3 m1, m3' = -s m L sn cn = -(c^2 / sqrt(2)) sn cn = m1 m2 / 2; the test also checks it
//     against the Taylor integration below). Compared as omega = m / I.
//   - sciml-rigid-body (to t = 10 and 100), hnw-eulr, tumbling-brick-damped: a Taylor-series
//     integration of y_i' = a_i y_j y_k + f_i(t, y) written here (the idea of
//     tests/test_rigid_bodies.cpp, extended to forcing of time and state): the coefficients of
//     the quadratic terms are Cauchy products, those of sin^2 t = (1 - cos 2t) / 2 about t0 are
//     closed-form (cos(2 t0 + 2h) = sum_n (2h)^n / n! cos(2 t0 + n pi / 2)), and the damping
//     -d_i t y_i is linear in t (its coefficients: -d_i (t0 y_i[n] + y_i[n-1])). Order 60, fixed
//     steps that land exactly on every sample time and, for hnw-eulr, on t = 3 pi and 4 pi
//     (computed in MPFR), where the forcing switches. Every step's truncation, estimated from its
//     last two terms, is asserted below 1e-60 of the state (1e-85 for the run that checks MPFR).
//     Physical scenes are integrated in omega (rad/s) and t (s), with a_i = (I_j - I_k) / I_i and
//     f = M / I from the scene files' decimals, copied here; the coefficient form in y and t.
//     The Taylor integration itself is checked against the two closed forms to 1e-60.
//
// Ours: each scene as the program computes it (load_scene_file, with_problem,
// integrate_reference_samples, default settings), at the scene's own sample times (every one:
// all spacings are 0.1). Physical scenes are integrated in tau and Omega; their samples are
// mapped back to omega in the body's axes as listed with scaling_of(s).omega_of_Omega (one
// product per component: an error of one rounding) and compared there.
//
// Steps: 0.1 (one per sample; two around 3 pi and 4 pi), 0.025 for sciml-rigid-body (its
// truth must hold 1e-85 for the MPFR check) and 0.02 for sciml-rigid-body-100 (y3 spins up to
// 13, |y'| to 21: the series' radius falls to about 0.2).
//
// Error: max over the samples of |y - y_truth|_inf / max(1, |y_truth|_inf), and printed beside it
// the same relative to |y_truth|_inf alone (the damped brick's rates fall to 1e-5 rad/s).
// Bounds, the acceptance numbers: 1e-30 in quad for every problem (about 5000 eps of
// binary128: the reference holds each segment's truncation to eps/16 and compensates its
// rounding; what remains grows with the span, by the phase drift of the periodic problems and
// the spin-up of the forced ones; and the truth is taken at the exact decimal sample times,
// which the quad run rounds, a further eps/2 t |y'| of up to 1.3e-31 at t = 100), and 1e-70 in
// mpfr:256 for sciml-rigid-body to t = 10 (about 1e7 eps of 257 bits). The truth's own error
// (truncation <= 1e-60 per step, 1e-85 for the MPFR check, rounding near 1e-100) is far below both.
// Measured (Release): quad 2.3e-33 (b5), 6.4e-33 (hlw), 2.0e-33 (sciml), 1.5e-32 (sciml-100;
// 7.6e-33 at the quad run's own rounded times), 4.5e-33 (hnw-eulr), 1.7e-34 (brick; 6.2e-33
// relative to its decayed rates); mpfr:256 sciml 4.6e-77. About 3.5 s in all, 2 s of it the
// Taylor truth of sciml-rigid-body-100.
#include <eulervop/reference/integrate.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <boost/math/constants/constants.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <boost/multiprecision/mpfr.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;
namespace sc = eulervop::scene;

// The truth's precision: 100 decimal digits, about 333 bits, fixed at compile time (stack storage).
using real = boost::multiprecision::number<
    boost::multiprecision::mpfr_float_backend<100, boost::multiprecision::allocate_stack>,
    boost::multiprecision::et_off>;
using state = std::array<real, 3>;

std::string problem_file(const std::string& name) {
  return std::string(EULERVOP_SOURCE_DIR) + "/data/scenes/problems/" + name + ".toml";
}

// The scene's sample times t_i = t_end i / (n - 1), exact decimals evaluated in `real` (the
// reference's own sample times are these rounded to its precision).
std::vector<real> exact_sample_times(const real& t_end, int samples) {
  std::vector<real> t;
  for (int i = 0; i < samples; ++i) t.push_back(t_end * i / (samples - 1));
  return t;
}

// ----------------------------------------------------------------------------------------------
// The Taylor-series integration of y_i' = a_i y_j y_k + f_i(t, y), (i, j, k) cyclic, with
//   f_3 += A sin^2 t          (on [from, to) when a window is given, else everywhere),
//   f_i += -d_i t y_i         (linear damping growing with time).
struct taylor_problem {
  state a{};
  state y0{};
  real sin2_amplitude = 0;
  std::optional<std::array<real, 2>> sin2_window;  // [from, to): a breakpoint at each end
  state damping{};                                 // d_i
};

struct taylor_run {
  std::vector<state> y;     // at the requested times
  real worst_truncation;    // max over the steps of the tail estimate / |y|_inf
  std::size_t steps = 0;
};

constexpr int taylor_order = 60;

// One step from (t0, y) by h: the Taylor coefficients c_i[0..N] of y(t0 + h) in powers of h,
// summed by Horner. Returns the truncation estimate |c[N-1]| h^(N-1) + |c[N]| h^N relative to
// the new state's largest component.
real taylor_step(const taylor_problem& p, bool forced, const real& t0, const real& h, state& y) {
  constexpr int N = taylor_order;
  std::array<std::array<real, N + 1>, 3> c;
  for (int i = 0; i < 3; ++i) c[i][0] = y[i];
  // sin^2(t0 + h) = 1/2 - cos(2 t0 + 2 h) / 2; the n-th derivative of cos(2 t0 + x) at 0 is
  // cos(2 t0 + n pi / 2) = C, -S, -C, S for n = 0, 1, 2, 3 (mod 4).
  real C = 0, S = 0;
  if (forced) {
    C = cos(2 * t0);
    S = sin(2 * t0);
  }
  real power = 1;  // 2^n / n!
  for (int n = 0; n < N; ++n) {
    std::array<real, 3> f{};
    if (forced) {
      if (n > 0) power = power * 2 / n;
      const real trig = (n % 4 == 0) ? C : (n % 4 == 1) ? real(-S) : (n % 4 == 2) ? real(-C) : S;
      f[2] = p.sin2_amplitude * (n == 0 ? real((1 - C) / 2) : real(-power * trig / 2));
    }
    for (int i = 0; i < 3; ++i)
      if (p.damping[i] != 0) f[i] -= p.damping[i] * (t0 * c[i][n] + (n > 0 ? c[i][n - 1] : real(0)));
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      real sum = 0;
      for (int m = 0; m <= n; ++m) sum += c[j][m] * c[k][n - m];
      c[i][n + 1] = (p.a[i] * sum + f[i]) / (n + 1);
    }
  }
  real norm = 0, tail = 0;
  const real hN1 = pow(h, N - 1), hN = hN1 * h;
  for (int i = 0; i < 3; ++i) {
    real sum = c[i][N];
    for (int n = N - 1; n >= 0; --n) sum = sum * h + c[i][n];
    y[i] = sum;
    norm = std::max(norm, real(abs(sum)));
    tail = std::max(tail, real(abs(c[i][N - 1]) * hN1 + abs(c[i][N]) * hN));
  }
  return tail / norm;
}

// y at `times` (increasing, times[0] = 0), stepping by equal steps of at most h_max between
// consecutive stops: the times themselves and the window's ends.
taylor_run taylor_integrate(const taylor_problem& p, const std::vector<real>& times, const real& h_max) {
  std::vector<real> stops = times;
  if (p.sin2_window) {
    stops.push_back((*p.sin2_window)[0]);
    stops.push_back((*p.sin2_window)[1]);
    std::sort(stops.begin(), stops.end());
  }
  taylor_run run;
  run.worst_truncation = 0;
  state y = p.y0;
  std::size_t next = 0;
  for (std::size_t s = 0; s < stops.size(); ++s) {
    if (s > 0) {
      const real& ta = stops[s - 1];
      const real& tb = stops[s];
      // (A ratio that is a whole number up to rounding, 0.1 / 0.05, must not give one more step.)
      const auto n = std::max(1L, static_cast<long>(ceil((tb - ta) / h_max * (1 - real("1e-50")))));
      const real h = (tb - ta) / n;
      for (long q = 0; q < n; ++q) {
        const real t0 = ta + h * q;
        // The step lies on one side of each window end (they are stops): its middle decides.
        const real mid = t0 + h / 2;
        const bool forced = p.sin2_amplitude != 0 &&
                            (!p.sin2_window || (mid >= (*p.sin2_window)[0] && mid < (*p.sin2_window)[1]));
        run.worst_truncation = std::max(run.worst_truncation, taylor_step(p, forced, t0, h, y));
        ++run.steps;
      }
    }
    if (next < times.size() && stops[s] == times[next]) {
      run.y.push_back(y);
      ++next;
    }
  }
  return run;
}

// ----------------------------------------------------------------------------------------------
// The closed forms.

// (sn, cn, dn)(u | m), Boost.Math in `real`; dn from sn (Boost's dn is 0/0 at odd multiples of K).
state jacobi(const real& u, const real& m) {
  real cn, dn_ratio;
  const real sn = boost::math::jacobi_elliptic(real(sqrt(m)), u, &cn, &dn_ratio);
  return {sn, cn, real(sqrt(1 - m * sn * sn))};
}

std::vector<state> b5_exact(const std::vector<real>& times) {
  const real m("0.51");
  std::vector<state> y;
  for (const real& t : times) y.push_back(jacobi(t, m));
  return y;
}

// omega = m / I of Hairer, Lubich and Wanner's free rigid body.
std::vector<state> hlw_exact(const std::vector<real>& times) {
  const real c = cos(real("1.1")), s = sin(real("1.1"));
  const real L = s / sqrt(real(2)), m = (c * c) / (s * s);
  const state I = {real(2), real(1), real(2) / 3};
  std::vector<state> w;
  for (const real& t : times) {
    const state e = jacobi(L * t, m);
    w.push_back({c * e[1] / I[0], -sqrt(real(2)) * c * e[0] / I[1], s * e[2] / I[2]});
  }
  return w;
}

// ----------------------------------------------------------------------------------------------
// The problems in the Taylor form, from the scenes' decimals (read here, not through eulervop).

state coefficients_of_moments(const state& I) {
  state a;
  for (int i = 0; i < 3; ++i) a[i] = (I[(i + 1) % 3] - I[(i + 2) % 3]) / I[i];
  return a;
}

taylor_problem b5_problem() {
  taylor_problem p;
  p.a = {real(1), real(-1), real("-0.51")};
  p.y0 = {real(0), real(1), real(1)};
  return p;
}

taylor_problem hlw_problem() {
  const state I = {real(2), real(1), real(2) / 3};
  const real c = cos(real("1.1")), s = sin(real("1.1"));
  taylor_problem p;
  p.a = coefficients_of_moments(I);
  p.y0 = {real(c / 2), real(0), real(real("1.5") * s)};
  return p;
}

taylor_problem sciml_problem() {
  taylor_problem p;
  p.a = {real(-2), real("1.25"), real("-0.5")};
  p.y0 = {real(1), real(0), real("0.9")};
  p.sin2_amplitude = real("0.25");
  return p;
}

taylor_problem hnw_problem() {
  const state I = {real("0.5"), real(2), real(3)};
  const real pi = boost::math::constants::pi<real>();
  taylor_problem p;
  p.a = coefficients_of_moments(I);
  p.y0 = {real(1), real(0), real("0.9")};
  p.sin2_amplitude = real("0.75") / I[2];  // M3 = 0.75 sin^2 t
  p.sin2_window = std::array<real, 2>{3 * pi, 4 * pi};
  return p;
}

taylor_problem brick_problem() {
  const state I = {real("0.002568217474088305265688"), real("0.0084210110376273461810076"),
                   real("0.0097546559392317348588660")};
  // M_i = -(rho V S l_i^2 / 4) omega_i with V = g0 t: rho, g0, S and l as in the scene's formulas.
  const real rho_g_S = real("0.459041") * real("9.80665") * real("0.02064512");
  const state l = {real("0.1016"), real("0.2032"), real("0.1016")};
  taylor_problem p;
  p.a = coefficients_of_moments(I);
  const real pi = boost::math::constants::pi<real>();
  p.y0 = {real(10 * pi / 180), real(20 * pi / 180), real(30 * pi / 180)};
  for (int i = 0; i < 3; ++i) p.damping[i] = rho_g_S * l[i] * l[i] / 4 / I[i];
  return p;
}

// ----------------------------------------------------------------------------------------------
// Our reference at the scene's sample times, in the scene's variables (omega in the body's axes
// as listed for a physical scene, mapped from Omega by the scene's scaling; y otherwise).
template <class T>
std::vector<vec3<T>> our_samples(const sc::scene& s) {
  const sc::sample_times<T> times = sc::sample_times_of<T>(s);
  std::vector<vec3<T>> out(times.tau.size());
  sc::with_problem<T>(s, [&](const auto& problem) {
    eulervop::integrate_reference_samples(problem, sc::tau_end_of<T>(s), times.tau,
                                          [&](std::size_t i, const T&, const vec3<T>& y) { out[i] = y; });
  });
  if (s.is_physical()) {
    const auto scale = sc::scaling_of<T>(s);
    for (auto& y : out) y = scale.omega_of_Omega(y);
  }
  return out;
}

struct error_pair {
  double vs_max1;   // |y - y_truth|_inf / max(1, |y_truth|_inf)
  double vs_state;  // |y - y_truth|_inf / |y_truth|_inf
};

template <class T>
error_pair max_error(const std::vector<vec3<T>>& got, const std::vector<state>& truth) {
  EXPECT_EQ(got.size(), truth.size());
  real worst1 = 0, worst_state = 0;
  for (std::size_t r = 0; r < std::min(got.size(), truth.size()); ++r) {
    real d = 0, n = 0;
    for (int i = 0; i < 3; ++i) {
      d = std::max(d, real(abs(real(got[r][i]) - truth[r][i])));
      n = std::max(n, real(abs(truth[r][i])));
    }
    worst1 = std::max(worst1, real(d / std::max(n, real(1))));
    worst_state = std::max(worst_state, real(d / n));
  }
  return {static_cast<double>(worst1), static_cast<double>(worst_state)};
}

sc::scene load(const std::string& name) { return sc::load_scene_file(problem_file(name)); }

std::vector<real> scene_times(const sc::scene& s) {
  return exact_sample_times(real(s.span_end.text), static_cast<int>(*s.samples));
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Checks our quad reference of `name` against `truth`, printing the errors.
void expect_quad_within(const std::string& name, const std::vector<state>& truth, double bound) {
  const auto start = std::chrono::steady_clock::now();
  const error_pair e = max_error(our_samples<quad>(load(name)), truth);
  std::printf("%-22s quad:     max |y - y_truth|_inf / max(1, |y|_inf) = %.3e  (/ |y|_inf: %.3e; %.2f s)\n",
              name.c_str(), e.vs_max1, e.vs_state, seconds_since(start));
  EXPECT_LE(e.vs_max1, bound) << name;
}

// The Taylor truth of a problem at its scene's sample times, with its truncation asserted.
std::vector<state> taylor_truth(const std::string& name, const taylor_problem& p, const real& h_max,
                                const real& truncation_bound) {
  const auto start = std::chrono::steady_clock::now();
  const taylor_run run = taylor_integrate(p, scene_times(load(name)), h_max);
  std::printf("%-22s Taylor truth: %zu steps, worst truncation %.3e of |y| (%.2f s)\n", name.c_str(), run.steps,
              static_cast<double>(run.worst_truncation), seconds_since(start));
  EXPECT_LE(run.worst_truncation, truncation_bound) << name;
  return run.y;
}

const real truncation_1e60("1e-60");

// ----------------------------------------------------------------------------------------------

// The Taylor integration reproduces both closed forms: its code, and the closed form for HLW's
// body derived above, agree to 1e-60 (neither shares anything with the other but MPFR).
TEST(PublishedProblems, TaylorTruthMatchesTheClosedForms) {
  {
    const auto times = scene_times(load("enright-pryce-b5"));
    const auto run = taylor_integrate(b5_problem(), times, real("0.1"));
    const auto exact = b5_exact(times);
    real worst = 0;
    for (std::size_t r = 0; r < times.size(); ++r)
      for (int i = 0; i < 3; ++i) worst = std::max(worst, real(abs(run.y[r][i] - exact[r][i])));
    std::printf("enright-pryce-b5: Taylor against (sn, cn, dn): %.3e\n", static_cast<double>(worst));
    EXPECT_LE(worst, real("1e-60"));
  }
  {
    const auto times = scene_times(load("hlw-free-rigid-body"));
    const auto run = taylor_integrate(hlw_problem(), times, real("0.1"));
    const auto exact = hlw_exact(times);
    real worst = 0;
    for (std::size_t r = 0; r < times.size(); ++r)
      for (int i = 0; i < 3; ++i) worst = std::max(worst, real(abs(run.y[r][i] - exact[r][i])));
    std::printf("hlw-free-rigid-body: Taylor against the closed form: %.3e\n", static_cast<double>(worst));
    EXPECT_LE(worst, real("1e-60"));
  }
}

TEST(PublishedProblems, EnrightPryceB5QuadMatchesJacobiFunctions) {
  expect_quad_within("enright-pryce-b5", b5_exact(scene_times(load("enright-pryce-b5"))), 1e-30);
}

TEST(PublishedProblems, HairerLubichWannerFreeRigidBodyQuadMatchesClosedForm) {
  expect_quad_within("hlw-free-rigid-body", hlw_exact(scene_times(load("hlw-free-rigid-body"))), 1e-30);
}

TEST(PublishedProblems, SciMLRigidBodyQuadAndMpfrMatchTaylor) {
  const std::string name = "sciml-rigid-body";
  const auto truth = taylor_truth(name, sciml_problem(), real("0.025"), real("1e-85"));
  expect_quad_within(name, truth, 1e-30);

  const auto start = std::chrono::steady_clock::now();
  eulervop::mpfr_precision_scope scope(256);
  const error_pair e = max_error(our_samples<mpfr_real>(load(name)), truth);
  std::printf("%-22s mpfr:256: max |y - y_truth|_inf / max(1, |y|_inf) = %.3e  (/ |y|_inf: %.3e; %.2f s)\n",
              name.c_str(), e.vs_max1, e.vs_state, seconds_since(start));
  EXPECT_LE(e.vs_max1, 1e-70);
}

TEST(PublishedProblems, SciMLRigidBodyTo100QuadMatchesTaylor) {
  const std::string name = "sciml-rigid-body-100";
  expect_quad_within(name, taylor_truth(name, sciml_problem(), real("0.02"), truncation_1e60), 1e-30);
}

TEST(PublishedProblems, HairerNorsettWannerEulrQuadMatchesTaylor) {
  const std::string name = "hnw-eulr";
  expect_quad_within(name, taylor_truth(name, hnw_problem(), real("0.1"), truncation_1e60), 1e-30);
}

TEST(PublishedProblems, TumblingBrickDampedQuadMatchesTaylor) {
  const std::string name = "tumbling-brick-damped";
  expect_quad_within(name, taylor_truth(name, brick_problem(), real("0.1"), truncation_1e60), 1e-30);
}

}  // namespace

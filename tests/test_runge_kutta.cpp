// Tests of the fixed-step Runge-Kutta methods: include/eulervop/rk/ method.hpp, tableaux.hpp,
// state_traits.hpp, explicit_rk.hpp and fixed_step.hpp.
//
// Reference values and their provenance:
//   - rotation x1' = -x2, x2' = x1: exact solution (cos t, sin t), evaluated in quad.
//   - y' = y cos t (non-autonomous, checks the nodes c): exact y = exp(sin t), in quad.
//   - normalized Euler equations (model/euler_problem.hpp, Eq. 5) with G = (1,1,1), Omega(0) = (0.5, 0, 1),
//     the paper's scene: no closed form. Reference by a Taylor-series integrator written in this
//     file (coefficients by Cauchy products, which are exact for a quadratic right-hand side),
//     order 60, MPFR at 200 bits; its own accuracy is checked by halving its step.
//   - x' = x^2, x(0) = 1: blows up at t = 1 exactly.
// Tolerances are in multiples of epsilon<T>() except where a coefficient's published precision
// is the limit (the DOP853 decimals, ~1e-30), which is stated where used.
#include "rk_test_systems.hpp"
#include "type_test_names.hpp"

#include <eulervop/core/scalar.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/rk/explicit_rk.hpp>
#include <eulervop/rk/fixed_step.hpp>
#include <eulervop/rk/method.hpp>
#include <eulervop/rk/state_traits.hpp>
#include <eulervop/rk/tableaux.hpp>

#include <gmp.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using eulervop::epsilon;
using eulervop::mpfr_precision_scope;
using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;
namespace rk = eulervop::rk;
using eulervop::rk_test::planar;
using eulervop::rk_test::euler_system;
using eulervop::rk_test::rotation;

using all_tableaux =
    ::testing::Types<rk::rk4_tableau, rk::rkf45_tableau, rk::dp45_tableau, rk::rk8_tableau>;

// ---- problems -----------------------------------------------------------------------------------

struct exp_sin {  // y' = y cos t
  template <class T>
  void operator()(const std::array<T, 1>& y, std::array<T, 1>& dy, const T& t) const {
    using std::cos;
    dy[0] = y[0] * cos(t);
  }
};

struct square {  // x' = x^2
  template <class T>
  void operator()(const std::array<T, 1>& x, std::array<T, 1>& dx, const T&) const {
    dx[0] = x[0] * x[0];
  }
};

template <class T, class State>
T max_abs_diff(const State& a, const State& b) {
  using std::abs;
  T m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    T d = abs(a[i] - b[i]);
    if (d > m) m = d;
  }
  return m;
}

// Taylor-series reference for Omega' = G + (-O2 O3, O1 O3, -O1 O2), in MPFR (caller's scope).
vec3<mpfr_real> euler_taylor(vec3<mpfr_real> x, const vec3<mpfr_real>& G, const mpfr_real& span,
                             int steps, int order) {
  const mpfr_real h = span / steps;
  std::vector<vec3<mpfr_real>> a(static_cast<std::size_t>(order) + 1);
  for (int s = 0; s < steps; ++s) {
    a[0] = x;
    for (int k = 0; k < order; ++k) {
      mpfr_real s12 = 0, s02 = 0, s01 = 0;
      for (int j = 0; j <= k; ++j) {
        const auto& p = a[static_cast<std::size_t>(j)];
        const auto& q = a[static_cast<std::size_t>(k - j)];
        s12 += p[1] * q[2];
        s02 += p[0] * q[2];
        s01 += p[0] * q[1];
      }
      auto& n = a[static_cast<std::size_t>(k) + 1];
      n[0] = ((k == 0 ? G[0] : mpfr_real(0)) - s12) / (k + 1);
      n[1] = ((k == 0 ? G[1] : mpfr_real(0)) + s02) / (k + 1);
      n[2] = ((k == 0 ? G[2] : mpfr_real(0)) - s01) / (k + 1);
    }
    for (int i = 0; i < 3; ++i) {  // Horner
      mpfr_real v = a[static_cast<std::size_t>(order)][static_cast<std::size_t>(i)];
      for (int k = order - 1; k >= 0; --k) v = v * h + a[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)];
      x[static_cast<std::size_t>(i)] = v;
    }
  }
  return x;
}

constexpr int euler_span = 2;  // tau in [0, 2]: about one Omega3 oscillation of the paper scene

// The Euler reference at tau = 2, in quad (rounded from 200-bit MPFR).
const vec3<quad>& euler_reference_quad() {
  static const vec3<quad> ref = [] {
    mpfr_precision_scope scope(200);
    const vec3<mpfr_real> x0{mpfr_real(1) / 2, 0, 1}, G{1, 1, 1};
    const auto x = euler_taylor(x0, G, mpfr_real(euler_span), 64, 60);
    return vec3<quad>{quad(x[0]), quad(x[1]), quad(x[2])};
  }();
  return ref;
}

// ---- observed order -----------------------------------------------------------------------------

template <class Tab, class State, class Sys>
State run(Sys sys, State x, const quad& span, std::size_t n) {
  const quad h = span / quad(n);
  const auto r = rk::integrate_fixed<Tab>(sys, x, quad(0), h, n);
  EXPECT_FALSE(r.diverged());
  EXPECT_EQ(r.steps, n);
  return x;
}

template <class Tab>
double rotation_error(std::size_t n) {
  const quad span = 2;
  const auto x = run<Tab>(rotation{}, std::array<quad, 2>{1, 0}, span, n);
  using std::cos;
  using std::sin;
  return static_cast<double>(max_abs_diff<quad>(x, std::array<quad, 2>{cos(span), sin(span)}));
}

template <class Tab>
double exp_sin_error(std::size_t n) {
  const quad span = 2;
  const auto y = run<Tab>(exp_sin{}, std::array<quad, 1>{1}, span, n);
  using std::exp;
  using std::sin;
  return static_cast<double>(max_abs_diff<quad>(y, std::array<quad, 1>{exp(sin(span))}));
}

template <class Tab>
double euler_error(std::size_t n) {
  const auto sys = euler_system<quad>({1, 1, 1});
  const auto x = run<Tab>(sys, vec3<quad>{quad(1) / 2, 0, 1}, quad(euler_span), n);
  return static_cast<double>(max_abs_diff<quad>(x, euler_reference_quad()));
}

// Step counts for the order test, per method: coarse enough that the error at the finer step
// stays far above quad round-off (and, for rk8, above the ~1e-30 floor of the DOP853 decimals),
// fine enough to be in the asymptotic regime.
template <class Tab>
std::size_t base_steps() {
  if constexpr (Tab::id == rk::method::rk4) return 64;
  else if constexpr (Tab::id == rk::method::rkf45) return 64;
  else if constexpr (Tab::id == rk::method::dp45) return 128;  // at 64 steps Euler is pre-asymptotic (4.65)
  else return 32;
}

template <class Tab>
struct RungeKuttaOrder : ::testing::Test {};
TYPED_TEST_SUITE(RungeKuttaOrder, all_tableaux, method_test_names);

template <class Tab, class ErrorFn>
void check_order(const char* problem, ErrorFn error) {
  const std::size_t n = base_steps<Tab>();
  const double e1 = error(n), e2 = error(2 * n), e4 = error(4 * n);
  const double p1 = std::log2(e1 / e2), p2 = std::log2(e2 / e4);
  std::printf("  %-6s %-9s n=%4zu,%4zu,%4zu  err=%.3e %.3e %.3e  order=%.3f %.3f (declared %d)\n",
              std::string(Tab::name).c_str(), problem, n, 2 * n, 4 * n, e1, e2, e4, p1, p2,
              Tab::order);
  EXPECT_NEAR(p1, Tab::order, 0.3) << problem;
  EXPECT_NEAR(p2, Tab::order, 0.3) << problem;
  EXPECT_GT(e4, 1e-27) << "finest error too close to the quad / coefficient floor";
}

TYPED_TEST(RungeKuttaOrder, LinearRotationInQuad) {
  check_order<TypeParam>("rotation", rotation_error<TypeParam>);
}
TYPED_TEST(RungeKuttaOrder, NonAutonomousInQuad) {
  check_order<TypeParam>("exp(sin)", exp_sin_error<TypeParam>);
}
TYPED_TEST(RungeKuttaOrder, NonlinearEulerInQuad) {
  check_order<TypeParam>("euler", euler_error<TypeParam>);
}

// ---- coefficients -------------------------------------------------------------------------------

// Runs f in each scalar type: double, quad, and MPFR at 200 bits (inside its precision scope).
template <class F>
void for_each_scalar(F&& f) {
  f(double{});
  f(quad{});
  mpfr_precision_scope scope(200);
  f(mpfr_real{});
}

// Row-sum and weight-sum defects, computed in T, each relative to the magnitude of its terms
// (|c_i - sum_j a_ij| / max(1, sum_j |a_ij|), |sum b - 1| / sum |b_j|): the rounding of a sum
// scales with its terms, and DOP853's rows 9-12 have sum |a_ij| up to 96.
template <class T>
struct consistency {
  T row_defect = 0;
  T b_defect = 0;
};
template <class Tab, class T>
consistency<T> measure_consistency(std::size_t first, std::size_t last) {
  using std::abs;
  const auto tab = Tab::template coefficients<T>();
  consistency<T> r;
  for (std::size_t i = first; i < last; ++i) {
    T sum = 0, mag = 1;
    for (std::size_t j = 0; j < Tab::stages; ++j) {
      if (j >= i) {
        EXPECT_EQ(tab.a[i][j], T(0)) << "not explicit at (" << i << "," << j << ")";
      }
      sum += tab.a[i][j];
      mag += abs(tab.a[i][j]);
    }
    const T d = abs(sum - tab.c[i]) / mag;
    if (d > r.row_defect) r.row_defect = d;
  }
  T sb = 0, mag = 0;
  for (const auto& bj : tab.b) {
    sb += bj;
    mag += abs(bj);
  }
  r.b_defect = abs(sb - T(1)) / mag;
  return r;
}

template <class Tab>
struct RungeKuttaCoefficients : ::testing::Test {};
TYPED_TEST_SUITE(RungeKuttaCoefficients, all_tableaux, method_test_names);

// c_i = sum_j a_ij and sum b = 1, computed in T. Rational rows (and DOP853's exact Q(sqrt 6) rows
// 1-7) hold to the rounding of the sum, within `stages` epsilon<T>() relative to its terms. DOP853's
// rows 8-12 and weights are the dop853.f decimals, 30 significant digits, each within half a unit
// of the 30th digit (5e-30 relative): that bound is their tolerance once it exceeds epsilon<T>().
TYPED_TEST(RungeKuttaCoefficients, RowSumsAndWeightSumInEveryPrecision) {
  using Tab = TypeParam;
  for_each_scalar([](auto zero) {
    using T = decltype(zero);
    const T tol = T(Tab::stages) * epsilon<T>();
    constexpr bool dop = Tab::id == rk::method::rk8;
    const auto exact = measure_consistency<Tab, T>(0, dop ? 7 : Tab::stages);
    EXPECT_EQ(Tab::template coefficients<T>().c[0], T(0));
    EXPECT_LE(exact.row_defect, tol) << Tab::name << " " << exact.row_defect;
    if (!dop) {
      EXPECT_LE(exact.b_defect, tol) << Tab::name << " " << exact.b_defect;
    } else {
      const auto decimal = measure_consistency<Tab, T>(7, Tab::stages);
      const T dtol = std::max<T>(tol, rk::detail::decimal<T>("5e-30"));
      EXPECT_LE(decimal.row_defect, dtol) << decimal.row_defect;
      EXPECT_LE(decimal.b_defect, dtol) << decimal.b_defect;
      std::printf("  rk8 in %-6s relative defects: rows 1-7 %.2e, rows 8-12 %.2e, sum b %.2e\n",
                  std::is_same_v<T, double> ? "double" : std::is_same_v<T, quad> ? "quad" : "mpfr200",
                  static_cast<double>(exact.row_defect), static_cast<double>(decimal.row_defect),
                  static_cast<double>(decimal.b_defect));
    }
  });
}

// The non-zero pattern the unrolled stage loop relies on (zeros are skipped at compile time)
// matches the coefficients, in every precision.
TYPED_TEST(RungeKuttaCoefficients, SparsityPatternMatchesTheCoefficients) {
  using Tab = TypeParam;
  for_each_scalar([](auto zero) {
    using T = decltype(zero);
    const auto tab = Tab::template coefficients<T>();
    for (std::size_t i = 0; i < Tab::stages; ++i) {
      for (std::size_t j = 0; j < Tab::stages; ++j)
        EXPECT_EQ(tab.a[i][j] != 0, Tab::nonzero.a[i][j]) << Tab::name << " a(" << i << "," << j << ")";
      EXPECT_EQ(tab.b[i] != 0, Tab::nonzero.b[i]) << Tab::name << " b" << i;
    }
  });
}

TYPED_TEST(RungeKuttaCoefficients, NameOrderStagesAndDispatch) {
  using Tab = TypeParam;
  EXPECT_EQ(rk::method_from_name(Tab::name), Tab::id);
  EXPECT_EQ(rk::method_name(Tab::id), Tab::name);
  EXPECT_EQ(rk::declared_order(Tab::id), Tab::order);
  EXPECT_EQ(rk::stage_count(Tab::id), Tab::stages);
  const auto stages = rk::dispatch_method(Tab::id, [](auto tag) { return decltype(tag)::stages; });
  EXPECT_EQ(stages, Tab::stages);
  EXPECT_TRUE((rk::dispatch_method(Tab::id, [](auto tag) {
    return std::is_same_v<decltype(tag), Tab>;
  })));
}

TEST(RungeKuttaCoefficients, UnknownNamesAreRejected) {
  for (const char* bad : {"", "RK4", "rk45", "rk 4", "rk8 ", "dopri5", "DOP853"})
    EXPECT_FALSE(rk::method_from_name(bad).has_value()) << bad;
  EXPECT_EQ(rk::method_from_name("dop853"), rk::method::dop853);
  EXPECT_EQ(rk::method_from_name("rk4"), rk::method::rk4);
  EXPECT_EQ(rk::method_from_name("rkf45"), rk::method::rkf45);
  EXPECT_EQ(rk::method_from_name("dp45"), rk::method::dp45);
  EXPECT_EQ(rk::method_from_name("rk8"), rk::method::rk8);
}

// The exact Q(sqrt 6) forms of DOP853's nodes and rows 2-7 against the dop853.f decimals
// (E. Hairer's dop853.f, ~30 significant digits): they must agree to the digits printed.
TEST(RungeKuttaCoefficients, Dop853ExactFormsMatchThePublishedDecimals) {
  mpfr_precision_scope scope(200);
  using T = mpfr_real;
  const auto tab = rk::rk8_tableau::coefficients<T>();
  struct entry {
    int i, j;  // j < 0: c_i
    const char* text;
  };
  const entry published[] = {
      {1, -1, "0.526001519587677318785587544488e-01"}, {2, -1, "0.789002279381515978178381316732e-01"},
      {3, -1, "0.118350341907227396726757197510"},     {4, -1, "0.281649658092772603273242802490"},
      {5, -1, "0.333333333333333333333333333333"},     {6, -1, "0.25"},
      {7, -1, "0.307692307692307692307692307692"},     {8, -1, "0.651282051282051282051282051282"},
      {9, -1, "0.6"},                                  {10, -1, "0.857142857142857142857142857142"},
      {1, 0, "5.26001519587677318785587544488e-02"},   {2, 0, "1.97250569845378994544595329183e-02"},
      {2, 1, "5.91751709536136983633785987549e-02"},   {3, 0, "2.95875854768068491816892993775e-02"},
      {3, 2, "8.87627564304205475450678981324e-02"},   {4, 0, "2.41365134159266685502369798665e-01"},
      {4, 2, "-8.84549479328286085344864962717e-01"},  {4, 3, "9.24834003261792003115737966543e-01"},
      {5, 0, "3.7037037037037037037037037037e-02"},    {5, 3, "1.70828608729473871279604482173e-01"},
      {5, 4, "1.25467687566822425016691814123e-01"},   {6, 0, "3.7109375e-02"},
      {6, 3, "1.70252211019544039314978060272e-01"},   {6, 4, "6.02165389804559606850219397283e-02"},
      {6, 5, "-1.7578125e-02"},                        {7, 6, "8.27378916381402288758473766002e-03"},
  };
  for (const auto& e : published) {
    const T& v = e.j < 0 ? tab.c[static_cast<std::size_t>(e.i)]
                         : tab.a[static_cast<std::size_t>(e.i)][static_cast<std::size_t>(e.j)];
    const T d = abs(v - T(e.text));
    EXPECT_LE(d, T("1e-30")) << "(" << e.i << "," << e.j << ") " << e.text << " vs " << v;
  }
}

// ---- the Euler reference and the rk8 floor -----------------------------------------------------

TEST(RungeKuttaReference, TaylorReferenceIsConvergedAt200Bits) {
  mpfr_precision_scope scope(200);
  const vec3<mpfr_real> x0{mpfr_real(1) / 2, 0, 1}, G{1, 1, 1};
  const auto a = euler_taylor(x0, G, mpfr_real(euler_span), 64, 60);
  const auto b = euler_taylor(x0, G, mpfr_real(euler_span), 128, 60);
  const mpfr_real d = max_abs_diff<mpfr_real>(a, b);
  std::printf("  Taylor(60) 64 vs 128 steps, MPFR 200 bits: %.2e\n", static_cast<double>(d));
  EXPECT_LE(d, mpfr_real("1e-50"));
}

// rk8 in MPFR at 200 bits against the Taylor reference: the rational-coefficient part converges
// at order 8 and then the ~1e-30 precision of the dop853.f decimals sets the floor.
TEST(RungeKuttaReference, Rk8InMpfrReachesTheDop853CoefficientFloor) {
  mpfr_precision_scope scope(200);
  using T = mpfr_real;
  const vec3<T> x0{T(1) / 2, 0, 1}, G{1, 1, 1};
  const auto ref = euler_taylor(x0, G, T(euler_span), 64, 60);
  const auto sys = euler_system<T>(G);
  std::vector<double> errors;
  for (std::size_t n : {256u, 1024u, 4096u, 16384u}) {
    vec3<T> x = x0;
    const auto r = rk::integrate_fixed<rk::rk8_tableau>(sys, x, T(0), T(euler_span) / T(n), n);
    EXPECT_EQ(r.steps, n);
    errors.push_back(static_cast<double>(max_abs_diff<T>(x, ref)));
  }
  std::printf("  rk8 MPFR-200 euler: err(256..16384)= %.2e %.2e %.2e %.2e\n", errors[0], errors[1], errors[2], errors[3]);
  // Order 8 between 256 and 1024 steps (error 1e-18 -> 1e-23), then the floor: about 1e-28 at
  // 16384 steps, set by the ~30-digit weights (relative consistency defect ~1e-30, see above).
  EXPECT_NEAR(std::log(errors[0] / errors[1]) / std::log(4.0), 8, 0.3);
  EXPECT_LE(errors[3], 1e-27);
}

// ---- states, dispatch, driver ---------------------------------------------------------------------

TEST(RungeKuttaStepper, AggregateStateGivesTheSameBitsAsArrayState) {
  const quad h = quad(1) / quad(10);
  std::array<quad, 2> xa{1, 0};
  planar<quad> xs{1, 0};
  rk::integrate_fixed<rk::rk8_tableau>(rotation{}, xa, quad(0), h, 37);
  const auto r = rk::integrate_fixed<rk::rk8_tableau>(rotation{}, xs, quad(0), h, 37);
  EXPECT_EQ(r.steps, 37u);
  EXPECT_EQ(xa[0], xs.x);
  EXPECT_EQ(xa[1], xs.y);
  static_assert(std::is_same_v<rk::state_value_t<planar<quad>>, quad>);
  static_assert(std::is_same_v<rk::state_value_t<vec3<double>>, double>);
}

TEST(RungeKuttaStepper, RuntimeDispatchEqualsTheStaticLoop) {
  const auto sys = euler_system<double>({1, 1, 1});
  for (rk::method m : rk::fixed_step_methods) {
    vec3<double> xs{0.5, 0, 1}, xd{0.5, 0, 1};
    const double h = 1.0 / 64;
    rk::dispatch_method(m, [&](auto tag) {
      return rk::integrate_fixed<decltype(tag)>(sys, xs, 0.0, h, 100);
    });
    const auto r = rk::integrate_fixed(m, sys, xd, 0.0, h, 100);
    EXPECT_EQ(xs, xd) << rk::method_name(m);
    EXPECT_EQ(r.steps, 100u);
  }
}

// The driver counts every right-hand-side evaluation: stages x steps (no FSAL in fixed steps).
TEST(RungeKuttaStepper, RhsEvaluationCountIsStagesTimesSteps) {
  for (rk::method m : rk::fixed_step_methods) {
    std::size_t calls = 0;
    auto counting = [&](const vec3<double>& x, vec3<double>& dx, const double&) {
      ++calls;
      eulervop::euler_rhs(x, vec3<double>{1, 1, 1}, dx);
    };
    vec3<double> x{0.5, 0, 1};
    std::size_t observed = 0;
    const auto r = rk::integrate_fixed(m, counting, x, 0.0, 0.01, 250,
                                       [&](std::size_t step, const double&, const vec3<double>&) {
                                         EXPECT_EQ(step, observed++);
                                       });
    EXPECT_EQ(observed, 251u) << "observer: step 0, then after each of the 250 steps";
    EXPECT_EQ(calls, rk::stage_count(m) * 250) << rk::method_name(m);
    EXPECT_EQ(r.rhs_evals, calls);
    EXPECT_EQ(r.steps, 250u);
    EXPECT_EQ(r.stop, eulervop::outcome_kind::success);
    EXPECT_EQ(r.t, 0.01 * 250);
  }
}

TEST(RungeKuttaStepper, ObserverReturningFalseStops) {
  vec3<double> x{0.5, 0, 1};
  const auto r = rk::integrate_fixed(rk::method::rk4, euler_system<double>({1, 1, 1}), x, 0.0, 0.1,
                                     100, [](std::size_t step, const double&, const vec3<double>&) {
                                       return step < 3;
                                     });
  EXPECT_EQ(r.steps, 3u);
  EXPECT_EQ(r.stop, eulervop::outcome_kind::observer_stop);
  EXPECT_FALSE(r.diverged());
  EXPECT_EQ(r.rhs_evals, 12u);
}

// MPFR values allocate through GMP's memory functions: count them around the stepping loop.
std::size_t gmp_allocations = 0;
void* (*gmp_alloc_orig)(size_t) = nullptr;
void* (*gmp_realloc_orig)(void*, size_t, size_t) = nullptr;
void (*gmp_free_orig)(void*, size_t) = nullptr;
void* counting_alloc(size_t n) { ++gmp_allocations; return gmp_alloc_orig(n); }
void* counting_realloc(void* p, size_t o, size_t n) { ++gmp_allocations; return gmp_realloc_orig(p, o, n); }

TEST(RungeKuttaStepper, MpfrSteppingLoopDoesNotAllocate) {
  mpfr_precision_scope scope(200);
  using T = mpfr_real;
  const auto sys = euler_system<T>({1, 1, 1});
  vec3<T> x{T(1) / 2, 0, 1};
  const T h = T(1) / 64;
  T t = 0;
  rk::explicit_rk<rk::rk8_tableau, vec3<T>> stepper(x);
  stepper.do_step(sys, x, t, h);  // warm-up
  mp_get_memory_functions(&gmp_alloc_orig, &gmp_realloc_orig, &gmp_free_orig);
  mp_set_memory_functions(counting_alloc, counting_realloc, gmp_free_orig);
  gmp_allocations = 0;
  for (int n = 0; n < 50; ++n) stepper.do_step(sys, x, t, h);
  const std::size_t in_loop = gmp_allocations;
  { const T control = x[0] + h; }  // positive control: a new MPFR value does allocate
  const std::size_t control = gmp_allocations - in_loop;
  mp_set_memory_functions(gmp_alloc_orig, gmp_realloc_orig, gmp_free_orig);
  EXPECT_EQ(in_loop, 0u) << "GMP/MPFR allocations in 50 rk8 steps";
  EXPECT_GT(control, 0u) << "the allocation counter is not hooked in";
  EXPECT_EQ(stepper.rhs_evaluations(), 51u * 12u);
}

// x' = x^2, x(0) = 1 blows up at t = 1. The run must stop there, say so, and keep a finite state.
template <class T>
void check_blow_up(rk::method m, const T& h, std::optional<T> bound) {
  std::array<T, 1> x{1};
  bool observer_saw_non_finite = false;
  rk::fixed_step_options<T> opt;
  opt.max_norm = bound;
  const auto r = rk::integrate_fixed(
      m, square{}, x, T(0), h, static_cast<std::size_t>(4 / static_cast<double>(h)),
      [&](std::size_t, const T&, const std::array<T, 1>& s) {
        if (!rk::all_finite(s)) observer_saw_non_finite = true;
      },
      opt);
  ASSERT_TRUE(r.diverged()) << rk::method_name(m);
  ASSERT_TRUE(r.failed_at.has_value());
  if (bound) {
    // A single step can jump from below the bound straight to Inf (rk8 in double does).
    EXPECT_TRUE(r.stop == eulervop::outcome_kind::norm_bound || r.stop == eulervop::outcome_kind::non_finite);
  } else {
    EXPECT_EQ(r.stop, eulervop::outcome_kind::non_finite);
  }
  EXPECT_FALSE(observer_saw_non_finite);
  EXPECT_TRUE(rk::all_finite(x)) << "the returned state must stay finite";
  EXPECT_EQ(r.t + h, *r.failed_at);
  EXPECT_EQ(r.rhs_evals, rk::stage_count(m) * (r.steps + 1));
  const double at = static_cast<double>(*r.failed_at), hd = static_cast<double>(h);
  std::printf("  %-5s h=%-9.3g bound=%-8.3g diverged_at=%.6f (blow-up at 1)\n",
              std::string(rk::method_name(m)).c_str(), hd,
              bound ? static_cast<double>(*bound) : 0.0, at);
  if (bound) {
    // |x| = bound exactly at t = 1 - 1/bound; the run stops within a step or two of it.
    EXPECT_NEAR(at, 1.0 - 1.0 / static_cast<double>(*bound), 2 * hd);
  } else {
    EXPECT_GT(at, 1.0 - hd);
    EXPECT_LT(at, 1.0 + 16 * hd);
  }
}

TEST(RungeKuttaDivergence, BlowUpIsReportedNearTheSingularity) {
  for (rk::method m : rk::fixed_step_methods) {
    check_blow_up<double>(m, 1.0 / 64, std::nullopt);
    check_blow_up<quad>(m, quad(1) / quad(64), std::nullopt);
    check_blow_up<double>(m, 1.0 / 1024, 1e6);
    check_blow_up<quad>(m, quad(1) / quad(1024), quad(1e6));
  }
}

}  // namespace

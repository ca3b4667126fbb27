// Nanoseconds per right-hand-side evaluation in double (docs/benchmarks.md): Euler's equations
// (Eq. 5) against the paper's VOP (Eqs. 13, 16), where k = c1/c2 changes at every call as it
// does between Runge-Kutta stages, so the modulus part is paid every time.
//
//   euler_rhs                Eq. 5.
//   vop_rhs_new_k            eulervop::vop_system<double>, k uniform in [0.05, 0.95] (the
//                            theta-function route of jacobi_theta.hpp).
//   vop_rhs_new_k_boost      the same Eqs. 13 and 16 with the elliptic quantities from Boost.Math
//                            without promotion (boost_elliptic_set.hpp: jacobi_elliptic,
//                            ellint_1/2, jacobi_zeta), the peer measured in the same run.
//   vop_rhs_new_k_separatrix k in [0.99, 1 - 1e-6], where vop_system falls back to the AGM route.
// Inputs cycle through 1024 fixed pseudo-random elements: c2 in [0.5, 100], u in [-50, 50].
#include "boost_elliptic_set.hpp"

#include <eulervop/model/euler_problem.hpp>
#include <eulervop/vop/vop_system.hpp>

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

namespace {

using eulervop::vec3;

std::vector<vec3<double>> element_inputs(double k_lo, double k_hi) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> kk(k_lo, k_hi), c2d(0.5, 100.0), ud(-50.0, 50.0);
  std::vector<vec3<double>> v;
  for (int i = 0; i < 1024; ++i) {
    const double c2 = c2d(rng);
    v.push_back({kk(rng) * c2, c2, ud(rng)});
  }
  return v;
}

const vec3<double> torque{1, 1, 1};

void BM_euler_rhs(benchmark::State& state) {
  const auto in = element_inputs(0.05, 0.95);
  vec3<double> d;
  std::size_t i = 0;
  for (auto _ : state) {
    eulervop::euler_rhs(in[i++ & 1023], torque, d);
    benchmark::DoNotOptimize(d);
  }
}
BENCHMARK(BM_euler_rhs);

void vop_rhs(benchmark::State& state, double k_lo, double k_hi) {
  const auto in = element_inputs(k_lo, k_hi);
  eulervop::vop_system<double> sys(torque);
  vec3<double> d;
  std::size_t i = 0;
  for (auto _ : state) {
    sys(in[i++ & 1023], d, 0.0);
    benchmark::DoNotOptimize(d);
  }
}

void BM_vop_rhs_new_k(benchmark::State& state) { vop_rhs(state, 0.05, 0.95); }
BENCHMARK(BM_vop_rhs_new_k);

void BM_vop_rhs_new_k_separatrix(benchmark::State& state) { vop_rhs(state, 0.99, 1 - 1e-6); }
BENCHMARK(BM_vop_rhs_new_k_separatrix);

// Eqs. 13 and 16 as vop_system writes them, with Boost.Math's special functions.
void BM_vop_rhs_new_k_boost(benchmark::State& state) {
  const auto in = element_inputs(0.05, 0.95);
  const bench::no_promote pol;
  const double G1 = torque[0], G2 = torque[1], G3 = torque[2];
  vec3<double> d;
  std::size_t i = 0;
  for (auto _ : state) {
    const vec3<double>& y = in[i++ & 1023];
    const double c1 = y[0], c2 = y[1];
    const double k = c1 / c2;
    const double kc2 = (c2 - c1) * (c2 + c1) / (c2 * c2);
    const double K = boost::math::ellint_1(k, pol), E = boost::math::ellint_2(k, pol);
    const bench::six j = bench::boost_set(y[2], k, K, E, pol);
    const double secular = j.E - kc2 * y[2];
    d[0] = j.cn * G1 + j.sn * G2;
    d[1] = k * j.sn * G2 + j.dn * G3;
    d[2] = c2 + (-j.sn * j.dn * G1 + kc2 * j.cn * j.dn * G2 + k * k * k * j.sn * j.cn * G3 +
                 secular * (j.cn * G1 + kc2 * j.sn * G2 - k * j.dn * G3)) /
                    (c1 * kc2);
    benchmark::DoNotOptimize(d);
  }
}
BENCHMARK(BM_vop_rhs_new_k_boost);

}  // namespace

BENCHMARK_MAIN();

// Nanoseconds per right-hand-side evaluation in double (issue 3 acceptance): Euler's equations
// (Eq. 5) against the paper's VOP (Eqs. 13, 16), where k = c1/c2 changes at every call as it
// does between Runge-Kutta stages, so the modulus part (AGM, K, E) is paid every time.
// Run together with bench_elliptic for the Boost.Math comparison of the special functions.
#include <eulervop/model.hpp>
#include <eulervop/vop.hpp>

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

namespace {

using eulervop::vec3;

std::vector<vec3<double>> element_inputs() {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> kk(0.05, 0.95), c2d(0.5, 100.0), ud(-50.0, 50.0);
  std::vector<vec3<double>> v;
  for (int i = 0; i < 1024; ++i) {
    const double c2 = c2d(rng);
    v.push_back({kk(rng) * c2, c2, ud(rng)});
  }
  return v;
}

void BM_euler_rhs(benchmark::State& state) {
  const auto in = element_inputs();
  const vec3<double> G{1, 1, 1};
  vec3<double> d;
  std::size_t i = 0;
  for (auto _ : state) {
    eulervop::euler_rhs(in[i++ & 1023], G, d);
    benchmark::DoNotOptimize(d);
  }
}
BENCHMARK(BM_euler_rhs);

void BM_vop_rhs_new_k(benchmark::State& state) {
  const auto in = element_inputs();
  eulervop::vop_system<double> sys({1, 1, 1});
  vec3<double> d;
  std::size_t i = 0;
  for (auto _ : state) {
    sys(in[i++ & 1023], d, 0.0);
    benchmark::DoNotOptimize(d);
  }
}
BENCHMARK(BM_vop_rhs_new_k);

}  // namespace

BENCHMARK_MAIN();

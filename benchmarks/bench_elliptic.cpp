// Nanoseconds per evaluation of sn, cn, dn, am(u), Z(u), E(u) (and K, E when k changes), in
// double: eulervop's fused AGM (include/eulervop/special/elliptic.hpp) and its theta-function route
// (include/eulervop/special/jacobi_theta.hpp: sn, cn, dn, Z, E(u), no am) against Boost.Math computing
// the same quantities (boost_elliptic_set.hpp), with double -> long double promotion off and
// with Boost's default policy.
//
// Two scenarios:
//   *_cached_k  the modulus is fixed (K, E and our elliptic_modulus computed once, outside the
//               loop); only the u-dependent part is timed.
//   *_new_k     k changes at every call (the VOP right-hand side, where k is an element): the
//               modulus-dependent part is timed too.
// Inputs cycle through 1024 fixed pseudo-random (u, k) pairs: u in [-4K, 4K], k in [0.05, 0.95]
// (cached: k = 0.5).
#include "boost_elliptic_set.hpp"
#include "eulervop/special/elliptic.hpp"
#include "eulervop/special/jacobi_theta.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

using bench::boost_set;
using bench::default_policy;
using bench::no_promote;
using bench::six;

constexpr std::size_t n_inputs = 1024;
constexpr double cached_k = 0.5;

struct inputs {
  std::vector<double> u, k;
};

const inputs& cached_inputs() {
  static const inputs in = [] {
    inputs r;
    std::mt19937_64 rng(1);
    const double K = boost::math::ellint_1(cached_k);
    for (std::size_t i = 0; i < n_inputs; ++i) {
      r.u.push_back((static_cast<double>(rng() >> 11) * 0x1p-53 * 2 - 1) * 4 * K);
      r.k.push_back(cached_k);
    }
    return r;
  }();
  return in;
}

const inputs& varying_inputs() {
  static const inputs in = [] {
    inputs r;
    std::mt19937_64 rng(2);
    for (std::size_t i = 0; i < n_inputs; ++i) {
      const double k = 0.05 + 0.9 * static_cast<double>(rng() >> 11) * 0x1p-53;
      const double K = boost::math::ellint_1(k);
      r.u.push_back((static_cast<double>(rng() >> 11) * 0x1p-53 * 2 - 1) * 4 * K);
      r.k.push_back(k);
    }
    return r;
  }();
  return in;
}

void consume(benchmark::State& state, const six& s) {
  benchmark::DoNotOptimize(s.sn);
  benchmark::DoNotOptimize(s.cn);
  benchmark::DoNotOptimize(s.dn);
  benchmark::DoNotOptimize(s.am);
  benchmark::DoNotOptimize(s.Z);
  benchmark::DoNotOptimize(s.E);
  (void)state;
}

// ---- cached modulus ---------------------------------------------------------------------

void eulervop_cached_k(benchmark::State& state) {
  const auto& in = cached_inputs();
  const eulervop::elliptic_modulus<double> m(cached_k);
  eulervop::jacobi_values<double> j;
  std::size_t i = 0;
  for (auto _ : state) {
    eulervop::jacobi_eval(in.u[i], m, j);
    consume(state, {j.sn, j.cn, j.dn, j.am, j.Z, j.E});
    i = (i + 1) % n_inputs;
  }
}

template <class Policy>
void boost_cached_k(benchmark::State& state) {
  const auto& in = cached_inputs();
  const double K = boost::math::ellint_1(cached_k), E = boost::math::ellint_2(cached_k);
  std::size_t i = 0;
  for (auto _ : state) {
    consume(state, boost_set(in.u[i], cached_k, K, E, Policy()));
    i = (i + 1) % n_inputs;
  }
}

// ---- modulus changes every call (VOP right-hand side) -------------------------------------

void eulervop_new_k(benchmark::State& state) {
  const auto& in = varying_inputs();
  eulervop::jacobi_values<double> j;
  std::size_t i = 0;
  for (auto _ : state) {
    const eulervop::elliptic_modulus<double> m(in.k[i]);
    eulervop::jacobi_eval(in.u[i], m, j);
    consume(state, {j.sn, j.cn, j.dn, j.am, j.Z, j.E});
    benchmark::DoNotOptimize(m.K());
    benchmark::DoNotOptimize(m.E());
    i = (i + 1) % n_inputs;
  }
}

template <class Policy>
void boost_new_k(benchmark::State& state) {
  const auto& in = varying_inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    const double k = in.k[i];
    const double K = boost::math::ellint_1(k, Policy()), E = boost::math::ellint_2(k, Policy());
    benchmark::DoNotOptimize(K);
    benchmark::DoNotOptimize(E);
    consume(state, boost_set(in.u[i], k, K, E, Policy()));
    i = (i + 1) % n_inputs;
  }
}

// The modulus part alone (AGM, K, E, E/K), for reference.
void eulervop_modulus_only(benchmark::State& state) {
  const auto& in = varying_inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    const eulervop::elliptic_modulus<double> m(in.k[i]);
    benchmark::DoNotOptimize(m.K());
    benchmark::DoNotOptimize(m.e_over_k());
    i = (i + 1) % n_inputs;
  }
}

// The theta route (jacobi_theta.hpp): everything but am, which the VOP right-hand side never uses.
void theta_cached_k(benchmark::State& state) {
  const auto& in = cached_inputs();
  const eulervop::theta_modulus m(cached_k);
  eulervop::jacobi_values<double> j;
  std::size_t i = 0;
  for (auto _ : state) {
    eulervop::theta_eval(in.u[i], m, j);
    consume(state, {j.sn, j.cn, j.dn, 0.0, j.Z, j.E});
    i = (i + 1) % n_inputs;
  }
}

void theta_new_k(benchmark::State& state) {
  const auto& in = varying_inputs();
  eulervop::theta_modulus m;
  eulervop::jacobi_values<double> j;
  std::size_t i = 0;
  for (auto _ : state) {
    m.assign(in.k[i]);
    eulervop::theta_eval(in.u[i], m, j);
    consume(state, {j.sn, j.cn, j.dn, 0.0, j.Z, j.E});
    benchmark::DoNotOptimize(m.K());
    benchmark::DoNotOptimize(m.E());
    i = (i + 1) % n_inputs;
  }
}

BENCHMARK(eulervop_cached_k)->Name("cached_k/eulervop_fused_agm");
BENCHMARK(theta_cached_k)->Name("cached_k/eulervop_theta_no_am");
BENCHMARK(boost_cached_k<no_promote>)->Name("cached_k/boost_no_promotion");
BENCHMARK(boost_cached_k<default_policy>)->Name("cached_k/boost_default_policy");
BENCHMARK(eulervop_new_k)->Name("new_k/eulervop_fused_agm");
BENCHMARK(theta_new_k)->Name("new_k/eulervop_theta_no_am");
BENCHMARK(boost_new_k<no_promote>)->Name("new_k/boost_no_promotion");
BENCHMARK(boost_new_k<default_policy>)->Name("new_k/boost_default_policy");
BENCHMARK(eulervop_modulus_only)->Name("new_k/eulervop_modulus_only");

}  // namespace

BENCHMARK_MAIN();

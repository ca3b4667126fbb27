// Nanoseconds per evaluation of sn, cn, dn, am(u), Z(u), E(u) (and K, E when k changes), in
// double: eulervop's fused AGM (include/eulervop/elliptic.hpp) against Boost.Math computing the
// same quantities, with double -> long double promotion off and with Boost's default policy.
//
//   Boost set: jacobi_elliptic(k, u, &cn, &dn)   -> sn, cn, dn
//              ellint_1(k), ellint_2(k)          -> K, E
//              am = n pi + atan2(sn, cn) with n = nearest(u / 2K)
//              jacobi_zeta(k, am)                -> Z;   E(u) = Z + (E/K) u
//
// Two scenarios:
//   *_cached_k  the modulus is fixed (K, E and our elliptic_modulus computed once, outside the
//               loop); only the u-dependent part is timed.
//   *_new_k     k changes at every call (the VOP right-hand side, where k is an element): the
//               modulus-dependent part is timed too.
// Inputs cycle through 1024 fixed pseudo-random (u, k) pairs: u in [-4K, 4K], k in [0.05, 0.95]
// (cached: k = 0.5).
#include "eulervop/elliptic.hpp"

#include <benchmark/benchmark.h>

#include <boost/math/policies/policy.hpp>
#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_2.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <boost/math/special_functions/jacobi_zeta.hpp>

#include <cmath>
#include <random>
#include <vector>

namespace {

using no_promote = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
using default_policy = boost::math::policies::policy<>;

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

struct six {
  double sn, cn, dn, am, Z, E;
};

template <class Policy>
six boost_set(double u, double k, double K, double E, const Policy& pol) {
  six out;
  out.sn = boost::math::jacobi_elliptic(k, u, &out.cn, &out.dn, pol);
  const double n = std::nearbyint(u / (2 * K));
  out.am = n * M_PI + std::atan2(n == 2 * std::floor(n / 2) ? out.sn : -out.sn,
                                 n == 2 * std::floor(n / 2) ? out.cn : -out.cn);
  out.Z = boost::math::jacobi_zeta(k, out.am, pol);
  out.E = out.Z + (E / K) * u;
  return out;
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

BENCHMARK(eulervop_cached_k)->Name("cached_k/eulervop_fused_agm");
BENCHMARK(boost_cached_k<no_promote>)->Name("cached_k/boost_no_promotion");
BENCHMARK(boost_cached_k<default_policy>)->Name("cached_k/boost_default_policy");
BENCHMARK(eulervop_new_k)->Name("new_k/eulervop_fused_agm");
BENCHMARK(boost_new_k<no_promote>)->Name("new_k/boost_no_promotion");
BENCHMARK(boost_new_k<default_policy>)->Name("new_k/boost_default_policy");
BENCHMARK(eulervop_modulus_only)->Name("new_k/eulervop_modulus_only");

}  // namespace

BENCHMARK_MAIN();

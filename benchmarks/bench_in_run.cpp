// Nanoseconds per right-hand-side evaluation inside whole runs (the cost that decides whether
// VOP pays), on the paper scene (G = (1,1,1), Omega(0) = (0.5, 0, 1), tau in [0, 136]):
//
//   fixed/<formulation>/<method>     eulervop::run_fixed at h = K(0.5)/3200 (258163 steps), as
//                                    `eulervop report --step K/3200` times it;
//   adaptive/<formulation>/<method>  eulervop::run_adaptive at atol = rtol = 1e-10;
//   odeint/rk4, odeint/dopri5        the peer in the same run: Boost.Odeint's runge_kutta4 at the
//                                    same step, and its controlled runge_kutta_dopri5 at the same
//                                    tolerances, on Eq. 5 (std::array<double, 3>).
// The counter ns_per_eval is the run's time over its evaluations (the statistic `report` and
// `sweep` print as seconds / rhs_evals).
//
//   cmake --build build --target bench_in_run && build/benchmarks/bench_in_run
#include <eulervop/runs/comparison_run.hpp>
#include <eulervop/special/elliptic.hpp>

#include <benchmark/benchmark.h>
#include <boost/numeric/odeint.hpp>

#include <array>
#include <string>

namespace {

using V = eulervop::vec3<double>;
namespace rk = eulervop::rk;
namespace odeint = boost::numeric::odeint;

constexpr double tau_end = 136;
const double h = eulervop::elliptic_modulus<double>(0.5).K() / 3200;

eulervop::euler_problem<double> paper() {
  eulervop::euler_problem<double> p;
  p.torque.G = {1, 1, 1};
  p.Omega0 = {0.5, 0, 1};
  return p;
}

void per_eval(benchmark::State& state, double seconds, std::size_t evals) {
  state.SetIterationTime(seconds);
  state.counters["ns_per_eval"] = seconds / static_cast<double>(evals) * 1e9;
  state.counters["evals"] = static_cast<double>(evals);
}

void fixed(benchmark::State& state, eulervop::formulation f, rk::method m) {
  const auto n = static_cast<std::size_t>(tau_end / h);
  for (auto _ : state) {
    const auto r = eulervop::run_fixed(f, m, paper(), eulervop::fixed_run_settings{h, n, n / 100});
    per_eval(state, r.seconds, r.rhs_evals);
  }
}

void adaptive(benchmark::State& state, eulervop::formulation f, rk::method m) {
  eulervop::adaptive_run_settings s;
  s.tau_end = tau_end;
  s.atol = s.rtol = 1e-10;
  s.h_max = 2 * 3200 * h / 2;  // K/2
  for (auto _ : state) {
    const auto r = eulervop::run_adaptive(f, m, paper(), s);
    per_eval(state, r.seconds, r.rhs_evals);
  }
}

struct euler_eq {
  void operator()(const V& x, V& dx, double) const { eulervop::euler_rhs(x, V{1, 1, 1}, dx); }
};

void odeint_rk4(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(tau_end / h);
  for (auto _ : state) {
    odeint::runge_kutta4<V> stepper;
    V x{0.5, 0, 1};
    const auto start = std::chrono::steady_clock::now();
    double t = 0;
    for (std::size_t i = 0; i < n; ++i) {
      stepper.do_step(euler_eq{}, x, t, h);
      t += h;
    }
    benchmark::DoNotOptimize(x);
    per_eval(state, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 4 * n);
  }
}

void odeint_dopri5(benchmark::State& state) {
  for (auto _ : state) {
    auto stepper = odeint::make_controlled(1e-10, 1e-10, odeint::runge_kutta_dopri5<V>());
    V x{0.5, 0, 1};
    std::size_t evals = 0;
    auto counting = [&](const V& a, V& d, double t) {
      ++evals;
      euler_eq{}(a, d, t);
    };
    const auto start = std::chrono::steady_clock::now();
    odeint::integrate_adaptive(stepper, counting, x, 0.0, tau_end, 1e-3);
    benchmark::DoNotOptimize(x);
    per_eval(state, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), evals);
  }
}

int register_all() {
  for (auto f : eulervop::all_formulations) {
    const std::string fn(eulervop::formulation_name(f));
    for (auto m : {rk::method::rk4, rk::method::rk8})
      benchmark::RegisterBenchmark(("fixed/" + fn + "/" + std::string(rk::method_name(m))).c_str(),
                                   [f, m](benchmark::State& s) { fixed(s, f, m); })
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond);
    for (auto m : {rk::method::dp45, rk::method::dop853})
      benchmark::RegisterBenchmark(("adaptive/" + fn + "/" + std::string(rk::method_name(m))).c_str(),
                                   [f, m](benchmark::State& s) { adaptive(s, f, m); })
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("odeint/rk4", odeint_rk4)->UseManualTime()->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("odeint/dopri5", odeint_dopri5)->UseManualTime()->Unit(benchmark::kMillisecond);
  return 0;
}
const int registered = register_all();

}  // namespace

BENCHMARK_MAIN();

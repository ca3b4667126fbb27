// Work-precision of reference generation on the paper scene (docs/benchmarks.md). A benchmark,
// not a timed test: speed is measured here and never asserted by the test suite.
//
// Scene (paper Section 3): G = (1, 1, 1), Omega(0) = (0.5, 0, 1), tau in [0, 136], Eq. 5.
// Samples: tau = i/16, i = 0..2176 (exact in every scalar type).
// Truth: our Chebyshev-Picard integrator in mpfr:320, computed once and cached next to this
// executable (bench_reference_truth_320_<tau_end>.txt, keyed by a header line).
// Error: Eq. 20, e = sqrt(sum_i (Omega_i - Omega_i^truth)^2), the maximum over the samples,
// computed in MPFR at 400 bits from the round-trip decimal texts of both sides.
//
// Rows, each the best wall time of --repeat N runs (std::chrono::steady_clock). A timed run
// produces the samples in the row's own scalar type: our integrator integrates and evaluates its
// dense output at the sample times; Boost.Odeint integrates with integrate_times, which steps
// onto every sample time. Text conversion and error measurement are outside the timing.
//   - ours, quad: tolerance 1e-20, 1e-24, 1e-28, 1e-30 and the default (epsilon of quad);
//   - ours, mpfr:256: tolerance 1e-40, 1e-50, 1e-60 and the default (epsilon at 257 bits);
//   - Boost.Odeint bulirsch_stoer<float128>, abs = rel tol 1e-20, 1e-24, 1e-28, 1e-32;
//   - Boost.Odeint controlled runge_kutta_fehlberg78<float128>, the same tolerances
//     (a row is abandoned after 60 s and printed as "skipped");
//   - Boost.Odeint bulirsch_stoer on MPFR at 256 bits, tol 1e-40, 1e-50, 1e-60; the sweep stops
//     after the first row that takes more than 120 s, and a row is abandoned after --mpfr-cap s.
//
// Options: --problem paper|sciml (default paper), --quick (quad rows with tol >= 1e-24 only,
//          tau_end = 20), --targets (only ours in quad at the default, Odeint
//          bulirsch_stoer<float128> at 1e-28 and ours in mpfr:256 at 1e-60: the rows the speed
//          targets compare), --repeat N, --no-mpfr, --mpfr-cap SECONDS (default 600),
//          --recompute-truth.
//
// --problem sciml: the SciML rigid body (SciMLBenchmarks, NonStiffODE/RigidBody_wpd.jmd), the
// scene data/scenes/problems/sciml-rigid-body-100.toml in the coefficient form:
//   y1' = -2 y2 y3, y2' = 1.25 y1 y3, y3' = -0.5 y1 y2 + 0.25 sin^2 t, y(0) = (1, 0, 0.9),
//   t in [0, 100], samples t = i/16, i = 0..1600.
// Our integrator runs the problem the scene compiles (scene::with_problem, a torque of time);
// the peer integrates the same equations written out, with the scene's initial state in its
// own type. Truth: ours in mpfr:320 (cached as bench_reference_truth_320_sciml_<t_end>.txt).
// Rows: ours in quad at 1e-24, 1e-28 and the default; Odeint bulirsch_stoer<float128> at 1e-20,
// 1e-24, 1e-28 (the baseline), 1e-32; --targets: ours quad default and Odeint 1e-28. No MPFR or
// rkf78 rows for this problem. The error is the same norm, sqrt(sum_i (y_i - y_i^truth)^2).
// The scene file is found from the working directory or from this source file's location.
// Progress goes to standard error; the table to standard output.
#include <eulervop/reference/integrate.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/model/expression_torque.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include "reference_bench_support.hpp"

#include <boost/multiprecision/float128.hpp>
#include <boost/multiprecision/mpfr.hpp>
#include <boost/numeric/odeint.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace odeint = boost::numeric::odeint;

// The Boost.Odeint MPFR scalar, the clock, text and progress helpers shared with bench_problems.
using eulervop::bench::odeint_mpfr;

namespace {

using eulervop::bench::bulirsch_stoer_maker;
using eulervop::bench::clock_type;
using eulervop::bench::executable_dir;
using eulervop::bench::progress_printer;
using eulervop::bench::seconds_since;
using eulervop::bench::text_of;
using text3 = std::array<std::string, 3>;

enum class problem_id { paper, sciml };

struct options {
  problem_id problem = problem_id::paper;
  bool quick = false;
  bool targets = false;  // only the rows the speed targets compare (docs/benchmarks.md)
  bool no_mpfr = false;
  bool recompute_truth = false;
  int repeat = 1;
  double mpfr_cap = 600;
};

// The scene and the sample grid.
constexpr int samples_per_unit = 16;
int sample_count(int tau_end) { return tau_end * samples_per_unit + 1; }

template <class T>
std::vector<T> sample_times(int tau_end) {
  std::vector<T> t(sample_count(tau_end));
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = T(static_cast<int>(i)) / T(samples_per_unit);
  return t;
}

template <class T>
eulervop::euler_problem<T> paper_problem() {
  eulervop::euler_problem<T> p;
  p.torque.G = {T(1), T(1), T(1)};
  p.Omega0 = {T(1) / T(2), T(0), T(1)};
  p.tau0 = T(0);
  return p;
}

// ---- the SciML rigid body ------------------------------------------------------------------
constexpr const char* sciml_scene_relative = "data/scenes/problems/sciml-rigid-body-100.toml";

std::filesystem::path sciml_scene_path() {
  const std::filesystem::path rel = sciml_scene_relative;
  if (std::filesystem::exists(rel)) return rel;
  return std::filesystem::path(__FILE__).parent_path().parent_path() / rel;
}

// The peer's equations, written out in V: y' = (a1 y2 y3, a2 y3 y1, a3 y1 y2 + 0.25 sin(t)^2),
// a = (-2, 1.25, -0.5); every constant is exact in binary.
template <class V>
struct sciml_system {
  std::array<V, 3> a{V(-2), V(5) / V(4), V(-1) / V(2)};
  V quarter = V(1) / V(4);
  void operator()(const std::array<V, 3>& y, std::array<V, 3>& dydt, const V& t) const {
    using std::sin;
    using boost::multiprecision::sin;
    const V s = sin(t);
    dydt[0] = a[0] * y[1] * y[2];
    dydt[1] = a[1] * y[2] * y[0];
    dydt[2] = a[2] * y[0] * y[1] + quarter * (s * s);
  }
};

// Loads the scene and checks that it is the problem the peer's equations state (coefficients,
// initial state, span, and the torque's value at a few times in quad), so that both sides
// integrate the same thing.
eulervop::scene::scene load_sciml_scene() {
  const auto path = sciml_scene_path();
  eulervop::scene::scene scn = eulervop::scene::load_scene_file(path);
  auto fail = [&](const std::string& why) {
    throw std::runtime_error("scene " + path.string() + " is not the SciML rigid body this benchmark states: " + why);
  };
  if (!scn.is_coefficient_form() || !scn.coefficients) fail("not in the coefficient form");
  const double a[3] = {-2.0, 1.25, -0.5}, y0[3] = {1.0, 0.0, 0.9};
  for (int i = 0; i < 3; ++i)
    if ((*scn.coefficients)[i].value != a[i]) fail("a differs");
  const auto* rates = std::get_if<eulervop::scene::initial_rates>(&scn.initial);
  if (!rates) fail("no initial y");
  for (int i = 0; i < 3; ++i)
    if (rates->rates[i].value != y0[i]) fail("y(0) differs");
  if (scn.span_end.value != 100.0) fail("t_end is not 100");
  if (eulervop::scene::torque_kind_of(scn) != eulervop::scene::torque_kind::of_time) fail("f is not a formula of time");
  using Q = eulervop::quad;
  const auto problem = eulervop::scene::to_problem_with_law<Q, false>(scn);
  const sciml_system<Q> sys;
  for (int i = 0; i < 3; ++i)
    if (problem.a[i] != sys.a[i]) fail("a in quad differs");
  const eulervop::vec3<Q> y = {Q(1), Q(2), Q(3)};
  for (int k = 0; k <= 7; ++k) {
    const Q t = Q(k * 13 + 1) / Q(8);
    const auto g = problem.torque.value(t, y);
    std::array<Q, 3> f;
    sys({Q(0), Q(0), Q(0)}, f, t);
    for (int i = 0; i < 3; ++i)
      if (abs(g[i] - f[i]) > 4 * std::numeric_limits<Q>::epsilon()) fail("f(t) differs at t = " + std::to_string(static_cast<double>(t)));
  }
  return scn;
}

// Calls f with the scene's problem in T, whose torque is a formula of time (the only kind this
// benchmark instantiates the integrator for).
template <class T, class F>
auto with_sciml_problem(const eulervop::scene::scene& scn, F&& f) {
  using time_problem = eulervop::euler_problem<T, eulervop::time_torque<T>>;
  using R = std::invoke_result_t<F&, const time_problem&>;
  return eulervop::scene::with_problem<T>(scn, [&](const auto& problem) -> R {
    if constexpr (std::is_same_v<std::decay_t<decltype(problem)>, time_problem>)
      return f(problem);
    else
      throw std::runtime_error("the SciML scene's torque is not a formula of time");
  });
}

// ---- truth ---------------------------------------------------------------------------------
std::string truth_header(problem_id problem, int tau_end) {
  if (problem == problem_id::sciml)
    return "# eulervop bench_reference truth v1: integrate_reference<mpfr_real> mpfr:320 default settings;"
           " scene sciml-rigid-body-100: y' = (-2 y2 y3, 1.25 y1 y3, -0.5 y1 y2 + 0.25*sin(t)^2)"
           " y0=(1,0,0.9) t=i/16 i=0.." +
           std::to_string(sample_count(tau_end) - 1);
  return "# eulervop bench_reference truth v1: integrate_reference<mpfr_real> mpfr:320 default settings;"
         " G=(1,1,1) Omega0=(0.5,0,1) tau=i/16 i=0.." +
         std::to_string(sample_count(tau_end) - 1);
}

// The truth's samples: the problem integrated in T (mpfr:320), its dense output at the samples.
template <class T, class Problem>
std::vector<text3> truth_samples(const Problem& problem, int tau_end, eulervop::picard_stats& st) {
  const auto traj = eulervop::integrate_reference<T>(problem, T(tau_end), {}, progress_printer("truth mpfr:320"), &st);
  std::vector<text3> rows;
  for (const T& tau : sample_times<T>(tau_end)) {
    const auto v = traj(tau);
    rows.push_back({eulervop::to_text(v[0]), eulervop::to_text(v[1]), eulervop::to_text(v[2])});
  }
  return rows;
}

std::vector<text3> load_or_make_truth(problem_id problem, const eulervop::scene::scene* scn, int tau_end,
                                      bool recompute) {
  const std::string key = problem == problem_id::sciml ? "sciml_" : "";
  const auto path = executable_dir() / ("bench_reference_truth_320_" + key + std::to_string(tau_end) + ".txt");
  const std::string header = truth_header(problem, tau_end);
  if (!recompute) {
    std::ifstream in(path);
    std::string line;
    if (in && std::getline(in, line) && line == header) {
      std::vector<text3> rows;
      text3 r;
      while (in >> r[0] >> r[1] >> r[2]) rows.push_back(r);
      if (static_cast<int>(rows.size()) == sample_count(tau_end)) {
        std::fprintf(stderr, "truth: loaded %s\n", path.c_str());
        return rows;
      }
    }
  }
  std::fprintf(stderr, "truth: computing mpfr:320 to tau = %d (cached in %s)\n", tau_end, path.c_str());
  eulervop::mpfr_precision_scope scope(320);
  using T = eulervop::mpfr_real;
  const auto t0 = clock_type::now();
  eulervop::picard_stats st;
  const std::vector<text3> rows =
      problem == problem_id::sciml
          ? with_sciml_problem<T>(*scn, [&](const auto& p) { return truth_samples<T>(p, tau_end, st); })
          : truth_samples<T>(paper_problem<T>(), tau_end, st);
  std::fprintf(stderr, "truth: %.1f s, %zu segments, degree %u\n", seconds_since(t0), st.segments, st.degree);
  const auto tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << header << '\n';
    for (const auto& r : rows) out << r[0] << ' ' << r[1] << ' ' << r[2] << '\n';
  }
  std::filesystem::rename(tmp, path);
  return rows;
}

// Max and final Eq. 20 error of `rows` against `truth`, in MPFR at 400 bits.
struct error_result {
  double max_error = 0;
  double final_error = 0;
};

error_result eq20_error(const std::vector<text3>& rows, const std::vector<text3>& truth) {
  eulervop::mpfr_precision_scope scope(400);
  using M = eulervop::mpfr_real;
  error_result out;
  M worst = 0, e2 = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    M s = 0;
    for (int i = 0; i < 3; ++i) {
      M d = M(rows[k][i]) - M(truth[k][i]);
      s += d * d;
    }
    if (s > worst) worst = s;
    e2 = s;
  }
  out.max_error = static_cast<double>(sqrt(worst));
  out.final_error = static_cast<double>(sqrt(e2));
  return out;
}

// ---- rows ----------------------------------------------------------------------------------
struct row {
  std::string method, precision, tolerance;
  bool done = false;
  std::string status;  // why a row did not finish
  double seconds = 0;
  error_result err;
  std::string notes;
};

void print_row_progress(const row& r) {
  if (r.done)
    std::fprintf(stderr, "  -> %-32s %-9s tol %-8s %9.3f s  max err %.2e  %s\n", r.method.c_str(),
                 r.precision.c_str(), r.tolerance.c_str(), r.seconds, r.err.max_error, r.notes.c_str());
  else
    std::fprintf(stderr, "  -> %-32s %-9s tol %-8s %s\n", r.method.c_str(), r.precision.c_str(),
                 r.tolerance.c_str(), r.status.c_str());
}

// A completed row: its best time and the error of its samples (converted to text, untimed).
template <class State>
void finish_row(row& r, const std::vector<State>& values, double best, const std::vector<text3>& truth) {
  std::vector<text3> rows;
  for (const auto& v : values) rows.push_back({text_of(v[0]), text_of(v[1]), text_of(v[2])});
  r.done = true;
  r.seconds = best;
  r.err = eq20_error(rows, truth);
}

std::string tol_text(double tol) {
  if (tol <= 0) return "default";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0e", tol);
  return buf;
}

// Our integrator in T: integrate, then evaluate the dense output at the sample times.
template <class T, class Problem>
row run_ours(const std::string& precision_name, double tol, int tau_end, const options& opt,
             const std::vector<text3>& truth, const Problem& problem) {
  row r;
  r.method = "ours Chebyshev-Picard";
  r.precision = precision_name;
  eulervop::picard_settings settings;
  settings.tolerance = tol;
  r.tolerance = tol_text(tol);
  std::fprintf(stderr, "row: %s %s tol %s\n", r.method.c_str(), r.precision.c_str(), r.tolerance.c_str());
  const auto times = sample_times<T>(tau_end);
  std::vector<eulervop::vec3<T>> values;
  eulervop::picard_stats st;
  double best = std::numeric_limits<double>::infinity();
  for (int rep = 0; rep < opt.repeat; ++rep) {
    values.clear();
    const auto t0 = clock_type::now();
    const auto traj = eulervop::integrate_reference<T>(problem, T(tau_end), settings,
                                                       progress_printer("ours " + precision_name), &st);
    values.reserve(times.size());
    for (const T& tau : times) values.push_back(traj(tau));
    best = std::min(best, seconds_since(t0));
  }
  finish_row(r, values, best, truth);
  r.notes = "N=" + std::to_string(st.degree) + " segments=" + std::to_string(st.segments) +
            " rejected=" + std::to_string(st.rejected) + " wide_residuals=" + std::to_string(st.wide_residuals) +
            " residual_updates=" + std::to_string(st.residual_updates) +
            " double_sweeps=" + std::to_string(st.double_sweeps);
  print_row_progress(r);
  return r;
}

// Thrown by the observer when a Boost.Odeint row runs past its time budget.
struct out_of_time {
  double tau;
};

template <class V>
struct euler_system {
  std::array<V, 3> G;
  void operator()(const std::array<V, 3>& x, std::array<V, 3>& dxdt, const V& /*t*/) const {
    eulervop::euler_rhs(x, G, dxdt);
  }
};

// The paper scene for the peer: Eq. 5 with G = (1, 1, 1), Omega(0) = (0.5, 0, 1).
template <class V>
euler_system<V> paper_system() {
  return {{V(1), V(1), V(1)}};
}
template <class V>
std::array<V, 3> paper_initial() {
  return {V(1) / V(2), V(0), V(1)};
}

// A Boost.Odeint controlled stepper run with integrate_times over the sample times.
// make_stepper(tol) returns a fresh stepper; the sweep abandons a run after `cap` seconds.
template <class V, class MakeStepper, class System>
row run_odeint(const std::string& method, const std::string& precision_name, double tol, int tau_end,
               const options& opt, const std::vector<text3>& truth, MakeStepper make_stepper, double cap,
               const System& sys, const std::array<V, 3>& x0) {
  row r;
  r.method = method;
  r.precision = precision_name;
  r.tolerance = tol_text(tol);
  std::fprintf(stderr, "row: %s %s tol %s\n", r.method.c_str(), r.precision.c_str(), r.tolerance.c_str());
  using state = std::array<V, 3>;
  const auto times = sample_times<V>(tau_end);
  std::vector<state> values;
  double best = std::numeric_limits<double>::infinity();
  std::size_t steps_observed = 0;
  for (int rep = 0; rep < opt.repeat; ++rep) {
    values.clear();
    values.reserve(times.size());
    state x = x0;
    auto stepper = make_stepper(V(tol));
    const auto t0 = clock_type::now();
    double last_report = 0;
    try {
      steps_observed = odeint::integrate_times(
          stepper, sys, x, times.begin(), times.end(), V(1) / V(100),
          [&](const state& s, const V& t) {
            values.push_back(s);
            const double el = seconds_since(t0);
            if (el - last_report >= 2.0) {
              std::fprintf(stderr, "  %s %s: tau = %.2f after %.0f s\n", method.c_str(),
                           precision_name.c_str(), static_cast<double>(t), el);
              last_report = el;
            }
            if (el > cap) throw out_of_time{static_cast<double>(t)};
          });
    } catch (const out_of_time& e) {
      char buf[128];
      std::snprintf(buf, sizeof buf, "skipped (> %.0f s; abandoned at tau = %.2f)", cap, e.tau);
      r.status = buf;
      r.seconds = seconds_since(t0);
      print_row_progress(r);
      return r;
    } catch (const std::exception& e) {
      r.status = std::string("failed: ") + e.what();
      print_row_progress(r);
      return r;
    }
    best = std::min(best, seconds_since(t0));
  }
  finish_row(r, values, best, truth);
  r.notes = "steps=" + std::to_string(steps_observed);
  print_row_progress(r);
  return r;
}

template <class V>
auto rkf78_maker() {
  return [](const V& tol) {
    return odeint::make_controlled(tol, tol, odeint::runge_kutta_fehlberg78<std::array<V, 3>, V>());
  };
}

void print_table(problem_id problem, const std::vector<row>& rows, const row* baseline, int tau_end, int samples) {
  if (problem == problem_id::sciml) {
    std::printf("\nReference generation, SciML rigid body (scene sciml-rigid-body-100: y1' = -2 y2 y3, "
                "y2' = 1.25 y1 y3, y3' = -0.5 y1 y2 + 0.25 sin^2 t, y(0) = (1, 0, 0.9)), t in [0, %d], "
                "%d samples (t = i/16)\n",
                tau_end, samples);
    std::printf("Error: max over the samples of sqrt(sum_i (y_i - y_i^truth)^2) against our mpfr:320 reference on "
                "the same problem, computed in MPFR 400 bits.\n");
  } else {
    std::printf("\nReference generation, paper scene (G = (1,1,1), Omega(0) = (0.5,0,1)), tau in [0, %d], "
                "%d samples (tau = i/16)\n",
                tau_end, samples);
    std::printf("Error: max over the samples of Eq. 20 against our mpfr:320 reference, computed in MPFR 400 bits.\n");
  }
  if (baseline)
    std::printf("Speed ratio: wall time of Boost.Odeint bulirsch_stoer<float128> tol 1e-28 (%.3f s) / row time.\n",
                baseline->seconds);
  std::printf("\n| method | precision | tol | wall s | max error | final error | speed vs BS quad 1e-28 | notes |\n");
  std::printf("|---|---|---|---:|---:|---:|---:|---|\n");
  for (const auto& r : rows) {
    if (!r.done) {
      std::printf("| %s | %s | %s | %s | - | - | - | |\n", r.method.c_str(), r.precision.c_str(),
                  r.tolerance.c_str(), r.status.c_str());
      continue;
    }
    char ratio[32] = "-";
    if (baseline) std::snprintf(ratio, sizeof ratio, "%.2fx", baseline->seconds / r.seconds);
    std::printf("| %s | %s | %s | %.3f | %.2e | %.2e | %s | %s |\n", r.method.c_str(), r.precision.c_str(),
                r.tolerance.c_str(), r.seconds, r.err.max_error, r.err.final_error, ratio, r.notes.c_str());
  }
  std::fflush(stdout);
}

int usage(const char* argv0) {
  std::fprintf(stderr,
               "usage: %s [--problem paper|sciml] [--quick | --targets] [--repeat N] [--no-mpfr] [--mpfr-cap SECONDS]"
               " [--recompute-truth]\n",
               argv0);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  options opt;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--problem" && a + 1 < argc) {
      const std::string name = argv[++a];
      if (name == "paper") opt.problem = problem_id::paper;
      else if (name == "sciml") opt.problem = problem_id::sciml;
      else return usage(argv[0]);
    } else if (arg == "--quick") opt.quick = true;
    else if (arg == "--targets") opt.targets = true;
    else if (arg == "--no-mpfr") opt.no_mpfr = true;
    else if (arg == "--recompute-truth") opt.recompute_truth = true;
    else if (arg == "--repeat" && a + 1 < argc) {
      opt.repeat = std::atoi(argv[++a]);
      if (opt.repeat < 1) return usage(argv[0]);
    } else if (arg == "--mpfr-cap" && a + 1 < argc) {
      opt.mpfr_cap = std::atof(argv[++a]);
      if (!(opt.mpfr_cap > 0)) return usage(argv[0]);
    } else {
      return usage(argv[0]);
    }
  }
  const bool sciml = opt.problem == problem_id::sciml;
  const int tau_end = opt.quick ? 20 : sciml ? 100 : 136;
  try {
    std::optional<eulervop::scene::scene> scn;
    if (sciml) scn = load_sciml_scene();
    const auto truth = load_or_make_truth(opt.problem, scn ? &*scn : nullptr, tau_end, opt.recompute_truth);
    std::vector<row> rows;
    if (sciml) {
      using Q = eulervop::quad;
      const std::vector<double> ours_tols = opt.quick     ? std::vector<double>{1e-20, 1e-24}
                                            : opt.targets ? std::vector<double>{0}
                                                          : std::vector<double>{1e-24, 1e-28, 0};
      const std::vector<double> peer_tols = opt.quick     ? std::vector<double>{1e-20, 1e-24}
                                            : opt.targets ? std::vector<double>{1e-28}
                                                          : std::vector<double>{1e-20, 1e-24, 1e-28, 1e-32};
      with_sciml_problem<Q>(*scn, [&](const auto& problem) {
        for (double tol : ours_tols) rows.push_back(run_ours<Q>("quad", tol, tau_end, opt, truth, problem));
      });
      const auto x0 = eulervop::scene::initial_state_of<Q>(*scn);
      std::optional<std::size_t> baseline_index;
      for (double tol : peer_tols) {
        if (tol == 1e-28) baseline_index = rows.size();
        rows.push_back(run_odeint<Q>("odeint bulirsch_stoer", "float128", tol, tau_end, opt, truth,
                                     bulirsch_stoer_maker<Q>(), 1e9, sciml_system<Q>{}, {x0[0], x0[1], x0[2]}));
      }
      const row* baseline = baseline_index && rows[*baseline_index].done ? &rows[*baseline_index] : nullptr;
      print_table(opt.problem, rows, baseline, tau_end, sample_count(tau_end));
      return 0;
    }
    const std::vector<double> quad_tols = opt.quick     ? std::vector<double>{1e-20, 1e-24}
                                          : opt.targets ? std::vector<double>{0}
                                                        : std::vector<double>{1e-20, 1e-24, 1e-28, 1e-30, 0};
    const std::vector<double> odeint_tols = opt.quick     ? std::vector<double>{1e-20, 1e-24}
                                            : opt.targets ? std::vector<double>{1e-28}
                                                          : std::vector<double>{1e-20, 1e-24, 1e-28, 1e-32};

    for (double tol : quad_tols)
      rows.push_back(run_ours<eulervop::quad>("quad", tol, tau_end, opt, truth, paper_problem<eulervop::quad>()));
    std::size_t baseline_index = rows.size();
    bool have_baseline = false;
    for (double tol : odeint_tols) {
      if (tol == 1e-28) {
        baseline_index = rows.size();
        have_baseline = true;
      }
      rows.push_back(run_odeint<eulervop::quad>("odeint bulirsch_stoer", "float128", tol, tau_end, opt, truth,
                                                bulirsch_stoer_maker<eulervop::quad>(), 1e9, paper_system<eulervop::quad>(),
                                                paper_initial<eulervop::quad>()));
    }
    if (!opt.targets)
      for (double tol : odeint_tols)
        rows.push_back(run_odeint<eulervop::quad>("odeint rk_fehlberg78 controlled", "float128", tol, tau_end, opt,
                                                  truth, rkf78_maker<eulervop::quad>(), 60.0,
                                                  paper_system<eulervop::quad>(), paper_initial<eulervop::quad>()));
    if (!opt.quick && !opt.no_mpfr) {
      {
        eulervop::mpfr_precision_scope scope(256);
        for (double tol : opt.targets ? std::vector<double>{1e-60} : std::vector<double>{1e-40, 1e-50, 1e-60, 0.0})
          rows.push_back(run_ours<eulervop::mpfr_real>("mpfr:256", tol, tau_end, opt, truth,
                                                       paper_problem<eulervop::mpfr_real>()));
      }
      if (!opt.targets) {
        // The peer at 256 bits (257 effective, like ours: the same digits10 setting).
        odeint_mpfr::thread_default_precision(eulervop::mpfr_digits10_for_bits(256));
        for (double tol : {1e-40, 1e-50, 1e-60}) {
          rows.push_back(run_odeint<odeint_mpfr>("odeint bulirsch_stoer", "mpfr:256", tol, tau_end, opt, truth,
                                                 bulirsch_stoer_maker<odeint_mpfr>(), opt.mpfr_cap,
                                                 paper_system<odeint_mpfr>(), paper_initial<odeint_mpfr>()));
          if (!rows.back().done || rows.back().seconds > 120) break;
        }
      }
    }
    const row* baseline = have_baseline && rows[baseline_index].done ? &rows[baseline_index] : nullptr;
    print_table(opt.problem, rows, baseline, tau_end, sample_count(tau_end));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_reference: %s\n", e.what());
    return 3;
  }
  return 0;
}

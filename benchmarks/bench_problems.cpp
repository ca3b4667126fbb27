// Every shipped test problem: the wall time and error of our quad reference and of the
// Boost.Odeint peer on the same equations (docs/benchmarks.md, "Every shipped problem"). A
// benchmark, not a timed test: speed is measured here and never asserted by the test suite.
//
// Scenes: data/scenes/problems/*.toml, data/scenes/paper-fig1.toml,
// data/scenes/spacecraft-physical.toml and data/scenes/attitude/*.toml (found from the working directory or from this source
// file's location), or the scene files named on the command line.
//
// Three sides integrate the problem the scene compiles in quad (scene::with_problem): its
// equations (Eq. 5, Eq. 1 in the direct form, or the coefficient form), its torque (constant, of
// time, of time and state, piecewise) and its variables (tau and Omega for a physical scene,
// Eqs. 2-4). A scene's attitude q is ignored where the torque does not read it: only the rates
// are integrated. Where it does (data/scenes/attitude/), both integrate the 7 states of
// scene::to_coupled_problem, the rates and q.
//   - Ours: integrate_reference_samples<quad> (integrate_coupled_samples for 7 states) at the
//     scene's reference settings (none of the shipped scenes sets any: tolerance = epsilon of
//     quad), sampling as the run passes the samples, as `eulervop reference` does.
//   - Peer: Boost.Odeint bulirsch_stoer<std::array<float128, D>>, abs = rel = 1e-28 (the peer of
//     bench_reference), integrate_times over the samples, with the compiled problem's
//     rhs(t, y, dy) in float128 as its system. It stops exactly at each breakpoint of a
//     piecewise torque and restarts there with a fresh stepper and the next interval's formulas
//     pinned, as our integrator ends a segment there (reference/chebyshev_picard.hpp,
//     set_breakpoints): neither side steps across a change of formula.
//   - Taylor peer (taylor_peer.hpp): the method of heyoka's taylor_adaptive and TIDES, at
//     tol = epsilon of quad, for the problems whose torque reads no state and has no pieces in the
//     normalized or coefficient form (the paper scene, the SciML rigid body, B5): "-" elsewhere.
//     Before timing, its first Taylor coefficient is checked against the compiled problem's rhs.
// Samples: the scene's own (scene::sample_times_of), in quad.
// Truth: ours in mpfr:320 at its default settings (tolerance = epsilon at 320 bits, about 1e-96)
// on the scene compiled at 320 bits, evaluated at the quad sample times converted exactly;
// cached next to this executable as bench_problems_truth_320_<scene>.txt, keyed by a header line
// with a hash of the scene's text. --recompute-truth forces a new computation.
// Error: at each sample |y - y_truth|_2 / max(1, |y_truth|_2) in the integrator's variables
// (relative where the state is large, absolute where it is small), computed in MPFR at 400 bits;
// the table gives its maximum over the samples and its value at the last sample.
// Time: in-process wall time (std::chrono::steady_clock) of the integration and its samples
// alone, the median of --repeat N runs (default 3); ours and the peer alternate in every repeat,
// so both see the same machine. A peer run longer than --cap S (default 60) is abandoned and the
// row says so.
// Progress goes to standard error; the table to standard output.
#include "reference_bench_support.hpp"
#include "taylor_peer.hpp"

#include <eulervop/core/scalar.hpp>
#include <eulervop/model/torque.hpp>
#include <eulervop/reference/integrate.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <boost/numeric/odeint.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace odeint = boost::numeric::odeint;
namespace scene = eulervop::scene;
using eulervop::bench::clock_type;
using eulervop::bench::seconds_since;
using Q = eulervop::quad;
using M = eulervop::mpfr_real;
using text_row = std::vector<std::string>;  // one sample of the truth, every component

constexpr double peer_tolerance = 1e-28;

struct options {
  int repeat = 3;
  double cap = 60;  // seconds for one peer run
  bool recompute_truth = false;
  std::string only;  // ours, odeint or taylor: that side alone, once (run_side)
  std::vector<fs::path> scenes;
};

// ---- scenes --------------------------------------------------------------------------------
fs::path data_path(const fs::path& rel) {
  if (fs::exists(rel)) return rel;
  return fs::path(__FILE__).parent_path().parent_path() / rel;
}

// The shipped problems (by name: sciml-rigid-body before sciml-rigid-body-100), then the paper scene and the physical spacecraft.
std::vector<fs::path> shipped_scenes() {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(data_path("data/scenes/problems")))
    if (entry.path().extension() == ".toml") out.push_back(entry.path());
  std::sort(out.begin(), out.end(), [](const fs::path& a, const fs::path& b) { return a.stem() < b.stem(); });
  out.push_back(data_path("data/scenes/paper-fig1.toml"));
  out.push_back(data_path("data/scenes/spacecraft-physical.toml"));
  std::vector<fs::path> attitude;
  for (const auto& entry : fs::directory_iterator(data_path("data/scenes/attitude")))
    if (entry.path().extension() == ".toml") attitude.push_back(entry.path());
  std::sort(attitude.begin(), attitude.end());
  out.insert(out.end(), attitude.begin(), attitude.end());
  return out;
}

std::string torque_text(const scene::scene& scn) {
  if (scn.couples_attitude()) return scn.gravity_gradient ? "of the attitude (gravity gradient), 7 states"
                                                         : "of the attitude (formulas), 7 states";
  if (!scn.has_torque_law()) return scn.torque ? "constant" : "none";
  std::string s = scn.torque_law->uses_state() ? "of t and state" : "of t";
  if (!scn.torque_law->pieces.empty()) s += ", piecewise";
  return s;
}

// ---- exact conversion and the error --------------------------------------------------------
// q exactly in MPFR (at 320 bits or more): binary128's 113 bits split into three doubles, each
// difference exact in quad and the remainder after two doubles short enough for the third.
M exactly(const Q& q) {
  const double hi = static_cast<double>(q);
  const Q r = q - Q(hi);
  const double mid = static_cast<double>(r);
  const double lo = static_cast<double>(r - Q(mid));
  return (M(hi) + M(mid)) + M(lo);
}

struct error_result {
  double max_error = 0;
  double final_error = 0;
};

// The largest and the last |y - y_truth|_2 / max(1, |y_truth|_2) over the samples, in MPFR 400.
template <std::size_t D>
error_result errors(const std::vector<std::array<Q, D>>& values, const std::vector<text_row>& truth) {
  using std::sqrt;
  eulervop::mpfr_precision_scope scope(400);
  error_result out;
  M worst = 0, last = 0;
  for (std::size_t k = 0; k < values.size(); ++k) {
    M d2 = 0, n2 = 0;
    for (std::size_t i = 0; i < D; ++i) {
      const M yt(truth[k][i]);
      const M d = exactly(values[k][i]) - yt;
      d2 += d * d;
      n2 += yt * yt;
    }
    last = n2 > 1 ? M(sqrt(d2 / n2)) : M(sqrt(d2));
    if (last > worst) worst = last;
  }
  out.max_error = static_cast<double>(worst);
  out.final_error = static_cast<double>(last);
  return out;
}

// ---- truth ---------------------------------------------------------------------------------
// FNV-1a, 64 bits: a stable key of the scene's text for the cache.
std::string text_hash(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (const unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::optional<std::vector<text_row>> read_truth(const fs::path& path, const std::string& header, std::size_t n,
                                                std::size_t dimension) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line) || line != header) return std::nullopt;
  std::vector<text_row> rows;
  for (text_row r(dimension); in >> r[0];) {
    for (std::size_t i = 1; i < dimension; ++i) in >> r[i];
    if (in) rows.push_back(r);
  }
  if (rows.size() != n) return std::nullopt;
  return rows;
}

template <std::size_t D>
text_row text_of(const std::array<M, D>& y) {
  text_row r;
  for (const M& v : y) r.push_back(eulervop::to_text(v));
  return r;
}

// Ours in mpfr:320, default settings, at the quad sample times converted exactly.
std::vector<text_row> compute_truth(const scene::scene& scn, const std::vector<Q>& taus_q) {
  eulervop::mpfr_precision_scope scope(320);
  std::vector<M> taus;
  for (const Q& t : taus_q) taus.push_back(exactly(t));
  // A physical scene's span end in quad may round above the one at 320 bits.
  const M tau_end = std::max(scene::tau_end_of<M>(scn), taus.back());
  std::vector<text_row> rows(taus.size());
  eulervop::picard_stats st;
  const auto t0 = clock_type::now();
  const auto progress = eulervop::bench::progress_printer("truth " + scn.name);
  if (scn.couples_attitude())
    eulervop::integrate_coupled_samples<M>(
        scene::to_coupled_problem<M>(scn), tau_end, taus,
        [&](std::size_t i, const M&, const std::array<M, 7>& y) { rows[i] = text_of(y); }, {}, progress, &st);
  else
    scene::with_problem<M>(scn, [&](const auto& problem) {
      eulervop::integrate_reference_samples<M>(
          problem, tau_end, taus, [&](std::size_t i, const M&, const eulervop::vec3<M>& y) { rows[i] = text_of(y); },
          {}, progress, &st);
    });
  std::fprintf(stderr, "truth %s: %.1f s, %zu segments, degree %u\n", scn.name.c_str(), seconds_since(t0),
               st.segments, st.degree);
  return rows;
}

std::vector<text_row> load_or_make_truth(const scene::scene& scn, const std::vector<Q>& taus, bool recompute) {
  const std::size_t dimension = scn.couples_attitude() ? 7 : 3;
  const fs::path path = eulervop::bench::executable_dir() / ("bench_problems_truth_320_" + scn.name + ".txt");
  const std::string header = "# eulervop bench_problems truth v1: integrate_reference_samples<mpfr_real> mpfr:320"
                             " default settings; scene " + scn.name + " text fnv1a " + text_hash(scn.source_text) +
                             "; samples " + std::to_string(taus.size()) + " at the quad sample times";
  if (!recompute)
    if (auto rows = read_truth(path, header, taus.size(), dimension)) {
      std::fprintf(stderr, "truth %s: loaded %s\n", scn.name.c_str(), path.c_str());
      return *rows;
    }
  std::vector<text_row> rows = compute_truth(scn, taus);
  const std::string tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << header << '\n';
    for (const auto& r : rows) {
      for (std::size_t i = 0; i < r.size(); ++i) out << (i ? " " : "") << r[i];
      out << '\n';
    }
  }
  fs::rename(tmp, path);
  return rows;
}

// ---- the two sides -------------------------------------------------------------------------
eulervop::picard_settings settings_of(const scene::scene& scn) {
  eulervop::picard_settings s;
  if (scn.degree) s.degree = *scn.degree;
  if (scn.tolerance) s.tolerance = scn.tolerance->value;
  return s;
}

// One run of ours: returns its wall time; the samples land in `values`.
template <class Problem>
double run_ours(const Problem& problem, const Q& tau_end, const std::vector<Q>& taus,
                const eulervop::picard_settings& settings, std::vector<typename Problem::state_type>& values,
                eulervop::picard_stats& st) {
  using state = typename Problem::state_type;
  const auto t0 = clock_type::now();
  const auto take = [&](std::size_t i, const Q&, const state& y) { values[i] = y; };
  if constexpr (eulervop::is_coupled_problem_v<Problem>)
    eulervop::integrate_coupled_samples<Q>(problem, tau_end, taus, take, settings, {}, &st);
  else
    eulervop::integrate_reference_samples<Q>(problem, tau_end, taus, take, settings, {}, &st);
  return seconds_since(t0);
}

// Thrown by the peer's observer when a run passes its time budget.
struct out_of_time {
  double tau;
};

// The intervals between the torque's breakpoints inside (tau0, tau_end): tau0, b_1, ..., tau_end.
template <class Problem>
std::vector<Q> interval_bounds(const Problem& p, const Q& tau_end) {
  std::vector<Q> out = {p.initial_time()};
  if constexpr (eulervop::piecewise_torque<typename Problem::torque_type>)
    for (const Q& b : p.torque.breakpoints())
      if (b > p.initial_time() && b < tau_end) out.push_back(b);
  out.push_back(tau_end);
  return out;
}

// One run of the peer: returns its wall time and adds its steps to `steps`; the samples land in
// `values`. Each interval between breakpoints is one integrate_times call from its start, over
// the samples inside, to its end, with that interval's formulas pinned (a step that ends on the
// breakpoint sees the formulas of its own side, as in our integrator).
template <class Problem>
double run_peer(const Problem& problem, const Q& tau_end, const std::vector<Q>& taus, double cap,
                std::vector<typename Problem::state_type>& values, std::size_t& steps) {
  using state = typename Problem::state_type;
  const Problem p = problem;  // pinned below: the peer's own copy
  const auto system = [&p](const state& y, state& dy, const Q& t) { p.rhs(t, y, dy); };
  const std::vector<Q> bounds = interval_bounds(p, std::max(tau_end, taus.back()));
  state x = p.initial_state();
  std::size_t next = 0;  // the first sample not yet taken
  const auto t0 = clock_type::now();
  const auto observe = [&](const state& y, const Q& t) {
    while (next < taus.size() && taus[next] == t) values[next++] = y;
    if (seconds_since(t0) > cap) throw out_of_time{static_cast<double>(t)};
  };
  for (std::size_t k = 0; k + 1 < bounds.size(); ++k) {
    std::vector<Q> times = {bounds[k]};
    for (std::size_t i = next; i < taus.size() && taus[i] <= bounds[k + 1]; ++i)
      if (taus[i] > bounds[k]) times.push_back(taus[i]);
    if (times.back() != bounds[k + 1]) times.push_back(bounds[k + 1]);
    if constexpr (eulervop::piecewise_torque<typename Problem::torque_type>)
      p.torque.pin(p.torque.interval_at(bounds[k]));
    auto stepper = eulervop::bench::bulirsch_stoer_maker<Q, Problem::dimension>()(Q(peer_tolerance));
    steps += odeint::integrate_times(stepper, system, x, times.begin(), times.end(), Q(1) / Q(100), observe);
  }
  return seconds_since(t0);
}

// The Taylor peer's problem, where it applies: Eq. 1's coefficients, the initial state and the
// forcing as the scene writes it (its variables are the integrator's in these forms).
template <class Problem>
std::optional<eulervop::bench::taylor_problem<Q>> taylor_problem_of(const scene::scene& scn, const Problem& problem) {
  if constexpr (eulervop::is_coupled_problem_v<Problem>) {
    return std::nullopt;
  } else {
    if (scn.is_physical()) return std::nullopt;
    if (scn.has_torque_law() && (scn.torque_law->uses_state() || !scn.torque_law->pieces.empty())) return std::nullopt;
    eulervop::bench::taylor_problem<Q> tp;
    tp.a = problem.a;
    tp.t0 = problem.initial_time();
    tp.y0 = problem.initial_state();
    if (scn.has_torque_law())
      for (std::size_t i = 0; i < 3; ++i) tp.forcing[i] = scn.torque_law->base[i];
    else if (scn.torque)
      for (std::size_t i = 0; i < 3; ++i) tp.constant[i] = (*scn.torque)[i].template to_scalar<Q>();
    // The same equations: the first coefficient is the right-hand side at t0.
    eulervop::vec3<Q> dy;
    problem.rhs(tp.t0, tp.y0, dy);
    for (int i = 0; i < 3; ++i) {
      const auto [j, k] = Problem::quadratic_pair[static_cast<std::size_t>(i)];
      Q f = tp.forcing[i] ? eulervop::bench::time_tape<Q>(*tp.forcing[i], 1).at(tp.t0)[0] : tp.constant[i];
      const Q d = tp.a[i] * tp.y0[j] * tp.y0[k] + f - dy[i];
      if (abs(d) > 1e-30 * (1 + abs(dy[i]))) throw std::runtime_error("taylor peer: its equations differ from the scene's");
    }
    return tp;
  }
}

// One run of the Taylor peer: returns its wall time and its step count.
double run_taylor(const eulervop::bench::taylor_problem<Q>& tp, const std::vector<Q>& taus,
                  std::vector<eulervop::vec3<Q>>& values, eulervop::bench::taylor_stats& st) {
  const auto t0 = clock_type::now();
  st = eulervop::bench::taylor_integrate<Q>(tp, std::numeric_limits<Q>::epsilon(), taus,
                                            [&](std::size_t i, const eulervop::vec3<Q>& y) { values[i] = y; });
  return seconds_since(t0);
}

// ---- rows ----------------------------------------------------------------------------------
struct side {
  bool done = false;
  std::string status;  // why it did not finish
  double seconds = 0;  // median
  error_result err;
  std::string notes;
};

struct row {
  std::string problem, torque, span;
  std::size_t samples = 0;
  side ours, peer, taylor;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

// Times both sides on one problem, alternating in each repeat, then measures their errors.
template <class Problem>
void time_both(const Problem& problem, const scene::scene& scn, const std::vector<Q>& taus,
               const std::vector<text_row>& truth, const options& opt, row& r) {
  const Q tau_end = scene::tau_end_of<Q>(scn);
  std::vector<typename Problem::state_type> ours_values(taus.size()), peer_values(taus.size());
  std::vector<double> ours_times, peer_times, taylor_times;
  eulervop::picard_stats st;
  std::size_t steps = 0;
  const auto tp = taylor_problem_of(scn, problem);
  std::vector<eulervop::vec3<Q>> taylor_values(taus.size());
  eulervop::bench::taylor_stats taylor_st;
  if (!tp) r.taylor.status = "-";
  for (int rep = 0; rep < opt.repeat; ++rep) {
    ours_times.push_back(run_ours(problem, tau_end, taus, settings_of(scn), ours_values, st));
    if (tp) taylor_times.push_back(run_taylor(*tp, taus, taylor_values, taylor_st));
    if (!r.peer.status.empty()) continue;
    try {
      steps = 0;
      peer_times.push_back(run_peer(problem, tau_end, taus, opt.cap, peer_values, steps));
    } catch (const out_of_time& e) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "skipped (> %.0f s; abandoned at tau = %.4g)", opt.cap, e.tau);
      r.peer.status = buf;
    } catch (const std::exception& e) {
      r.peer.status = std::string("failed: ") + e.what();
    }
  }
  r.ours = {true, "", median(ours_times), errors(ours_values, truth),
            "N=" + std::to_string(st.degree) + " segments=" + std::to_string(st.segments)};
  if (r.peer.status.empty())
    r.peer = {true, "", median(peer_times), errors(peer_values, truth),
              "steps=" + std::to_string(steps) + " intervals=" + std::to_string(interval_bounds(problem, tau_end).size() - 1)};
  if (tp)
    r.taylor = {true, "", median(taylor_times), errors(taylor_values, truth),
                "order=" + std::to_string(taylor_st.order) + " steps=" + std::to_string(taylor_st.steps)};
}

// --only SIDE: that side alone, once, without the truth or the table, so that a whole process
// can be timed (tools/time_vs_peer.sh): one line "SIDE SCENE SECONDS".
template <class Problem>
void run_side(const Problem& problem, const scene::scene& scn, const std::vector<Q>& taus, const options& opt) {
  const Q tau_end = scene::tau_end_of<Q>(scn);
  double seconds = 0;
  if (opt.only == "ours") {
    std::vector<typename Problem::state_type> values(taus.size());
    eulervop::picard_stats st;
    seconds = run_ours(problem, tau_end, taus, settings_of(scn), values, st);
  } else if (opt.only == "odeint") {
    std::vector<typename Problem::state_type> values(taus.size());
    std::size_t steps = 0;
    seconds = run_peer(problem, tau_end, taus, opt.cap, values, steps);
  } else {
    const auto tp = taylor_problem_of(scn, problem);
    if (!tp) throw std::runtime_error("the Taylor peer does not take scene " + scn.name);
    std::vector<eulervop::vec3<Q>> values(taus.size());
    eulervop::bench::taylor_stats st;
    seconds = run_taylor(*tp, taus, values, st);
  }
  std::printf("%s %s %.6f\n", opt.only.c_str(), scn.name.c_str(), seconds);
}

row run_scene(const fs::path& file, const options& opt) {
  const scene::scene scn = scene::load_scene_file(file);
  row r;
  r.problem = scn.name;
  r.torque = torque_text(scn);
  r.span = std::string(scn.time_name()) + " in [0, " + scn.span_end.text + "]";
  std::fprintf(stderr, "problem %s (%s)\n", scn.name.c_str(), file.c_str());
  try {
    const std::vector<Q> taus = scene::sample_times_of<Q>(scn).tau;
    r.samples = taus.size();
    const std::vector<text_row> truth = load_or_make_truth(scn, taus, opt.recompute_truth);
    if (scn.couples_attitude())
      time_both(scene::to_coupled_problem<Q>(scn), scn, taus, truth, opt, r);
    else
      scene::with_problem<Q>(scn, [&](const auto& problem) { time_both(problem, scn, taus, truth, opt, r); });
  } catch (const std::exception& e) {
    r.ours.status = std::string("failed: ") + e.what();
  }
  const auto show = [](const char* who, const side& s) {
    if (s.done)
      std::fprintf(stderr, "  -> %s %.4f s  max err %.2e  final err %.2e  %s\n", who, s.seconds, s.err.max_error,
                   s.err.final_error, s.notes.c_str());
    else
      std::fprintf(stderr, "  -> %s %s\n", who, s.status.c_str());
  };
  show("ours", r.ours);
  show("peer", r.peer);
  show("taylor", r.taylor);
  return r;
}

std::string cell_seconds(const side& s) {
  if (!s.done) return s.status.empty() ? "-" : s.status;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", s.seconds);
  return buf;
}
std::string cell_error(const side& s, double e) {
  if (!s.done) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2e", e);
  return buf;
}

void print_table(const std::vector<row>& rows, const options& opt) {
  std::printf("\nEvery shipped problem: ours (quad, default settings) against Boost.Odeint bulirsch_stoer<float128>, "
              "abs = rel = %.0e, on the equations each scene compiles, over the scene's samples.\n",
              peer_tolerance);
  std::printf("Error: |y - y_truth|_2 / max(1, |y_truth|_2) in the integrator's variables, max over the samples and "
              "at the last one, against ours in mpfr:320 (default settings), computed in MPFR 400 bits.\n");
  std::printf("Time: median of %d in-process runs of the integration and its samples, ours and the peer "
              "alternating; ratio = ours / peer.\n",
              opt.repeat);
  std::printf("Taylor: the Taylor-series peer (taylor_peer.hpp) at tol = epsilon of quad, where it applies.\n");
  std::printf("\n| problem | torque | span | samples | ours s | peer s | ours / peer | taylor s | ours / taylor |"
              " ours max err | peer max err | taylor max err | ours final err | peer final err | notes |\n");
  std::printf("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
  for (const row& r : rows) {
    char ratio[32] = "-", taylor_ratio[32] = "-";
    if (r.ours.done && r.peer.done) std::snprintf(ratio, sizeof ratio, "%.3f", r.ours.seconds / r.peer.seconds);
    if (r.ours.done && r.taylor.done)
      std::snprintf(taylor_ratio, sizeof taylor_ratio, "%.3f", r.ours.seconds / r.taylor.seconds);
    std::printf("| %s | %s | %s | %zu | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s; %s; %s |\n",
                r.problem.c_str(), r.torque.c_str(), r.span.c_str(), r.samples, cell_seconds(r.ours).c_str(),
                cell_seconds(r.peer).c_str(), ratio, cell_seconds(r.taylor).c_str(), taylor_ratio,
                cell_error(r.ours, r.ours.err.max_error).c_str(), cell_error(r.peer, r.peer.err.max_error).c_str(),
                cell_error(r.taylor, r.taylor.err.max_error).c_str(), cell_error(r.ours, r.ours.err.final_error).c_str(),
                cell_error(r.peer, r.peer.err.final_error).c_str(), r.ours.notes.c_str(), r.peer.notes.c_str(),
                r.taylor.notes.c_str());
  }
  std::fflush(stdout);
}

int usage(const char* argv0) {
  std::fprintf(stderr, "usage: %s [--repeat N] [--cap SECONDS] [--recompute-truth] [--only ours|odeint|taylor] [SCENE.toml ...]\n",
               argv0);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  options opt;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--repeat" && a + 1 < argc) {
      opt.repeat = std::atoi(argv[++a]);
      if (opt.repeat < 1) return usage(argv[0]);
    } else if (arg == "--cap" && a + 1 < argc) {
      opt.cap = std::atof(argv[++a]);
      if (!(opt.cap > 0)) return usage(argv[0]);
    } else if (arg == "--recompute-truth") {
      opt.recompute_truth = true;
    } else if (arg == "--only" && a + 1 < argc) {
      opt.only = argv[++a];
      if (opt.only != "ours" && opt.only != "odeint" && opt.only != "taylor") return usage(argv[0]);
    } else if (!arg.starts_with("--")) {
      opt.scenes.emplace_back(arg);
    } else {
      return usage(argv[0]);
    }
  }
  try {
    if (opt.scenes.empty()) opt.scenes = shipped_scenes();
    if (!opt.only.empty()) {
      for (const fs::path& file : opt.scenes) {
        const scene::scene scn = scene::load_scene_file(file);
        const std::vector<Q> taus = scene::sample_times_of<Q>(scn).tau;
        if (scn.couples_attitude())
          run_side(scene::to_coupled_problem<Q>(scn), scn, taus, opt);
        else
          scene::with_problem<Q>(scn, [&](const auto& problem) { run_side(problem, scn, taus, opt); });
      }
      return 0;
    }
    std::vector<row> rows;
    for (const fs::path& file : opt.scenes) rows.push_back(run_scene(file, opt));
    print_table(rows, opt);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_problems: %s\n", e.what());
    return 3;
  }
  return 0;
}

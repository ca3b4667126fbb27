#include "compute/work_precision_runs.hpp"

#include <eulervop/runs/comparison_run.hpp>
#include "compute/reference_compute.hpp"
#include "compute/scene_library.hpp"
#include "compute/task_pool.hpp"
#include "compute/with_scalar.hpp"

#include <eulervop/core/quaternion.hpp>
#include <eulervop/model/error_measure.hpp>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>

namespace eulervop::app {

namespace {

template <class Problem>
wp_result run_case(const wp_grid& g, const wp_case& c, const Problem& problem, int repeat) {
  wp_result out;
  std::optional<attitude_settings> attitude;
  if (g.scn.has_attitude()) attitude = attitude_settings{body_rates_of<double>(g.scn), attitude_of<double>(g.scn)};
  for (int k = 0; k < repeat; ++k) {
    run_result r;
    if (c.adaptive) {
      adaptive_run_settings s;
      s.tau_end = tau_end_of<double>(g.scn);
      s.atol = s.rtol = g.tols[c.rung].value;
      s.h_max = g.max_step.h;
      s.samples = g.samples;
      s.attitude = attitude;
      r = run_adaptive(c.form, c.method, problem, s);
    } else {
      const ladder_step& st = g.steps[c.rung];
      fixed_run_settings s{st.choice.h, st.choice.n_steps, st.sample_every};
      s.attitude = attitude;
      r = run_fixed(c.form, c.method, problem, s);
    }
    if (k == 0) {
      out.seconds = r.seconds;
      out.run = std::move(r);
    } else {
      out.seconds = std::min(out.seconds, r.seconds);
    }
  }
  return out;
}

// The case's runs on the grid's problem, which each task builds for itself (a torque given by
// formulas keeps scratch space for its evaluation: tasks run on several threads); a torque of the
// attitude as each stage's q shows it (with_run_problem).
wp_result run_case(const wp_grid& g, const wp_case& c, int repeat) {
  return with_run_problem(g.scn, [&](const auto& problem) { return run_case(g, c, problem, repeat); });
}

// Work for the scheduler's order only (longest first keeps the workers evenly loaded).
double estimated_cost(const wp_grid& g, const wp_case& c) {
  const double stages = static_cast<double>(rk::stage_count(c.method));
  const double per_eval = c.form == formulation::euler ? 1.0 : 10.0;  // the VOP right-hand sides cost more
  if (!c.adaptive) return static_cast<double>(g.steps[c.rung].choice.n_steps) * stages * per_eval;
  const double span = tau_end_of<double>(g.scn);
  return span / g.max_step.h * std::pow(g.tols[c.rung].value, -1.0 / (rk::declared_order(c.method) + 1)) * stages *
         per_eval;
}

// The time of sample i of a run, in T: n h exactly for a fixed step, tau_hi + tau_lo otherwise.
template <scalar T>
T sample_time(const wp_grid& g, const wp_case& c, const run_result& r, std::size_t i) {
  if (!c.adaptive) return tau_of_step<T>(r.sample_steps[i], g.steps[c.rung].choice.h);
  return T(r.sample_tau[i]) + T(r.sample_tau_lo[i]);
}

template <scalar T>
void measure(const wp_grid& g, const wp_case& c, const dense_trajectory<T>& ref, wp_result& out) {
  const run_result& r = out.run;
  if (r.diverged()) return;
  double worst = 0;
  std::optional<double> last;
  for (std::size_t i = 0; i < r.Omega.size(); ++i) {
    const double e = static_cast<double>(eq20_error(sample_dense(ref, sample_time<T>(g, c, r, i)), r.Omega[i]));
    if (!std::isfinite(e)) return;  // never a NaN as an error value
    worst = std::max(worst, e);
    last = e;
  }
  out.max_error = worst;
  out.final_error = last;
}

// The errors of every case of a grid with an attitude: its reference (the rates and q, as
// `report` integrates them) at all the runs' samples in increasing order, each sample's Eq. 20
// error and rotation angle recorded in its case. A run that diverged, or has a non-finite error,
// keeps none (never a NaN as an error value).
template <scalar T>
void measure_with_attitude(const wp_grid& g, const picard_settings& settings, wp_outcome& out) {
  struct sample {
    T tau;
    std::size_t ci, k;
  };
  std::vector<sample> all;
  for (std::size_t ci = 0; ci < g.cases.size(); ++ci) {
    const run_result& r = out.results[ci].run;
    if (r.diverged()) continue;
    for (std::size_t k = 0; k < r.Omega.size(); ++k) all.push_back({sample_time<T>(g, g.cases[ci], r, k), ci, k});
  }
  std::stable_sort(all.begin(), all.end(), [](const sample& a, const sample& b) { return a.tau < b.tau; });
  T tau_end = tau_end_of<T>(g.scn);
  if (!all.empty() && all.back().tau > tau_end) tau_end = all.back().tau;
  std::vector<T> taus;
  taus.reserve(all.size());
  for (const sample& s : all) taus.push_back(s.tau);
  std::vector<std::vector<double>> errors(g.cases.size()), angles(g.cases.size());
  for (std::size_t ci = 0; ci < g.cases.size(); ++ci) {
    errors[ci].assign(out.results[ci].run.Omega.size(), std::numeric_limits<double>::quiet_NaN());
    angles[ci] = errors[ci];
  }
  const reference_run ref = integrate_scene_attitude<T>(
      g.scn, tau_end, taus, settings, "", [&](std::size_t j, const vec3<T>& Om, const quaternion<T>& q) {
        const auto [tau, ci, k] = all[j];
        const run_result& r = out.results[ci].run;
        errors[ci][k] = static_cast<double>(eq20_error(Om, r.Omega[k]));
        const quaternion<double>& qr = r.q[k];
        angles[ci][k] = static_cast<double>(rotation_angle(q, quaternion<T>{T(qr.w), T(qr.x), T(qr.y), T(qr.z)}));
      });
  out.reference_seconds = ref.wall_seconds;
  out.reference_segments = ref.stats.segments;
  out.reference_tau_end = static_cast<double>(tau_end);
  for (std::size_t ci = 0; ci < g.cases.size(); ++ci) {
    wp_result& w = out.results[ci];
    if (w.run.diverged() || errors[ci].empty()) continue;
    const bool finite = std::all_of(errors[ci].begin(), errors[ci].end(), [](double e) { return std::isfinite(e); }) &&
                        std::all_of(angles[ci].begin(), angles[ci].end(), [](double a) { return std::isfinite(a); });
    if (!finite) continue;
    w.max_error = *std::max_element(errors[ci].begin(), errors[ci].end());
    w.final_error = errors[ci].back();
    w.max_attitude_error = *std::max_element(angles[ci].begin(), angles[ci].end());
    w.final_attitude_error = angles[ci].back();
  }
}

// The reference of one grid, to the end of its longest run.
template <scalar T>
dense_reference<T> grid_reference(const wp_grid& g, const picard_settings& settings, wp_outcome& out) {
  T tau_end = tau_end_of<T>(g.scn);
  for (const ladder_step& st : g.steps) {  // within the 1e-9 h slack of n_steps
    const T last = tau_of_step<T>(st.choice.n_steps, st.choice.h);
    if (last > tau_end) tau_end = last;
  }
  // The adaptive runs end at the span's end in double, which for a physical scene (t_end times
  // dtau/dt of Eq. 4, rounded) may lie past its value in T.
  if (!g.tols.empty() && T(tau_end_of<double>(g.scn)) > tau_end) tau_end = T(tau_end_of<double>(g.scn));
  dense_reference<T> ref = with_problem<T>(
      g.scn, [&](const auto& problem) { return integrate_dense<T>(problem, tau_end, settings, ""); });
  out.reference_seconds = ref.wall_seconds;
  out.reference_segments = ref.stats.segments;
  out.reference_tau_end = static_cast<double>(tau_end);
  return ref;
}

std::vector<wp_outcome> outcomes_for(const std::vector<wp_grid>& grids) {
  std::vector<wp_outcome> out(grids.size());
  for (std::size_t gi = 0; gi < grids.size(); ++gi) out[gi].results.resize(grids[gi].cases.size());
  return out;
}

// Every case is a task; errors after all of them, in the calling thread.
template <scalar T>
std::vector<wp_outcome> run_all(const std::vector<wp_grid>& grids, const eulervop::precision& p,
                                const picard_settings& settings, const wp_run_options& o) {
  std::vector<wp_outcome> out = outcomes_for(grids);
  std::vector<dense_reference<T>> refs(grids.size());

  // The references first (they are the longest), then every case, longest first.
  std::vector<std::function<void()>> tasks;
  for (std::size_t gi = 0; gi < grids.size(); ++gi)
    if (!grids[gi].scn.has_attitude())  // with one, the reference comes after the runs
      tasks.emplace_back([&, gi] {
        mpfr_scope_on_this_thread(p, [&] { refs[gi] = grid_reference<T>(grids[gi], settings, out[gi]); });
      });
  std::vector<std::pair<std::size_t, std::size_t>> order;
  for (std::size_t gi = 0; gi < grids.size(); ++gi)
    for (std::size_t ci = 0; ci < grids[gi].cases.size(); ++ci) order.emplace_back(gi, ci);
  std::stable_sort(order.begin(), order.end(), [&](const auto& a, const auto& b) {
    return estimated_cost(grids[a.first], grids[a.first].cases[a.second]) >
           estimated_cost(grids[b.first], grids[b.first].cases[b.second]);
  });
  for (const auto& [gi, ci] : order)
    tasks.emplace_back([&, gi = gi, ci = ci] {
      out[gi].results[ci] = run_case(grids[gi], grids[gi].cases[ci], o.repeat);
    });
  run_tasks(tasks, o.jobs, o.progress_label);

  // Eq. 20 in the calling thread (MPFR temporaries take its default precision).
  for (std::size_t gi = 0; gi < grids.size(); ++gi) {
    if (grids[gi].scn.has_attitude()) {
      mpfr_scope_on_this_thread(p, [&] { measure_with_attitude<T>(grids[gi], settings, out[gi]); });
      continue;
    }
    for (std::size_t ci = 0; ci < grids[gi].cases.size(); ++ci)
      measure<T>(grids[gi], grids[gi].cases[ci], refs[gi].trajectory, out[gi].results[ci]);
  }
  return out;
}

// One ladder: a formulation, a method and a kind (fixed or adaptive), its cases from loose to tight.
struct ladder {
  std::size_t grid;
  std::vector<std::size_t> cases;
  double cost = 0;
};

// Every grid's ladders, the costliest first.
std::vector<ladder> ladders_of(const std::vector<wp_grid>& grids) {
  std::vector<ladder> ladders;
  for (std::size_t gi = 0; gi < grids.size(); ++gi) {
    const wp_grid& g = grids[gi];
    for (std::size_t ci = 0; ci < g.cases.size(); ++ci) {
      const wp_case& c = g.cases[ci];
      bool same = !ladders.empty() && ladders.back().grid == gi;
      if (same) {
        const wp_case& prev = g.cases[ladders.back().cases.back()];
        same = prev.form == c.form && prev.method == c.method && prev.adaptive == c.adaptive;
      }
      if (!same) ladders.push_back({gi, {}, 0});
      ladders.back().cases.push_back(ci);
      ladders.back().cost += estimated_cost(g, c);
    }
  }
  std::stable_sort(ladders.begin(), ladders.end(), [](const ladder& a, const ladder& b) { return a.cost > b.cost; });
  return ladders;
}

// Runs a ladder's rungs from loose to tight, measuring each at once, and stops at the first
// that reaches o.stop_below: the rest are marked skipped.
template <scalar T>
void run_ladder(const wp_grid& g, const ladder& l, const dense_trajectory<T>& ref, const eulervop::precision& p, const wp_run_options& o,
                wp_outcome& out) {
  bool reached = false;
  for (std::size_t ci : l.cases) {
    wp_result& r = out.results[ci];
    if (reached) {
      r.skipped = true;
      r.run.form = g.cases[ci].form;
      r.run.method = g.cases[ci].method;
      continue;
    }
    r = run_case(g, g.cases[ci], o.repeat);
    mpfr_scope_on_this_thread(p, [&] { measure<T>(g, g.cases[ci], ref, r); });
    reached = r.max_error && *r.max_error <= *o.stop_below;
  }
}

// The grids' references as the ladder tasks wait for them: each is ready when its task ends,
// and the first failure of any is kept for every waiting ladder.
class reference_gate {
 public:
  explicit reference_gate(std::size_t n) : ready_(n, 0) {}

  template <class Compute>
  void run(std::size_t gi, Compute&& compute) {
    try {
      compute();
    } catch (...) {
      const std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
    {
      const std::lock_guard lock(mutex_);
      ready_[gi] = 1;
    }
    changed_.notify_all();
  }
  // Waits until reference gi is ready; rethrows the first failure of any reference.
  void wait(std::size_t gi) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return ready_[gi] != 0; });
    if (error_) std::rethrow_exception(error_);
  }
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<char> ready_;
  std::exception_ptr error_;
};

// Every ladder is a task that waits for its grid's reference and runs its rungs (run_ladder).
// The reference tasks are all taken before any ladder task, so a waiting ladder always waits for
// a reference that some thread is computing.
template <scalar T>
std::vector<wp_outcome> run_ladders(const std::vector<wp_grid>& grids, const eulervop::precision& p,
                                    const picard_settings& settings, const wp_run_options& o) {
  std::vector<wp_outcome> out = outcomes_for(grids);
  std::vector<dense_reference<T>> refs(grids.size());
  reference_gate gate(grids.size());
  std::vector<std::function<void()>> tasks;
  for (std::size_t gi = 0; gi < grids.size(); ++gi)
    tasks.emplace_back([&, gi] {
      gate.run(gi, [&] {
        mpfr_scope_on_this_thread(p, [&] { refs[gi] = grid_reference<T>(grids[gi], settings, out[gi]); });
      });
    });
  for (const ladder& l : ladders_of(grids))
    tasks.emplace_back([&, l] {
      gate.wait(l.grid);
      run_ladder<T>(grids[l.grid], l, refs[l.grid].trajectory, p, o, out[l.grid]);
    });
  run_tasks(tasks, o.jobs, o.progress_label);
  gate.rethrow();
  return out;
}

}  // namespace

std::vector<wp_outcome> run_grids(const std::vector<wp_grid>& grids, const eulervop::precision& p,
                                  const picard_settings& settings, const wp_run_options& options) {
  return with_scalar(p, [&](auto zero) {
    using T = decltype(zero);
    const bool attitude =
        std::any_of(grids.begin(), grids.end(), [](const wp_grid& g) { return g.scn.has_attitude(); });
    return options.stop_below && !attitude ? run_ladders<T>(grids, p, settings, options)
                                           : run_all<T>(grids, p, settings, options);
  });
}

}  // namespace eulervop::app

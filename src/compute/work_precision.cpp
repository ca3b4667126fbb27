#include "compute/work_precision.hpp"

#include "io/progress_line.hpp"
#include "compute/reference_compute.hpp"
#include "compute/scene_library.hpp"
#include "compute/scene_overrides.hpp"
#include "compute/with_scalar.hpp"

#include <eulervop/model/error_measure.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <thread>

namespace eulervop::app {

// ---- the grid -----------------------------------------------------------------------------------

void wp_grid::make_cases() {
  cases.clear();
  for (formulation f : forms)
    for (rk::method m : methods) {
      if (rk::is_fixed_step(m))
        for (std::size_t i = 0; i < steps.size(); ++i) cases.push_back({f, m, false, i});
      if (rk::is_adaptive(m))
        for (std::size_t i = 0; i < tols.size(); ++i) cases.push_back({f, m, true, i});
    }
}

std::string wp_grid::rung_text(const wp_case& c) const {
  return c.adaptive ? fmt::format("tol {}", tols[c.rung].text) : steps[c.rung].text;
}

std::string wp_grid::configuration(const wp_case& c) const {
  return fmt::format("{} {}", rk::method_name(c.method), rung_text(c));
}

// ---- ladders --------------------------------------------------------------------------------------

std::vector<ladder_step> step_ladder(const scene& s, const std::vector<std::string>& texts, const std::string& flag,
                                     bool from_default, std::size_t samples) {
  std::vector<ladder_step> out;
  for (const std::string& text : texts) {
    if (std::any_of(out.begin(), out.end(), [&](const ladder_step& st) { return st.text == text; }))
      throw input_error(fmt::format("{}: step {} is listed twice", flag, text));
    ladder_step st;
    st.text = text;
    const std::string origin = from_default ? fmt::format("the default ladder's step {} (give {})", text, flag)
                                            : fmt::format("{} {}", flag, text);
    st.choice = resolve_step(s, parse_step_text(text, flag), origin);
    st.sample_every = std::max<std::size_t>(1, st.choice.n_steps / std::max<std::size_t>(samples, 1));
    out.push_back(std::move(st));
  }
  return out;
}

std::vector<ladder_tol> tol_ladder(const std::string& flag, const std::string& text) {
  std::vector<ladder_tol> out;
  for (const decimal& d : flag_ladder(flag, text)) {
    if (!(d.value < 1))
      throw input_error(fmt::format("{} {}: {} is not below 1 (the tolerances are relative and absolute errors per "
                                    "step)",
                                    flag, text, d.text));
    out.push_back({d.text, d.value});
  }
  return out;
}

fixed_step_choice max_step_of(const scene& s, const std::string& text, const std::string& origin) {
  return step_length(s, parse_step_text(text, origin), origin);
}

void resolve_max_step(wp_grid& g, const std::optional<std::string>& flag) {
  if (flag) {
    const fixed_step_choice c = max_step_of(g.scn, *flag, "--max-step " + *flag);
    g.h_max = c.h;
    g.h_max_rule = fmt::format("{} ({})", *flag, c.rule);
    return;
  }
  try {
    const fixed_step_choice c = max_step_of(g.scn, default_max_step, "the default --max-step " + default_max_step);
    g.h_max = c.h;
    g.h_max_rule = fmt::format("{} ({})", default_max_step, c.rule);
  } catch (const input_error&) {
    g.h_max = tau_end_of<double>(g.scn);
    g.h_max_rule = fmt::format("the span, {} (K is undefined at the initial state)", g.h_max);
  }
}

void check_methods_for_ladders(const std::vector<rk::method>& methods, bool steps, bool tols, const std::string& where) {
  for (rk::method m : methods) {
    if ((steps && rk::is_fixed_step(m)) || (tols && rk::is_adaptive(m))) continue;
    const std::string name(rk::method_name(m));
    if (!tols)
      throw input_error(fmt::format("{}: {} is run under error control and needs --tols (at a fixed step it is rk8)",
                                    where, name));
    throw input_error(fmt::format("{}: {} has no embedded error estimate, so it cannot run with --tols (adaptive "
                                  "methods: rkf45, dp45, dop853)",
                                  where, name));
  }
}

// ---- running ------------------------------------------------------------------------------------

namespace {

// Runs `tasks` on `jobs` threads (a shared queue, taken in the given order), drawing progress
// in the calling thread. The first exception of any task is rethrown after all threads have
// stopped; no new task starts after one has failed.
void run_tasks(const std::vector<std::function<void()>>& tasks, int jobs, const std::string& label) {
  const std::size_t n_threads = std::min<std::size_t>(static_cast<std::size_t>(std::max(jobs, 1)), tasks.size());
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::mutex mutex;
  std::condition_variable changed;
  std::size_t done = 0, stopped = 0;
  std::exception_ptr error;
  auto worker = [&] {
    while (!failed.load()) {
      const std::size_t i = next.fetch_add(1);
      if (i >= tasks.size()) break;
      std::exception_ptr e;
      try {
        tasks[i]();
      } catch (...) {
        e = std::current_exception();
        failed = true;
      }
      {
        const std::lock_guard lock(mutex);
        ++done;
        if (e && !error) error = e;
      }
      changed.notify_one();
    }
    {
      const std::lock_guard lock(mutex);
      ++stopped;
    }
    changed.notify_one();
  };
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < n_threads; ++t) threads.emplace_back(worker);
  {
    progress_line progress(label, static_cast<double>(tasks.size()), "task");
    std::unique_lock lock(mutex);
    while (stopped < n_threads) {
      changed.wait_for(lock, std::chrono::milliseconds(100));
      progress.update(static_cast<double>(done));
    }
  }
  for (std::thread& t : threads) t.join();
  if (error) std::rethrow_exception(error);
}

wp_result run_case(const wp_grid& g, const wp_case& c, const euler_problem<double>& problem, int repeat) {
  wp_result out;
  for (int k = 0; k < repeat; ++k) {
    run_result r;
    if (c.adaptive) {
      adaptive_run_settings s;
      s.tau_end = tau_end_of<double>(g.scn);
      s.atol = s.rtol = g.tols[c.rung].value;
      s.h_max = g.h_max;
      s.samples = g.samples;
      r = run_adaptive(c.form, c.method, problem, s);
    } else {
      const ladder_step& st = g.steps[c.rung];
      r = run_fixed(c.form, c.method, problem, fixed_run_settings{st.choice.h, st.choice.n_steps, st.sample_every});
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

// Work for the scheduler's order only (longest first keeps the workers evenly loaded).
double estimated_cost(const wp_grid& g, const wp_case& c) {
  const double stages = static_cast<double>(rk::stage_count(c.method));
  const double per_eval = c.form == formulation::euler ? 1.0 : 10.0;  // the VOP right-hand sides cost more
  if (!c.adaptive) return static_cast<double>(g.steps[c.rung].choice.n_steps) * stages * per_eval;
  const double span = tau_end_of<double>(g.scn);
  return span / g.h_max * std::pow(g.tols[c.rung].value, -1.0 / (rk::declared_order(c.method) + 1)) * stages * per_eval;
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

// The reference of one grid, to the end of its longest run.
template <scalar T>
dense_reference<T> grid_reference(const wp_grid& g, const picard_settings& settings, wp_outcome& out) {
  const euler_problem<T> problem = to_problem<T>(g.scn);
  T tau_end = tau_end_of<T>(g.scn);
  for (const ladder_step& st : g.steps) {  // within the 1e-9 h slack of n_steps
    const T last = tau_of_step<T>(st.choice.n_steps, st.choice.h);
    if (last > tau_end) tau_end = last;
  }
  dense_reference<T> ref = integrate_dense<T>(problem, tau_end, settings, "");
  out.reference_seconds = ref.wall_seconds;
  out.reference_segments = ref.stats.segments;
  out.reference_tau_end = static_cast<double>(tau_end);
  return ref;
}

// Every case is a task; errors after all of them, in the calling thread.
template <scalar T>
std::vector<wp_outcome> run_all(const std::vector<wp_grid>& grids, const eulervop::precision& p,
                                const picard_settings& settings, const wp_run_options& o) {
  std::vector<wp_outcome> out(grids.size());
  std::vector<dense_reference<T>> refs(grids.size());
  std::vector<euler_problem<double>> problems;
  for (const wp_grid& g : grids) problems.push_back(to_problem<double>(g.scn));

  // The references first (they are the longest), then every case, longest first.
  std::vector<std::function<void()>> tasks;
  for (std::size_t gi = 0; gi < grids.size(); ++gi) {
    out[gi].results.resize(grids[gi].cases.size());
    tasks.emplace_back([&, gi] {
      mpfr_scope_on_this_thread(p, [&] { refs[gi] = grid_reference<T>(grids[gi], settings, out[gi]); });
    });
  }
  std::vector<std::pair<std::size_t, std::size_t>> order;
  for (std::size_t gi = 0; gi < grids.size(); ++gi)
    for (std::size_t ci = 0; ci < grids[gi].cases.size(); ++ci) order.emplace_back(gi, ci);
  std::stable_sort(order.begin(), order.end(), [&](const auto& a, const auto& b) {
    return estimated_cost(grids[a.first], grids[a.first].cases[a.second]) >
           estimated_cost(grids[b.first], grids[b.first].cases[b.second]);
  });
  for (const auto& [gi, ci] : order)
    tasks.emplace_back([&, gi = gi, ci = ci] {
      out[gi].results[ci] = run_case(grids[gi], grids[gi].cases[ci], problems[gi], o.repeat);
    });
  run_tasks(tasks, o.jobs, o.progress_label);

  // Eq. 20 in the calling thread (MPFR temporaries take its default precision).
  for (std::size_t gi = 0; gi < grids.size(); ++gi)
    for (std::size_t ci = 0; ci < grids[gi].cases.size(); ++ci)
      measure<T>(grids[gi], grids[gi].cases[ci], refs[gi].trajectory, out[gi].results[ci]);
  return out;
}

// Every ladder is a task that waits for its grid's reference, runs its rungs from loose to
// tight and measures each at once, stopping at the first that reaches o.stop_below. The
// reference tasks are all taken before any ladder task, so a waiting ladder always waits for a
// reference that some thread is computing.
template <scalar T>
std::vector<wp_outcome> run_ladders(const std::vector<wp_grid>& grids, const eulervop::precision& p,
                                    const picard_settings& settings, const wp_run_options& o) {
  std::vector<wp_outcome> out(grids.size());
  std::vector<dense_reference<T>> refs(grids.size());
  std::vector<euler_problem<double>> problems;
  for (const wp_grid& g : grids) problems.push_back(to_problem<double>(g.scn));
  std::mutex mutex;
  std::condition_variable ready_changed;
  std::vector<char> ready(grids.size(), 0);
  std::exception_ptr reference_error;

  struct ladder {
    std::size_t grid;
    std::vector<std::size_t> cases;  // loose to tight
    double cost = 0;
  };
  std::vector<ladder> ladders;
  for (std::size_t gi = 0; gi < grids.size(); ++gi) {
    const wp_grid& g = grids[gi];
    out[gi].results.resize(g.cases.size());
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

  std::vector<std::function<void()>> tasks;
  for (std::size_t gi = 0; gi < grids.size(); ++gi)
    tasks.emplace_back([&, gi] {
      try {
        mpfr_scope_on_this_thread(p, [&] { refs[gi] = grid_reference<T>(grids[gi], settings, out[gi]); });
      } catch (...) {
        const std::lock_guard lock(mutex);
        if (!reference_error) reference_error = std::current_exception();
      }
      {
        const std::lock_guard lock(mutex);
        ready[gi] = 1;
      }
      ready_changed.notify_all();
    });
  for (const ladder& l : ladders)
    tasks.emplace_back([&, l] {
      {
        std::unique_lock lock(mutex);
        ready_changed.wait(lock, [&] { return ready[l.grid] != 0; });
        if (reference_error) std::rethrow_exception(reference_error);
      }
      const wp_grid& g = grids[l.grid];
      bool reached = false;
      for (std::size_t ci : l.cases) {
        wp_result& r = out[l.grid].results[ci];
        if (reached) {
          r.skipped = true;
          r.run.form = g.cases[ci].form;
          r.run.method = g.cases[ci].method;
          continue;
        }
        r = run_case(g, g.cases[ci], problems[l.grid], o.repeat);
        mpfr_scope_on_this_thread(p, [&] { measure<T>(g, g.cases[ci], refs[l.grid].trajectory, r); });
        reached = r.max_error && *r.max_error <= *o.stop_below;
      }
    });
  run_tasks(tasks, o.jobs, o.progress_label);
  if (reference_error) std::rethrow_exception(reference_error);
  return out;
}

}  // namespace

std::vector<wp_outcome> run_grids(const std::vector<wp_grid>& grids, const eulervop::precision& p,
                                  const picard_settings& settings, const wp_run_options& options) {
  return with_scalar(p, [&](auto zero) {
    using T = decltype(zero);
    return options.stop_below ? run_ladders<T>(grids, p, settings, options) : run_all<T>(grids, p, settings, options);
  });
}

// ---- the cheapest configurations ------------------------------------------------------------------

std::string level_text(double level) { return fmt::format("{:.0e}", level); }

std::vector<level_choice> cheapest_per_level(const wp_grid& g, const wp_outcome& o, const std::vector<double>& levels) {
  std::vector<level_choice> out;
  for (double level : levels) {
    level_choice lc;
    lc.level = level;
    lc.best.resize(g.forms.size());
    for (std::size_t f = 0; f < g.forms.size(); ++f) {
      for (std::size_t i = 0; i < g.cases.size(); ++i) {
        if (g.cases[i].form != g.forms[f]) continue;
        const wp_result& r = o.results[i];
        if (r.skipped || r.run.diverged() || !r.max_error || !(*r.max_error <= level)) continue;
        if (!lc.best[f] || r.seconds < o.results[*lc.best[f]].seconds) lc.best[f] = i;
      }
      if (lc.best[f] && (!lc.winner || o.results[*lc.best[f]].seconds < o.results[*lc.best[*lc.winner]].seconds))
        lc.winner = f;
    }
    out.push_back(std::move(lc));
  }
  return out;
}

}  // namespace eulervop::app

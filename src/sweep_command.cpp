#include "sweep_command.hpp"

#include "input_error.hpp"
#include "progress_line.hpp"
#include "reference_compute.hpp"
#include "scene_problem.hpp"

#include <eulervop/chebyshev_picard.hpp>
#include <eulervop/comparison_run.hpp>
#include <eulervop/error_measure.hpp>
#include <eulervop/model.hpp>
#include <eulervop/runge_kutta.hpp>
#include <eulervop/scalar.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <limits>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

namespace eulervop::app {

namespace fs = std::filesystem;

namespace {

constexpr std::int64_t default_samples = 200;
constexpr std::int64_t default_repeat = 3;
constexpr std::int64_t max_repeat = 1000;
constexpr std::int64_t max_jobs = 256;
// The default ladder: K/25, K/50, ..., K/6400 (nine steps, doubling).
constexpr std::int64_t ladder_first = 25, ladder_last = 6400;

// ---- flags -> a job ----------------------------------------------------------------------------

struct sweep_step {
  std::string text;          // as given: "K/25", "0.01"
  fixed_step_choice choice;  // h in tau, steps to the span end
  std::size_t sample_every = 1;
  std::vector<std::size_t> sample_steps;  // 0, m, 2m, ..., and the last step
};

struct sweep_case {
  formulation form;
  rk::method method;
  std::size_t step = 0;  // index into sweep_job::steps
};

struct sweep_job {
  scene scn;
  std::string overrides;
  std::vector<formulation> forms;
  std::vector<rk::method> methods;
  std::vector<sweep_step> steps;
  std::vector<sweep_case> cases;  // formulation-major, then method, then step: the output order
  std::size_t samples = 0;
  int repeat = 1;
  int jobs = 1;
  eulervop::precision precision;
  picard_settings settings;
  fs::path out_dir;
  bool plot = true;
};

std::vector<sweep_step> steps_of(const scene& s, const std::optional<std::string>& flag, std::size_t samples) {
  std::vector<std::string> texts;
  if (flag) {
    texts = flag_list("--steps", *flag);
  } else {
    for (std::int64_t n = ladder_first; n <= ladder_last; n *= 2) texts.push_back(fmt::format("K/{}", n));
  }
  std::vector<sweep_step> out;
  for (const std::string& text : texts) {
    if (std::any_of(out.begin(), out.end(), [&](const sweep_step& st) { return st.text == text; }))
      throw input_error(fmt::format("--steps {}: step {} is listed twice", *flag, text));
    sweep_step st;
    st.text = text;
    const std::string origin = flag ? "--steps " + text : fmt::format("the default ladder's step {} (give --steps)", text);
    st.choice = resolve_step(s, parse_step_text(text, "--steps"), origin);
    const std::size_t n = st.choice.n_steps;
    st.sample_every = std::max<std::size_t>(1, n / std::max<std::size_t>(samples, 1));
    for (std::size_t k = 0; k <= n; k += st.sample_every) st.sample_steps.push_back(k);
    if (st.sample_steps.back() != n) st.sample_steps.push_back(n);
    out.push_back(std::move(st));
  }
  return out;
}

sweep_job make_job(const sweep_options& o) {
  sweep_job job;
  job.scn = o.scene_path ? load_scene_file(*o.scene_path) : load_default_scene();
  scene& s = job.scn;

  // Error samples are step points of each run, about --samples of them; the scene's own sample
  // times and count are for `reference` and do not apply.
  s.times.clear();
  s.samples = default_samples;
  const applied_overrides applied = apply_scene_overrides(s, o.overrides);
  job.overrides = applied.text();
  job.precision = applied.precision;
  job.settings = applied.settings;
  job.samples = static_cast<std::size_t>(*s.samples);

  job.repeat = o.repeat ? static_cast<int>(flag_integer("--repeat", *o.repeat, 1, max_repeat)) : default_repeat;
  job.jobs = o.jobs ? static_cast<int>(flag_integer("--jobs", *o.jobs, 1, max_jobs)) : 1;

  // The whole grid by default: the scene's [run] methods and formulations choose the runs of
  // `report`, not the sweep's.
  if (o.formulations)
    job.forms = formulations_of(flag_list("--formulations", *o.formulations), "--formulations " + *o.formulations, "");
  else
    job.forms.assign(all_formulations.begin(), all_formulations.end());
  if (o.methods)
    job.methods = methods_of(flag_list("--methods", *o.methods), "--methods " + *o.methods, "");
  else
    job.methods.assign(rk::fixed_step_methods.begin(), rk::fixed_step_methods.end());
  job.steps = steps_of(s, o.steps, job.samples);
  for (formulation f : job.forms)
    for (rk::method m : job.methods)
      for (std::size_t i = 0; i < job.steps.size(); ++i) job.cases.push_back({f, m, i});

  probe_formulations(job.forms, to_problem<double>(s), job.steps.front().choice.h);

  if (o.out_dir && o.out_dir->empty()) throw input_error("--out-dir: empty path");
  job.out_dir = o.out_dir ? fs::path(*o.out_dir) : fs::path("eulervop-sweep");
  job.plot = !o.no_plot;
  return job;
}

// ---- running the cases ----------------------------------------------------------------------------

// A case's outcome: the first of its timed runs (they are identical but for the time) and the
// minimum time over all of them.
struct case_result {
  run_result run;
  double seconds = 0;
};

// The reference at every step's sample points.
template <scalar T>
struct sweep_reference {
  std::vector<std::vector<vec3<T>>> Omega;  // [step][sample]
  double seconds = 0;                        // integration and sampling
  std::size_t segments = 0;
  double tau_end = 0;
};

template <scalar T>
sweep_reference<T> compute_reference(const sweep_job& job) {
  const auto start = std::chrono::steady_clock::now();
  sweep_reference<T> out;
  const normalized_problem<T> problem = to_problem<T>(job.scn);
  T tau_end = tau_end_of<T>(job.scn);
  for (const sweep_step& st : job.steps) {  // within the 1e-9 h slack of n_steps
    const T last = tau_of_step<T>(st.choice.n_steps, st.choice.h);
    if (last > tau_end) tau_end = last;
  }
  const dense_reference<T> dense = integrate_dense<T>(problem, tau_end, job.settings, "");
  for (const sweep_step& st : job.steps) {
    std::vector<vec3<T>> samples;
    samples.reserve(st.sample_steps.size());
    for (std::size_t n : st.sample_steps) samples.push_back(sample_dense(dense.trajectory, tau_of_step<T>(n, st.choice.h)));
    out.Omega.push_back(std::move(samples));
  }
  out.segments = dense.stats.segments;
  out.tau_end = static_cast<double>(tau_end);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

case_result run_case(const sweep_job& job, const sweep_case& c, const normalized_problem<double>& problem) {
  const sweep_step& st = job.steps[c.step];
  const fixed_run_settings settings{st.choice.h, st.choice.n_steps, st.sample_every};
  case_result out;
  for (int k = 0; k < job.repeat; ++k) {
    run_result r = run_fixed(c.form, c.method, problem, settings);
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
double estimated_cost(const sweep_job& job, const sweep_case& c) {
  const auto stages = rk::dispatch_method(c.method, [](auto tag) { return decltype(tag)::stages; });
  const double per_eval = c.form == formulation::euler ? 1.0 : 10.0;  // the VOP right-hand sides cost more
  return static_cast<double>(job.steps[c.step].choice.n_steps) * static_cast<double>(stages) * per_eval;
}

// Runs `tasks` on `jobs` threads (a shared queue, taken in the given order), drawing progress
// in the calling thread. The first exception of any task is rethrown after all threads have
// stopped; no new task starts after one has failed.
void run_tasks(const std::vector<std::function<void()>>& tasks, int jobs) {
  const std::size_t n_threads = std::min<std::size_t>(static_cast<std::size_t>(jobs), tasks.size());
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
    progress_line progress("sweep", static_cast<double>(tasks.size()), "task");
    std::unique_lock lock(mutex);
    while (stopped < n_threads) {
      changed.wait_for(lock, std::chrono::milliseconds(100));
      progress.update(static_cast<double>(done));
    }
  }
  for (std::thread& t : threads) t.join();
  if (error) std::rethrow_exception(error);
}

// ---- errors -------------------------------------------------------------------------------------

struct case_errors {
  std::optional<double> max_error, final_error;  // none for a diverged run
};

// Eq. 20 at the run's sample steps (computed in the calling thread: MPFR temporaries take the
// thread's default precision).
template <scalar T>
case_errors errors_of(const sweep_step& st, const std::vector<vec3<T>>& ref, const run_result& r) {
  case_errors out;
  if (r.diverged) return out;
  std::size_t pos = 0;
  double worst = 0;
  std::optional<double> last;
  for (std::size_t i = 0; i < st.sample_steps.size(); ++i) {
    const std::size_t n = st.sample_steps[i];
    while (pos < r.sample_steps.size() && r.sample_steps[pos] < n) ++pos;
    if (pos == r.sample_steps.size() || r.sample_steps[pos] != n)
      throw std::logic_error(fmt::format("sweep: run without its sample at step {}", n));
    const double e = static_cast<double>(eq20_error(ref[i], r.Omega[pos]));
    if (!std::isfinite(e)) return {};  // never a NaN as an error value
    worst = std::max(worst, e);
    last = e;
  }
  out.max_error = worst;
  out.final_error = last;
  return out;
}

// ---- the cheapest configurations ------------------------------------------------------------------

struct level_choice {
  double level = 0;
  std::vector<std::optional<std::size_t>> best;  // per formulation (job.forms order): case index
  std::optional<std::size_t> winner;             // index into job.forms
};

std::vector<level_choice> cheapest_of(const sweep_job& job, const std::vector<case_result>& results,
                                      const std::vector<case_errors>& errors) {
  std::vector<level_choice> out;
  for (double level : sweep_error_levels) {
    level_choice lc;
    lc.level = level;
    lc.best.resize(job.forms.size());
    for (std::size_t f = 0; f < job.forms.size(); ++f) {
      for (std::size_t i = 0; i < job.cases.size(); ++i) {
        if (job.cases[i].form != job.forms[f]) continue;
        if (results[i].run.diverged || !errors[i].max_error || !(*errors[i].max_error <= level)) continue;
        if (!lc.best[f] || results[i].seconds < results[*lc.best[f]].seconds) lc.best[f] = i;
      }
      if (lc.best[f] && (!lc.winner || results[*lc.best[f]].seconds < results[*lc.best[*lc.winner]].seconds))
        lc.winner = f;
    }
    out.push_back(std::move(lc));
  }
  return out;
}

std::string level_text(double level) { return fmt::format("{:.0e}", level); }

// "vop, 2.60x faster than euler, 1.10x faster than vop-theta" (and which reach nothing).
std::string verdict(const sweep_job& job, const std::vector<case_result>& results, const level_choice& lc) {
  if (!lc.winner) return "no formulation reaches it";
  const double best = results[*lc.best[*lc.winner]].seconds;
  std::string s(formulation_name(job.forms[*lc.winner]));
  std::vector<std::string> missing;
  for (std::size_t f = 0; f < job.forms.size(); ++f) {
    if (f == *lc.winner) continue;
    const std::string name(formulation_name(job.forms[f]));
    if (lc.best[f])
      s += fmt::format(", {:.2f}x faster than {}", results[*lc.best[f]].seconds / best, name);
    else
      missing.push_back(name);
  }
  if (!missing.empty()) s += fmt::format("; not reached by {}", joined(missing));
  return s;
}

// ---- output ---------------------------------------------------------------------------------------

std::string optional_number(const std::optional<double>& x) { return x ? fmt::format("{}", *x) : std::string(); }

std::string sweep_csv(const sweep_job& job, const std::vector<case_result>& results,
                      const std::vector<case_errors>& errors) {
  fmt::memory_buffer out;
  auto put = [&]<class... Args>(fmt::format_string<Args...> f, Args&&... args) {
    fmt::format_to(std::back_inserter(out), f, std::forward<Args>(args)...);
  };
  put("formulation,method,step,h,steps,rhs_evals,seconds,max_error,final_error,diverged,diverged_at\n");
  for (std::size_t i = 0; i < job.cases.size(); ++i) {
    const sweep_case& c = job.cases[i];
    const run_result& r = results[i].run;
    put("{},{},{},{},{},{},{:.6g},{},{},{},{}\n", formulation_name(c.form), rk::method_name(c.method),
        job.steps[c.step].text, job.steps[c.step].choice.h, r.steps, r.rhs_evals, results[i].seconds,
        optional_number(errors[i].max_error), optional_number(errors[i].final_error), r.diverged ? "true" : "false",
        r.diverged ? optional_number(r.diverged_at) : std::string());
  }
  return fmt::to_string(out);
}

std::string cheapest_csv(const sweep_job& job, const std::vector<case_result>& results,
                         const std::vector<case_errors>& errors, const std::vector<level_choice>& levels) {
  fmt::memory_buffer out;
  auto put = [&]<class... Args>(fmt::format_string<Args...> f, Args&&... args) {
    fmt::format_to(std::back_inserter(out), f, std::forward<Args>(args)...);
  };
  // One row per level and formulation; empty cells where the formulation does not reach the
  // level. `factor` is its time over the level's cheapest time (1 for the cheapest).
  put("level,formulation,method,step,h,seconds,max_error,rhs_evals,factor\n");
  for (const level_choice& lc : levels) {
    for (std::size_t f = 0; f < job.forms.size(); ++f) {
      put("{},{}", level_text(lc.level), formulation_name(job.forms[f]));
      if (!lc.best[f]) {
        put(",,,,,,,\n");
        continue;
      }
      const std::size_t i = *lc.best[f];
      const sweep_case& c = job.cases[i];
      put(",{},{},{},{:.6g},{},{},{:.4g}\n", rk::method_name(c.method), job.steps[c.step].text,
          job.steps[c.step].choice.h, results[i].seconds, *errors[i].max_error, results[i].run.rhs_evals,
          results[i].seconds / results[*lc.best[*lc.winner]].seconds);
    }
  }
  return fmt::to_string(out);
}

std::string timing_note(const sweep_job& job) {
  if (job.jobs == 1)
    return fmt::format("each time is the minimum of {} run(s), one case at a time", job.repeat);
  return fmt::format("each time is the minimum of {} run(s); --jobs {}: cases ran in parallel, so the timings were "
                     "taken in parallel and are less pure than with --jobs 1",
                     job.repeat, job.jobs);
}

template <scalar T>
nlohmann::ordered_json summary_json(const sweep_job& job, const sweep_reference<T>& ref,
                                    const std::vector<case_result>& results, const std::vector<case_errors>& errors,
                                    const std::vector<level_choice>& levels, double wall_seconds) {
  nlohmann::ordered_json j;
  j["scene"] = job.scn.name;
  j["overrides"] = job.overrides;
  j["reference"] = {{"precision", job.precision.name()},
                    {"tau_end", ref.tau_end},
                    {"seconds", ref.seconds},
                    {"segments", ref.segments}};
  j["samples"] = job.samples;
  j["repeat"] = job.repeat;
  j["jobs"] = job.jobs;
  j["timing"] = timing_note(job);
  j["wall_seconds"] = wall_seconds;
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  for (const sweep_step& st : job.steps)
    steps.push_back({{"step", st.text},
                     {"h", st.choice.h},
                     {"steps", st.choice.n_steps},
                     {"sample_every", st.sample_every},
                     {"samples", st.sample_steps.size()},
                     {"rule", st.choice.rule}});
  j["steps"] = steps;
  j["runs"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < job.cases.size(); ++i) {
    const sweep_case& c = job.cases[i];
    const run_result& r = results[i].run;
    j["runs"].push_back({{"formulation", std::string(formulation_name(c.form))},
                         {"method", std::string(rk::method_name(c.method))},
                         {"step", job.steps[c.step].text},
                         {"h", job.steps[c.step].choice.h},
                         {"steps", r.steps},
                         {"rhs_evals", r.rhs_evals},
                         {"seconds", results[i].seconds},
                         {"max_error", number_or_null(errors[i].max_error)},
                         {"final_error", number_or_null(errors[i].final_error)},
                         {"diverged", r.diverged},
                         {"diverged_at", r.diverged ? number_or_null(r.diverged_at) : nlohmann::ordered_json(nullptr)},
                         {"why", r.diverged ? nlohmann::ordered_json(r.why) : nlohmann::ordered_json(nullptr)}});
  }
  j["cheapest"] = nlohmann::ordered_json::array();
  for (const level_choice& lc : levels) {
    nlohmann::ordered_json by = nlohmann::ordered_json::object();
    for (std::size_t f = 0; f < job.forms.size(); ++f) {
      const std::string name(formulation_name(job.forms[f]));
      if (!lc.best[f]) {
        by[name] = nullptr;
        continue;
      }
      const std::size_t i = *lc.best[f];
      by[name] = {{"method", std::string(rk::method_name(job.cases[i].method))},
                  {"step", job.steps[job.cases[i].step].text},
                  {"seconds", results[i].seconds},
                  {"max_error", *errors[i].max_error},
                  {"factor", results[i].seconds / results[*lc.best[*lc.winner]].seconds}};
    }
    j["cheapest"].push_back(
        {{"level", lc.level},
         {"cheapest", lc.winner ? nlohmann::ordered_json(std::string(formulation_name(job.forms[*lc.winner])))
                                : nlohmann::ordered_json(nullptr)},
         {"verdict", verdict(job, results, lc)},
         {"by_formulation", by}});
  }
  return j;
}

// Columns: text left-aligned, numbers right-aligned; a trailing note column.
std::string aligned(const std::vector<std::vector<std::string>>& rows, std::size_t text_columns) {
  std::vector<std::size_t> width;
  for (const auto& row : rows) {
    if (width.size() < row.size()) width.resize(row.size(), 0);
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  }
  std::string out;
  for (const auto& row : rows) {
    std::string line;
    for (std::size_t c = 0; c < row.size(); ++c) {
      const bool last = c + 1 == row.size() && c + 1 == width.size();
      const std::string cell = c < text_columns || last ? fmt::format("{:<{}}", row[c], last ? 0 : width[c])
                                                        : fmt::format("{:>{}}", row[c], width[c]);
      line += (c ? "  " : "") + cell;
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line + "\n";
  }
  return out;
}

template <scalar T>
std::string table_text(const sweep_job& job, const sweep_reference<T>& ref, const std::vector<case_result>& results,
                       const std::vector<case_errors>& errors, const std::vector<level_choice>& levels,
                       double wall_seconds) {
  std::string out;
  out += fmt::format("scene {}{}: {} formulation(s) x {} method(s) x {} step(s) = {} runs, to tau = {:.6g}\n",
                     job.scn.name, job.overrides.empty() ? "" : " (" + job.overrides + ")", job.forms.size(),
                     job.methods.size(), job.steps.size(), job.cases.size(), ref.tau_end);
  out += fmt::format("reference: {} ({:.1f} s, {} segments); errors (Eq. 20) at about {} samples per run\n",
                     job.precision.name(), ref.seconds, ref.segments, job.samples);
  out += fmt::format("timing: {}\n", timing_note(job));
  out += fmt::format("wall time of the sweep: {:.1f} s\n\n", wall_seconds);

  std::vector<std::vector<std::string>> rows = {
      {"formulation", "method", "step", "h", "steps", "rhs evals", "seconds", "max error", "final error", ""}};
  for (std::size_t i = 0; i < job.cases.size(); ++i) {
    const sweep_case& c = job.cases[i];
    const run_result& r = results[i].run;
    auto sci = [](const std::optional<double>& x) { return x ? fmt::format("{:.3e}", *x) : std::string("-"); };
    rows.push_back({std::string(formulation_name(c.form)), std::string(rk::method_name(c.method)),
                    job.steps[c.step].text, fmt::format("{:.6g}", job.steps[c.step].choice.h),
                    fmt::format("{}", r.steps), fmt::format("{}", r.rhs_evals), fmt::format("{:.3e}", results[i].seconds),
                    sci(errors[i].max_error), sci(errors[i].final_error),
                    r.diverged ? fmt::format("DIVERGED at tau={} ({})",
                                             r.diverged_at ? fmt::format("{:.6g}", *r.diverged_at) : "?", r.why)
                               : ""});
  }
  out += aligned(rows, 3);

  out += "\ncheapest configuration per formulation (max error over the span <= level; diverged runs excluded):\n";
  std::vector<std::vector<std::string>> table;
  std::vector<std::string> header = {"level"};
  for (formulation f : job.forms) header.emplace_back(formulation_name(f));
  header.emplace_back("cheaper");
  table.push_back(header);
  for (const level_choice& lc : levels) {
    std::vector<std::string> row = {level_text(lc.level)};
    for (std::size_t f = 0; f < job.forms.size(); ++f) {
      if (!lc.best[f]) {
        row.emplace_back("not reached");
        continue;
      }
      const std::size_t i = *lc.best[f];
      row.push_back(fmt::format("{} {} {:.3e} s", rk::method_name(job.cases[i].method), job.steps[job.cases[i].step].text,
                                results[i].seconds));
    }
    row.push_back(verdict(job, results, lc));
    table.push_back(std::move(row));
  }
  out += aligned(table, table.front().size());
  return out;
}

template <scalar T>
void execute(const sweep_job& job, std::ostream& standard_output, unsigned mpfr_bits) {
  const auto start = std::chrono::steady_clock::now();
  output_dir dir(job.out_dir, "sweep.csv");

  // The tasks: the reference first (it is the longest), then the runs longest first. Results
  // land in their case's slot, so the output order never depends on the scheduling.
  const normalized_problem<double> problem = to_problem<double>(job.scn);
  std::vector<case_result> results(job.cases.size());
  sweep_reference<T> ref;
  std::vector<std::function<void()>> tasks;
  tasks.emplace_back([&] {
    if constexpr (std::is_same_v<T, mpfr_real>) {
      const mpfr_precision_scope scope(mpfr_bits);  // this thread's default precision
      ref = compute_reference<T>(job);
    } else {
      (void)mpfr_bits;
      ref = compute_reference<T>(job);
    }
  });
  std::vector<std::size_t> order(job.cases.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return estimated_cost(job, job.cases[a]) > estimated_cost(job, job.cases[b]);
  });
  for (std::size_t i : order) tasks.emplace_back([&, i] { results[i] = run_case(job, job.cases[i], problem); });
  run_tasks(tasks, job.jobs);

  std::vector<case_errors> errors;
  for (std::size_t i = 0; i < job.cases.size(); ++i)
    errors.push_back(errors_of<T>(job.steps[job.cases[i].step], ref.Omega[job.cases[i].step], results[i].run));
  const std::vector<level_choice> levels = cheapest_of(job, results, errors);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  write_atomically(dir.path() / "sweep.csv", sweep_csv(job, results, errors));
  write_atomically(dir.path() / "cheapest.csv", cheapest_csv(job, results, errors, levels));
  write_atomically(dir.path() / "summary.json", summary_json<T>(job, ref, results, errors, levels, wall).dump(2) + "\n");
  dir.keep();

  standard_output << table_text<T>(job, ref, results, errors, levels, wall) << std::flush;
  if (job.plot) draw_figure(dir.path(), "plot_work_precision.py");
}

}  // namespace

CLI::App* add_sweep_command(CLI::App& app, sweep_options& o) {
  CLI::App* sub = app.add_subcommand(
      "sweep", "Work against precision: every formulation x method x step, timed and measured against one reference");
  auto bind = [&](const std::string& name, std::optional<std::string>& target, const std::string& help) {
    return sub->add_option_function<std::string>(name, [&target](const std::string& v) { target = v; }, help);
  };
  bind("scene", o.scene_path, "Scene file (TOML); default: the embedded paper scene")->type_name("SCENE");
  bind("--steps", o.steps, "Comma-separated fixed steps: K/N (K of the initial modulus) or h (default: K/25 to "
                           "K/6400, doubling)")
      ->type_name("LIST");
  bind("--methods", o.methods, "Comma-separated: rk4,rkf45,dp45,rk8 (default: all)")->type_name("LIST");
  bind("--formulations", o.formulations, "Comma-separated: " + joined(available_formulations()) + " (default: all)")
      ->type_name("LIST");
  bind("--repeat", o.repeat, "Timed runs per case; the minimum time is kept (default: 3)")->type_name("N");
  bind("--jobs", o.jobs, "Cases run in parallel (default: 1; above 1 the timings are less pure)")->type_name("N");
  scene_override_set which;
  which.times = false;
  add_scene_override_options(*sub, o.overrides, which,
                             "About this many error samples per run, at its step points (default: 200)");
  bind("--out-dir", o.out_dir, "Output directory (default: ./eulervop-sweep/, created if missing)")->type_name("DIR");
  sub->add_flag("--no-plot", o.no_plot, "Do not draw work_precision.png/work_precision.svg");
  return sub;
}

void run_sweep(const sweep_options& options, std::ostream& standard_output) {
  const sweep_job job = make_job(options);
  const eulervop::precision& p = job.precision;
  switch (p.type) {
    case eulervop::precision::kind::binary64: return execute<double>(job, standard_output, 0);
    case eulervop::precision::kind::binary128: return execute<quad>(job, standard_output, 0);
    case eulervop::precision::kind::mpfr: {
      const mpfr_precision_scope scope(p.bits);
      return execute<mpfr_real>(job, standard_output, p.bits);
    }
  }
  throw std::logic_error("unknown precision kind");
}

}  // namespace eulervop::app

#include "commands/batch_command.hpp"

#include "io/atomic_file.hpp"
#include "cli/exit_codes.hpp"
#include "io/output_dir.hpp"
#include "io/progress_line.hpp"
#include "commands/reference_command.hpp"
#include "commands/report_command.hpp"
#include "compute/scene_library.hpp"
#include "io/shell_word.hpp"

#include <eulervop/reference/integrate.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

namespace eulervop::app {

namespace {

namespace fs = std::filesystem;

constexpr const char* stamp_name = ".batch-hash";

struct shard_spec {
  std::int64_t index = 1, count = 1;
};

shard_spec parse_shard(const std::string& text) {
  const auto bad = [&] {
    return input_error(fmt::format("--shard: expected I/N with 1 <= I <= N (e.g. 3/16), got `{}`", text));
  };
  const auto slash = text.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == text.size()) throw bad();
  const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
  const auto digits = [](const std::string& s) {
    return s.size() <= 9 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!digits(a) || !digits(b)) throw bad();
  shard_spec s{std::stoll(a), std::stoll(b)};
  if (s.count < 1 || s.index < 1 || s.index > s.count) throw bad();
  return s;
}

std::uint64_t fnv1a(std::uint64_t h, std::string_view data) {
  for (unsigned char c : data) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::optional<std::string> read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) return std::nullopt;
  return s.str();
}

// One scene of the batch.
struct scene_task {
  std::string path;  // as given
  std::string name;  // the file's stem: the output directory's name
};

struct scene_outcome {
  std::string status = "failed";
  int exit_code = exit_internal_error;
  std::string message;
  std::vector<std::string> outputs;  // relative to the output directory
  std::string hash;
  double seconds = 0;
};

struct batch_settings {
  fs::path out_dir;
  bool report = false;
  bool verify = false;
  bool certify = false;
  scene_override_flags overrides;
  std::string flags_text;  // the flags that shape the outputs, for the hash and the commands
};

std::string flags_text_of(const batch_options& o) {
  std::string t;
  const auto add = [&](const char* flag, const std::optional<std::string>& v) {
    if (v) t += fmt::format(" {} {}", flag, shell_word(*v));
  };
  add("--samples", o.overrides.samples);
  add("--precision", o.overrides.precision);
  add("--degree", o.overrides.degree);
  add("--tolerance", o.overrides.tolerance);
  if (o.verify) t += " --verify";
  if (o.certify) t += " --certify";
  return t;
}

std::vector<std::string> expected_outputs(const batch_settings& s, const scene_task& t) {
  std::vector<std::string> out = {t.name + "/reference.csv"};
  if (s.report) {
    out.push_back(t.name + "/report/errors.csv");
    out.push_back(t.name + "/report/summary.json");
  }
  return out;
}

scene_outcome run_one(const batch_settings& s, const scene_task& t) {
  const auto start = std::chrono::steady_clock::now();
  scene_outcome r;
  const auto finish = [&] {
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
  };
  const fs::path dir = s.out_dir / t.name;
  const fs::path stamp = dir / stamp_name;
  try {
    const std::optional<std::string> text = read_all(t.path);
    if (!text) throw input_error(fmt::format("scene {}: cannot read the file", t.path));
    std::uint64_t h = 0xcbf29ce484222325ULL;
    for (const std::string_view part : {std::string_view(EULERVOP_VERSION), std::string_view(t.path),
                                        std::string_view(*text), std::string_view(s.flags_text),
                                        std::string_view(s.report ? "report" : "")}) {
      h = fnv1a(h, part);
      h = fnv1a(h, std::string_view("\0", 1));
    }
    r.hash = fmt::format("{:016x}", h);
    const std::vector<std::string> outputs = expected_outputs(s, t);

    // Up to date: the stamp (written last) matches and every output is there.
    if (const auto old = read_all(stamp); old && *old == r.hash + "\n" &&
        std::all_of(outputs.begin(), outputs.end(), [&](const std::string& o) { return fs::is_regular_file(s.out_dir / o); })) {
      r.status = "skipped-up-to-date";
      r.exit_code = exit_success;
      r.outputs = outputs;
      return finish();
    }

    std::error_code ec;
    fs::remove(stamp, ec);
    fs::create_directories(dir, ec);
    if (ec) throw input_error(fmt::format("cannot create {}: {}", dir.string(), ec.message()));

    reference_options ref;
    ref.scene_path = t.path;
    ref.overrides = s.overrides;
    ref.out = (dir / "reference.csv").string();
    ref.verify = s.verify;
    ref.certify = s.certify;
    ref.omit_timing = true;
    ref.command = "eulervop reference " + shell_word(t.path) + s.flags_text;
    std::ostringstream sink;
    run_reference(ref, sink);

    if (s.report) {
      report_options rep;
      rep.scene_path = t.path;
      rep.overrides.precision = s.overrides.precision;
      rep.overrides.degree = s.overrides.degree;
      rep.overrides.tolerance = s.overrides.tolerance;
      rep.out_dir = (dir / "report").string();
      rep.format = "json";
      rep.no_plot = true;
      rep.verify = s.verify;
      run_report(rep, sink);
    }

    write_atomically(stamp, r.hash + "\n");
    r.status = "ok";
    r.exit_code = exit_success;
    r.outputs = outputs;
  } catch (const input_error& e) {
    r.exit_code = exit_bad_input;
    r.message = e.what();
  } catch (const numerical_failure& e) {
    r.exit_code = exit_numerical_failure;
    r.message = e.what();
  } catch (const std::exception& e) {
    r.exit_code = exit_internal_error;
    r.message = fmt::format("internal error: {}", e.what());
  }
  return finish();
}

// The scenes of the batch (sorted, duplicates removed, this shard's only); input_error for two
// scenes that would write the same directory.
std::vector<scene_task> tasks_of(const batch_options& o, const std::optional<shard_spec>& shard) {
  std::vector<std::string> paths = o.scenes;
  std::sort(paths.begin(), paths.end());
  paths.erase(std::unique(paths.begin(), paths.end()), paths.end());
  std::map<std::string, std::string> by_name;
  std::vector<scene_task> tasks;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const std::string name = fs::path(paths[i]).stem().string();
    if (name.empty() || name == "." || name == "..") throw input_error(fmt::format("batch: `{}` is not a scene file", paths[i]));
    if (auto [it, fresh] = by_name.emplace(name, paths[i]); !fresh)
      throw input_error(fmt::format("batch: scenes `{}` and `{}` would both write {}/ (rename one)", it->second, paths[i], name));
    if (shard && static_cast<std::int64_t>(i % static_cast<std::size_t>(shard->count)) != shard->index - 1) continue;
    tasks.push_back({paths[i], name});
  }
  return tasks;
}

// Runs every task on up to `jobs` threads, one status line per scene on stderr.
std::vector<scene_outcome> run_tasks(const batch_settings& s, const std::vector<scene_task>& tasks, std::int64_t jobs) {
  progress_line::disable_all();  // several runs share the terminal
  std::vector<scene_outcome> results(tasks.size());
  std::atomic<std::size_t> next{0};
  std::mutex print_mutex;
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < tasks.size();) {
      results[i] = run_one(s, tasks[i]);
      const std::lock_guard lock(print_mutex);
      const scene_outcome& r = results[i];
      fmt::print(stderr, "batch: {} {} ({:.2f} s){}\n", tasks[i].name, r.status, r.seconds,
                 r.message.empty() ? "" : ": " + input_error::one_line(r.message));
    }
  };
  const std::size_t n_threads = std::min<std::size_t>(static_cast<std::size_t>(jobs), std::max<std::size_t>(tasks.size(), 1));
  if (n_threads <= 1) {
    worker();
  } else {
    std::vector<std::jthread> threads;
    for (std::size_t t = 0; t < n_threads; ++t) threads.emplace_back(worker);
  }

  return results;
}

// Writes the manifest (no timings: they are on stderr, so reruns give identical files) and the
// summary line; returns the batch's exit code, the gravest of the scenes'.
int write_manifest(const batch_settings& s, const std::optional<shard_spec>& shard, const std::vector<scene_task>& tasks,
                   const std::vector<scene_outcome>& results, std::ostream& standard_output) {
  const std::string suffix = shard ? fmt::format("-{}-of-{}", shard->index, shard->count) : "";
  nlohmann::ordered_json manifest;
  manifest["eulervop"] = EULERVOP_VERSION;
  manifest["shard"] = shard ? nlohmann::ordered_json(fmt::format("{}/{}", shard->index, shard->count)) : nullptr;
  manifest["flags"] = s.flags_text.empty() ? "" : s.flags_text.substr(1);
  manifest["report"] = s.report;
  manifest["scenes"] = nlohmann::ordered_json::array();
  bool any_bad_input = false, any_numerical = false, any_internal = false;
  std::size_t n_ok = 0, n_skipped = 0, n_failed = 0;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const scene_outcome& r = results[i];
    manifest["scenes"].push_back({{"path", tasks[i].path},
                                  {"name", tasks[i].name},
                                  {"status", r.status},
                                  {"exit_code", r.exit_code},
                                  {"message", r.message},
                                  {"outputs", r.outputs},
                                  {"hash", r.hash}});
    if (r.status == "ok") ++n_ok;
    else if (r.status == "skipped-up-to-date") ++n_skipped;
    else ++n_failed;
    any_bad_input |= r.exit_code == exit_bad_input;
    any_numerical |= r.exit_code == exit_numerical_failure;
    any_internal |= r.exit_code == exit_internal_error;
  }
  const fs::path manifest_path = s.out_dir / ("manifest" + suffix + ".json");
  write_atomically(manifest_path, manifest.dump(2) + "\n");
  standard_output << fmt::format("batch: {} scene{}: {} ok, {} skipped (up to date), {} failed; manifest {}\n",
                                 tasks.size(), tasks.size() == 1 ? "" : "s", n_ok, n_skipped, n_failed,
                                 manifest_path.string())
                  << std::flush;
  if (any_bad_input) return exit_bad_input;
  if (any_numerical) return exit_numerical_failure;
  if (any_internal) return exit_internal_error;
  return exit_success;
}

}  // namespace

CLI::App* add_batch_command(CLI::App& app, batch_options& o) {
  CLI::App* sub = app.add_subcommand("batch", "Run `reference` (and optionally `report`) for many scenes");
  sub->add_option("scenes", o.scenes, "Scene files (TOML)")->type_name("SCENE...");
  sub->add_option_function<std::string>(
         "--out-dir", [&o](const std::string& v) { o.out_dir = v; }, "Output directory (created if missing)")
      ->type_name("DIR")
      ->required();
  sub->add_option_function<std::string>(
         "--jobs", [&o](const std::string& v) { o.jobs = v; }, "Scenes run at once on this many threads (default 1)")
      ->type_name("N");
  sub->add_option_function<std::string>(
         "--shard", [&o](const std::string& v) { o.shard = v; },
         "Run only share I of N: the scenes, sorted by path, whose index % N == I-1")
      ->type_name("I/N");
  add_scene_override_options(*sub, o.overrides, scene_override_set{false, true, false, true},
                             "Number of reference samples per scene (default: each scene's own)");
  sub->add_flag("--report", o.report, "Also run `report` (no figure) into DIR/SCENE/report/");
  sub->add_flag("--verify", o.verify, "Verify each reference one precision up (# estimated_max_error)");
  sub->add_flag("--certify", o.certify, "Certify each reference: a proven radius per row (docs/certified.md)");
  return sub;
}

int run_batch(const batch_options& o, std::ostream& standard_output) {
  // ---- flags (all checked before anything runs) ----
  if (o.scenes.empty()) throw input_error("batch: no scenes given");
  if (!o.out_dir || o.out_dir->empty()) throw input_error("--out-dir: empty path");
  const std::int64_t jobs = o.jobs ? flag_integer("--jobs", *o.jobs, 1, 1024) : 1;
  const std::optional<shard_spec> shard = o.shard ? std::optional(parse_shard(*o.shard)) : std::nullopt;
  {
    // The flags are checked by the same rules as `reference`'s, once, on the embedded scene.
    scene probe = load_default_scene();
    apply_scene_overrides(probe, o.overrides);
  }

  const std::vector<scene_task> tasks = tasks_of(o, shard);

  batch_settings s;
  s.out_dir = *o.out_dir;
  s.report = o.report;
  s.verify = o.verify;
  s.certify = o.certify;
  s.overrides = o.overrides;
  s.flags_text = flags_text_of(o);
  {
    std::error_code ec;
    fs::create_directories(s.out_dir, ec);
    if (ec || !fs::is_directory(s.out_dir)) throw input_error(fmt::format("--out-dir: cannot create `{}`", s.out_dir.string()));
  }

  const std::vector<scene_outcome> results = run_tasks(s, tasks, jobs);
  return write_manifest(s, shard, tasks, results, standard_output);
}

}  // namespace eulervop::app

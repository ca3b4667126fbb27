#include "commands/batch/batch_command.hpp"

#include "cli/command_flags.hpp"
#include "cli/flags.hpp"
#include "cli/scene_overrides.hpp"
#include "commands/batch/batch_manifest.hpp"
#include "commands/batch/batch_scene.hpp"
#include "compute/scene_library.hpp"
#include "io/progress_line.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

namespace eulervop::app {

namespace {

namespace fs = std::filesystem;

// The flags passed on to every scene's `reference`, as a command line states them: in the input
// hash, the manifest and each reference file's "# command:" line.
std::string passed_flags_text(const reference_options& r) {
  return command_line_text(override_flags::samples, r.overrides.samples) +
         command_line_text(override_flags::precision, r.overrides.precision) +
         command_line_text(override_flags::degree, r.overrides.degree) +
         command_line_text(override_flags::tolerance, r.overrides.tolerance) +
         command_line_text(reference_flags::verify, r.verify) + command_line_text(reference_flags::certify, r.certify);
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
    if (name.empty() || name == "." || name == "..")
      throw input_error(fmt::format("batch: `{}` is not a scene file", paths[i]));
    if (auto [it, fresh] = by_name.emplace(name, paths[i]); !fresh)
      throw input_error(
          fmt::format("batch: scenes `{}` and `{}` would both write {}/ (rename one)", it->second, paths[i], name));
    if (shard && static_cast<std::int64_t>(i % static_cast<std::size_t>(shard->count)) != shard->index - 1) continue;
    tasks.push_back({paths[i], name});
  }
  return tasks;
}

// Runs every task on up to `jobs` threads, one status line per scene on stderr.
std::vector<scene_outcome> run_scenes(const batch_settings& s, const std::vector<scene_task>& tasks,
                                      std::int64_t jobs) {
  progress_line::disable_all();  // several runs share the terminal
  std::vector<scene_outcome> results(tasks.size());
  std::atomic<std::size_t> next{0};
  std::mutex print_mutex;
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < tasks.size();) {
      results[i] = run_scene(s, tasks[i]);
      const std::lock_guard lock(print_mutex);
      const scene_outcome& r = results[i];
      fmt::print(stderr, "batch: {} {} ({:.2f} s){}\n", tasks[i].name, r.status, r.seconds,
                 r.message.empty() ? "" : ": " + input_error::one_line(r.message));
    }
  };
  const std::size_t n_threads =
      std::min<std::size_t>(static_cast<std::size_t>(jobs), std::max<std::size_t>(tasks.size(), 1));
  if (n_threads <= 1) {
    worker();
  } else {
    std::vector<std::jthread> threads;
    for (std::size_t t = 0; t < n_threads; ++t) threads.emplace_back(worker);
  }
  return results;
}

}  // namespace

void add_batch_flags(CLI::App& sub, batch_options& o) {
  add_positional_list(sub, {"scenes", "SCENE...", "Scene files (TOML)"}, o.scenes);
  add_required_text_flag(sub, {"--out-dir", "DIR", "Output directory (created if missing)"}, o.out_dir);
  add_text_flag(sub, {"--jobs", "N", "Scenes run at once on this many threads (default 1)"}, o.jobs);
  add_text_flag(sub, {"--shard", "I/N", "Run only share I of N: the scenes, sorted by path, whose index % N == I-1"},
                o.shard);
  add_scene_override_flags(sub, o.reference.overrides, scene_override_set{false, true, false, true},
                           "Number of reference samples per scene (default: each scene's own)");
  add_switch(sub, {"--report", "", "Also run `report` (no figure) into DIR/SCENE/report/"}, o.report);
  add_switch(sub, reference_flags::verify.described("Verify each reference one precision up (# estimated_max_error)"),
             o.reference.verify);
  add_switch(sub,
             reference_flags::certify.described("Certify each reference: a proven radius per row (docs/certified.md)"),
             o.reference.certify);
}

int run_batch(const batch_options& o, std::ostream& standard_output) {
  // ---- flags (all checked before anything runs) ----
  if (o.scenes.empty()) throw input_error("batch: no scenes given");
  if (!o.out_dir || o.out_dir->empty()) throw input_error("--out-dir: empty path");
  const std::int64_t jobs = o.jobs ? flag_integer("--jobs", *o.jobs, 1, 1024) : 1;
  const std::optional<shard_spec> shard = o.shard ? std::optional(flag_shard(*o.shard)) : std::nullopt;
  {
    // The flags are checked by the same rules as `reference`'s, once, on the embedded scene.
    scene probe = load_default_scene();
    apply_scene_overrides(probe, o.reference.overrides);
  }
  const std::vector<scene_task> tasks = tasks_of(o, shard);

  batch_settings s{*o.out_dir, o.report, o.reference, passed_flags_text(o.reference)};
  s.reference.certify_one_thread = jobs > 1;  // the scenes' threads already share the cores
  std::error_code ec;
  fs::create_directories(s.out_dir, ec);
  if (ec || !fs::is_directory(s.out_dir))
    throw input_error(fmt::format("--out-dir: cannot create `{}`", s.out_dir.string()));

  return write_manifest(s, shard, tasks, run_scenes(s, tasks, jobs), standard_output);
}

}  // namespace eulervop::app
